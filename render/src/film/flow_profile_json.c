/* The flow profiles of a render (vr_render_options.flow_profile) as the
 * "flow_profile" member of the statistics: what bench/bench_ddm_sim.c
 * builds its model of the decomposition from. */
#include <inttypes.h>
#include <stdbool.h>
#include <stdatomic.h>
#include <stdio.h>

#include "vr/film.h"
#include "vr/flow.h"
#include "vr/json.h"

static uint64_t get(_Atomic uint64_t *v) { return atomic_load_explicit(v, memory_order_relaxed); }

void vr_flow_profile_write_json(FILE *f, const vr_render_result *r) {
  if (!r->nprofiles || !r->profile_load_seconds || !r->profile_cell_bytes) return;
  int S = r->profiles[0].p->ncells;
  /* Cells: [bytes when loaded, seconds of the last load]. */
  fputs("  \"flow_profile\": {\"cells\": [", f);
  for (int c = 0; c < S; c++) {
    fprintf(f, "%s[%.0f, ", c ? ", " : "", r->profile_cell_bytes[c]);
    vr_json_number(f, r->profile_load_seconds[c]);
    fputc(']', f);
  }
  fputs("],\n    \"passes\": [", f);
  for (int i = 0; i < r->nprofiles; i++) {
    vr_flow_profile *p = r->profiles[i].p;
    fprintf(f, "%s\n      {\"name\": ", i ? "," : "");
    vr_json_string(f, r->profiles[i].name);
    fprintf(f, ", \"units\": %" PRIu64 ", \"generate_seconds\": ", get(&p->units));
    vr_json_number(f, 1e-9 * (double)get(&p->gen_ns));
    /* Per cell: [closest rays, their seconds, shadow rays, their seconds]. */
    fputs(", \"rays\": [", f);
    for (int c = 0; c < S; c++) {
      fprintf(f, "%s[%" PRIu64 ", ", c ? ", " : "", get(&p->rays[0][c]));
      vr_json_number(f, 1e-9 * (double)get(&p->ns[0][c]));
      fprintf(f, ", %" PRIu64 ", ", get(&p->rays[1][c]));
      vr_json_number(f, 1e-9 * (double)get(&p->ns[1][c]));
      fputc(']', f);
    }
    /* Moves: [from, to, rays], from -1 for the units' own rays; the
     * non-zero ones only. */
    fputs("], \"moves\": [", f);
    bool first = true;
    for (int a = 0; a <= S; a++)
      for (int b = 0; b < S; b++) {
        uint64_t n = get(&p->moves[(size_t)a * (size_t)S + (size_t)b]);
        if (!n) continue;
        fprintf(f, "%s[%d, %d, %" PRIu64 "]", first ? "" : ", ", a == S ? -1 : a, b, n);
        first = false;
      }
    fputs("]}", f);
  }
  fputs("\n    ]},\n", f);
}
