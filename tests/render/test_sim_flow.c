/* The model of the decomposition that bench/bench_ddm_sim.c predicts the
 * paper's Table 1 with (bench/sim/): its profile reader and its event
 * engine, on a two-cell profile small enough to work out by hand.
 *
 * The profile: cells of 1 MB loading in 2 s and 1 s; 100 units taking
 * 1 s to generate, each sending 10 rays into cell 0 (3 ms a ray), each of
 * which sends one ray into cell 1 (1 ms a ray).  Work: 1 + 1000 x 0.003 +
 * 1000 x 0.001 = 5 s of generating and tracing, 3 s of loading.
 *   - one rank, one thread: prepare + loads + work, 8 s after preparing
 *     (nothing runs in parallel: the sum is exact);
 *   - one rank, two threads on one core: processor sharing conserves
 *     work, so the same 8 s; on two cores with no contention the loads
 *     take half (T^1 on 2 threads) and the work between half and all of
 *     its 5 s;
 *   - image space on 2 ranks (a node each): each loads the scene (3 s),
 *     then its 50 units, each 5 s / 100: 3 + 2.5 s; refused under a
 *     budget smaller than the scene;
 *   - the reader refuses what is not a profile: no flow_profile, moves
 *     naming a cell past the last, a pass without its rays. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "sim/sim_flow.h"
#include "sim/sim_profile.h"

static const char *profile_json =
    "{\"version\": \"0.1.0\",\n"
    "  \"flow_profile\": {\"cells\": [[1000000, 2], [1000000, 1]],\n"
    "    \"passes\": [\n"
    "      {\"name\": \"camera\", \"units\": 100, \"generate_seconds\": 1, "
    "\"rays\": [[1000, 3, 0, 0], [600, 0.6, 400, 0.4]], "
    "\"moves\": [[-1, 0, 1000], [0, 1, 1000]]}\n"
    "    ]},\n"
    "  \"seconds_total\": 1\n}\n";

static sim_profile read_profile(void) {
  sim_profile p;
  char msg[256] = "";
  bool ok = sim_profile_read(profile_json, &p, msg, sizeof msg);
  if (!ok) fail_msg("%s", msg);
  return p;
}

static void test_reader(void **state) {
  (void)state;
  sim_profile p = read_profile();
  assert_int_equal(p.S, 2);
  assert_int_equal(p.npasses, 1);
  assert_string_equal(p.pass[0].name, "camera");
  assert_int_equal(p.pass[0].units, 100);
  /* Closest and shadow rays together, their cost per ray. */
  assert_true(fabs(p.pass[0].rays[1] - 1000) < 1e-12);
  assert_true(fabs(p.pass[0].cost[0] - 0.003) < 1e-15);
  assert_true(fabs(p.pass[0].cost[1] - 0.001) < 1e-15);
  /* Moves per unit (row S) and per ray traced. */
  assert_true(fabs(p.pass[0].out[2 * 2 + 0] - 10) < 1e-12);
  assert_true(fabs(p.pass[0].out[0 * 2 + 1] - 1) < 1e-12);
  assert_true(fabs(sim_pass_seconds(&p, 0) - 5) < 1e-12);
  sim_profile_free(&p);
}

/* json is refused with a message containing want. */
static void refused(const char *json, const char *want) {
  sim_profile p;
  char msg[256] = "";
  assert_false(sim_profile_read(json, &p, msg, sizeof msg));
  if (!strstr(msg, want)) fail_msg("'%s' lacks '%s'", msg, want);
  sim_profile_free(&p);
}

static void test_refusals(void **state) {
  (void)state;
  refused("{\"seconds_total\": 1}", "no flow_profile");
  refused("\"flow_profile\": {\"cells\": [[1, 1]], \"passes\": [{\"name\": \"camera\", \"units\": 1, "
          "\"generate_seconds\": 0, \"rays\": [[1, 1, 0, 0]], \"moves\": [[0, 3, 1]]}]}",
          "names no cell");
  refused("\"flow_profile\": {\"cells\": [[1, 1]], \"passes\": [{\"name\": \"camera\", \"units\": 1, "
          "\"generate_seconds\": 0, \"moves\": []}]}",
          "incomplete");
}

static sim_config config(int cores, int threads) {
  sim_config c;
  sim_config_default(&c);
  c.nodes = 1, c.cores = cores, c.ranks = 1, c.threads = threads;
  c.load_scaling = 1;
  c.prepare_s = 0.5;
  return c;
}

/* One rank on one node: 1 thread on 1 core, 2 threads sharing 1 core
 * (both the exact sum), 2 threads on 2 cores (loads halved, the work
 * between half and all of it). */
static void test_one_rank(void **state) {
  (void)state;
  sim_profile p = read_profile();
  const int cores[] = {1, 1, 2}, threads[] = {1, 2, 2};
  for (int k = 0; k < 3; k++) {
    sim_config c = config(cores[k], threads[k]);
    sim_result r;
    assert_true(sim_run(&p, &c, &r));
    assert_true(fabs(r.loads - 2) < 1e-12);
    if (cores[k] == 1) {
      assert_true(fabs(r.seconds - (0.5 + 3 + 5)) < 1e-9);
    } else {
      assert_true(r.seconds >= 0.5 + 1.5 + 2.5 - 1e-9);
      assert_true(r.seconds < 0.5 + 1.5 + 5);
    }
  }
  sim_profile_free(&p);
}

static void test_image_space(void **state) {
  (void)state;
  sim_profile p = read_profile();
  sim_config c = config(1, 1);
  c.nodes = 2, c.ranks = 2, c.image_space = true;
  sim_result r;
  assert_true(sim_run(&p, &c, &r));
  assert_false(r.refused);
  assert_true(fabs(r.seconds - (0.5 + 3 + 2.5)) < 1e-9);
  c.budget = 1.5e6;
  assert_true(sim_run(&p, &c, &r));
  assert_true(r.refused);
  sim_profile_free(&p);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_reader),
      cmocka_unit_test(test_refusals),
      cmocka_unit_test(test_one_rank),
      cmocka_unit_test(test_image_space),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
