/* A surface-roughness layer above its film (the film named after the
 * layer that mixes it): the model must equal the same stack with the
 * roughness written as a constant index, the Bruggeman mixture solved by
 * hand.  Bruggeman (Ann. Phys. 24, 636, 1935), two components:
 *   f (ea - e)/(ea + 2e) + (1 - f)(eb - e)/(eb + 2e) = 0
 *   <=> 2e² - [(3f - 1) ea + (2 - 3f) eb] e - ea eb = 0, the root with
 *   Re e > 0. */
#include "vr_test.h"
#include "vr/ellipso_fit.h"

static vr_sample_model *model(const char *text, vr_error *err) {
  vr_sample_model *m = NULL;
  vr_model_parse(text, strlen(text), "r.model", VR_SOURCE_DIR, NULL, &m, err);
  return m;
}

static void roughness_above_film(void **state) {
  (void)state;
  vr_error err = {0};
  /* film n = 1.5 (Cauchy with A only), void; fraction is of component B. */
  vr_sample_model *m = model("layer rough ema=bruggeman(film,void) thickness=3 fraction=0.4\n"
                             "layer film cauchy thickness=50 A=1.5 B=0 C=0\n"
                             "substrate file:samples/ellipsometry/Si_Aspnes.yml\n",
                             &err);
  if (!m) fail_msg("%s", err.message);
  double ea = 1.5 * 1.5, eb = 1.0, f = 0.6; /* f: fraction of the film (A) */
  double b = (3 * f - 1) * ea + (2 - 3 * f) * eb;
  double e = (b + sqrt(b * b + 8 * ea * eb)) / 4;
  char text[512];
  snprintf(text, sizeof text,
           "layer rough constant n=%.17g thickness=3\nlayer film cauchy thickness=50 A=1.5 B=0 C=0\n"
           "substrate file:samples/ellipsometry/Si_Aspnes.yml\n",
           sqrt(e));
  vr_sample_model *h = model(text, &err);
  if (!h) fail_msg("%s", err.message);
  for (double nm = 400; nm <= 800; nm += 100) {
    double p1 = 0, d1 = 0, p2 = 0, d2 = 0;
    if (vr_model_psi_delta(m, nm, 70, &p1, &d1, NULL, &err) || vr_model_psi_delta(h, nm, 70, &p2, &d2, NULL, &err))
      fail_msg("%s", err.message);
    assert_near(p1, p2, 1e-10);
    assert_near(d1, d2, 1e-10);
  }
  vr_model_destroy(h);
  vr_model_destroy(m);
  /* A component named before its layer must have a material of its own. */
  err = (vr_error){0};
  assert_null(model("layer r ema=bruggeman(s,void) thickness=2\nlayer s ema=bruggeman(t,void) thickness=2\n"
                    "layer t constant n=1.5 thickness=5\nsubstrate constant\n",
                    &err));
  assert_contains(err.message, "r.model:1: effective medium of layer 'r': 's' comes later and is itself an effective medium");
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(roughness_above_film)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
