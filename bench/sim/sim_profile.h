/* A recorded flow profile (vr-render --stats FILE --flow-profile, the
 * statistics' "flow_profile"), read for the model of the decomposition:
 * per cell its bytes, load time, rays traced and cost per ray; per pass
 * its units and where rays go from each cell. */
#ifndef BENCH_SIM_PROFILE_H
#define BENCH_SIM_PROFILE_H

#include <stdbool.h>

#define SIM_MAX_PASSES 16

typedef struct sim_pass {
  char name[32];
  long units;
  double gen_s;   /* seconds the units took to generate their rays */
  double *rays;   /* per cell: rays traced there (closest and shadow) */
  double *cost;   /* per cell: seconds per ray (0 where none was traced) */
  /* (S + 1) x S: rays cell a sent into cell b per ray traced in a (row S:
   * rays a unit sends into b, per unit). */
  double *out;
} sim_pass;

typedef struct sim_profile {
  int S;
  double *bytes;   /* per cell: bytes when loaded (arrays and BVH) */
  double *load_s;  /* per cell: seconds of its load */
  int npasses;
  sim_pass pass[SIM_MAX_PASSES];
} sim_profile;

/* Reads the flow profile from a statistics JSON text; false (with why in
 * msg) if it has none or it is malformed. */
bool sim_profile_read(const char *json, sim_profile *p, char *msg, int n);
void sim_profile_free(sim_profile *p);
/* Rays and tracing seconds of a pass in all (for checks and reports). */
double sim_pass_rays(const sim_profile *p, int pass);
double sim_pass_seconds(const sim_profile *p, int pass);

#endif
