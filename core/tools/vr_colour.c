/* vr-colour: the colour of spectra.  Reads a table of reflectance,
 * transmittance or emission spectra (first column wavelength, one spectrum
 * per further column) and prints CIE XYZ, xy, CIELAB and 8-bit sRGB for each
 * one, under a chosen illuminant and observer; for emission spectra, the
 * correlated colour temperature, Duv and the CIE 13.3 colour rendering
 * indices (vr/cri.h). */
#include "vr/args.h"
#include "vr/colour.h"
#include "vr/cri.h"
#include "vr/json.h"
#include "vr/spectrum.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const vr_option OPTIONS[] = {
    {"illuminant", 'i', "NAME", "illuminant for reflectances (default D65); see --list-illuminants"},
    {"observer", 'o', "2|10", "CIE 1931 2° (default) or CIE 1964 10° observer"},
    {"emitter", 'e', NULL, "the spectra are radiances in W/(sr m² nm): print absolute XYZ (cd/m²), CCT, Duv and the CIE 13.3 colour rendering index"},
    {"json", 'j', NULL, "print JSON instead of a table"},
    {"list-illuminants", 0, NULL, "list the built-in illuminant names and exit"},
    {"extend", 0, NULL, "a spectrum that stops inside 400-700 nm is extended by its end values"},
};
#define NOPT (sizeof OPTIONS / sizeof OPTIONS[0])

/* What the colorimetry needs of a spectrum, checked for every spectrum
 * before anything is printed:
 *   - two wavelengths at least (one row is no spectrum);
 *   - the range 400-700 nm, where the CIE 1931 observer's y-bar holds
 *     99.6 % of its integral: beyond the data, end values are held (CIE
 *     015:2018, 7.2.2), which is said; a spectrum that stops inside that
 *     range is refused unless --extend, and one that does not reach 380-780
 *     nm at all is refused always (there is nothing to extend);
 *   - a reflectance within [-0.05, 1.5] (noise below 0, fluorescence above
 *     1; beyond, a unit error such as percent);
 *   - a colour that is finite (values of 1e308 overflow XYZ). */
static bool check_spectrum(const char *file, const char *name, const vr_spectrum *s, bool emitter,
                           bool extend, vr_error *err) {
  if (s->n < 2)
    return vr_error_set(err, VR_E_RANGE,
                        "%s: spectrum '%s' has one wavelength (%g nm): a colour needs the visible "
                        "range, 400-700 nm at least",
                        file, name, s->nm[0]),
           false;
  double lo = s->nm[0], hi = s->nm[s->n - 1];
  if (hi < 380 || lo > 780)
    return vr_error_set(err, VR_E_RANGE,
                        "%s: spectrum '%s' covers %g-%g nm, outside the visible range (380-780 "
                        "nm): it has no colour",
                        file, name, lo, hi),
           false;
  if ((lo > 400 || hi < 700) && !extend)
    return vr_error_set(err, VR_E_RANGE,
                        "%s: spectrum '%s' covers %g-%g nm, not the 400-700 nm a colour needs: "
                        "give --extend to hold its end values beyond (CIE 015:2018, 7.2.2)",
                        file, name, lo, hi),
           false;
  for (size_t k = 0; k < s->n; k++) {
    double v = s->value[k];
    if (!emitter && (v < -0.05 || v > 1.5))
      return vr_error_set(err, VR_E_RANGE,
                          "%s: spectrum '%s' has reflectance %g at %g nm: a reflectance lies in "
                          "[0, 1] (up to 1.5 for fluorescence, down to -0.05 for noise)%s",
                          file, name, v, s->nm[k], v > 1.5 && v <= 100 ? "; in percent? divide by 100" : ""),
             false;
  }
  if (emitter) {
    /* Dark-subtracted spectroradiometer data dip slightly below 0 at the
     * ends: 1 % of the peak is noise, more is not a radiance. */
    double peak = 0;
    for (size_t k = 0; k < s->n; k++) peak = fmax(peak, s->value[k]);
    for (size_t k = 0; k < s->n; k++)
      if (s->value[k] < -0.01 * peak || (peak <= 0 && s->value[k] < 0))
        return vr_error_set(err, VR_E_RANGE,
                            "%s: spectrum '%s' has radiance %g at %g nm: below -1 %% of its peak "
                            "(%g), not noise about 0",
                            file, name, s->value[k], s->nm[k], peak),
               false;
  }
  return true;
}

/* An emission spectrum that stops inside 360-830 nm as the colorimetry
 * reads it: zero beyond its data (held end values would add light that was
 * not measured), reached within 1 nm of its ends. */
static vr_spectrum *emission_extended(const vr_spectrum *s, vr_error *err) {
  size_t n = s->n, k = 0;
  double *nm = malloc((n + 4) * sizeof *nm), *v = malloc((n + 4) * sizeof *v);
  vr_spectrum *out = NULL;
  if (nm && v) {
    double lo = s->nm[0], hi = s->nm[n - 1];
    if (lo > 361) nm[k] = 360, v[k++] = 0;
    if (lo > 360) nm[k] = lo - 1 > 360 ? lo - 1 : (lo + 360) / 2, v[k++] = 0;
    for (size_t i = 0; i < n; i++) nm[k] = s->nm[i], v[k++] = s->value[i];
    if (hi < 830) nm[k] = hi + 1 < 830 ? hi + 1 : (hi + 830) / 2, v[k++] = 0;
    if (hi < 829) nm[k] = 830, v[k++] = 0;
    out = vr_spectrum_create(k, nm, v, err);
  } else {
    vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  free(nm);
  free(v);
  return out;
}

int main(int argc, char **argv) {
  vr_args a;
  vr_args_outcome o = vr_args_parse(
      &a, "vr-colour", "[options] SPECTRA.csv",
      "Prints the CIE colour of each spectrum in SPECTRA.csv (header line; first column the\n"
      "wavelength in nm, um, A or eV as its header says; one spectrum per further column).\n"
      "Reflectances are taken under the illuminant and normalised so the perfect white has\n"
      "Y = 1; CIELAB is relative to the illuminant's white; sRGB (IEC 61966-2-1) is computed\n"
      "after Bradford adaptation from that white to D65, and marked '*' when out of gamut.",
      OPTIONS, NOPT, argc, argv);
  if (o == VR_ARGS_EXIT_OK) return 0;
  if (o == VR_ARGS_EXIT_USAGE) return 2;
  int rc = 1;
  vr_error err = {0};
  vr_spectrum *illum = NULL;
  vr_spectrum_table t = {0};
  if (vr_args_flag(&a, "list-illuminants")) {
    size_t n;
    const char *const *names = vr_illuminant_names(&n);
    for (size_t i = 0; i < n; i++) printf("%s\n", names[i]);
    printf("D<CCT>   CIE daylight at any CCT from 4000 to 25000 K, e.g. D6000\n");
    printf("BB<T>    blackbody at T kelvin, e.g. BB2700\n");
    vr_args_free(&a);
    return 0;
  }
  if (a.noperands != 1) {
    fprintf(stderr, "vr-colour: expected one spectra file, got %zu\nTry 'vr-colour --help'.\n",
            a.noperands);
    vr_args_free(&a);
    return 2;
  }
  vr_observer obs = VR_CIE1931_2DEG;
  const char *obs_text = vr_args_get(&a, "observer");
  const char *illum_name = vr_args_get(&a, "illuminant");
  bool emitter = vr_args_flag(&a, "emitter"), json = vr_args_flag(&a, "json");
  if (!illum_name) illum_name = "D65";
  if (obs_text && vr_observer_parse(obs_text, &obs, &err)) goto fail;
  if (!(illum = vr_illuminant(illum_name, &err))) goto fail;
  if (vr_spectrum_table_read(a.operands[0], &t, &err)) goto fail;
  bool extend = vr_args_flag(&a, "extend");
  size_t held = 0;
  for (size_t i = 0; i < t.count; i++) {
    if (!check_spectrum(a.operands[0], t.names[i], t.spectra[i], emitter, extend, &err)) goto fail;
    const vr_spectrum *s = t.spectra[i];
    held += s->nm[0] > 380 || s->nm[s->n - 1] < 780;
    if (emitter && (s->nm[0] > 360 || s->nm[s->n - 1] < 830)) {
      vr_spectrum *z = emission_extended(s, &err);
      if (!z) goto fail;
      vr_spectrum_destroy(t.spectra[i]);
      t.spectra[i] = z;
      s = z;
    }
    double xyz[3];
    if (emitter) vr_xyz_emitter(s, obs, xyz);
    else vr_xyz_reflectance(s, illum, obs, xyz);
    if (!isfinite(xyz[0]) || !isfinite(xyz[1]) || !isfinite(xyz[2])) {
      vr_error_set(&err, VR_E_RANGE,
                   "%s: spectrum '%s': its values are too large for a colour (XYZ overflows)",
                   a.operands[0], t.names[i]);
      goto fail;
    }
  }
  if (held)
    fprintf(stderr,
            emitter ? "vr-colour: %zu of %zu emission spectra stop inside 380-780 nm: their "
                      "emission is taken as zero beyond their data\n"
                    : "vr-colour: %zu of %zu spectra stop inside 380-780 nm: their end values are "
                      "held beyond (CIE 015:2018, 7.2.2)\n",
            held, t.count);

  double white[3], d65[3];
  vr_xyz_white(illum, obs, white);
  vr_srgb_white(d65);
  if (json) printf("{\"illuminant\": \"%s\", \"observer\": \"%s\", \"spectra\": [", illum_name,
                   obs == VR_CIE1931_2DEG ? "CIE 1931 2" : "CIE 1964 10");
  else if (emitter)
    printf("%-20s %12s %12s %12s %8s %8s %8s %8s %6s %6s\n", "spectrum", "X", "Y (cd/m2)", "Z", "x",
           "y", "CCT (K)", "Duv", "Ra", "R9");
  else
    printf("%-20s %9s %9s %9s %8s %8s %8s %8s %8s %s\n", "spectrum", "X", "Y", "Z", "x", "y",
           "L*", "a*", "b*", "sRGB8");
  for (size_t i = 0; i < t.count; i++) {
    double xyz[3], xyy[3], lab[3], adapted[3];
    int rgb[3];
    if (emitter) vr_xyz_emitter(t.spectra[i], obs, xyz);
    else vr_xyz_reflectance(t.spectra[i], illum, obs, xyz);
    vr_xyz_to_xyy(xyz, white, xyy);
    vr_xyz_to_lab(xyz, white, lab);
    vr_bradford(xyz, white, d65, adapted);
    bool clipped = vr_xyz_to_srgb8(adapted, rgb);
    /* A lamp's CCT, Duv (CIE 1931 observer, as CIE 015 defines them) and
     * colour rendering; a light far from the Planckian locus (a coloured
     * LED) has none, and gets no figures rather than meaningless ones. */
    /* The CCT shown is the chromaticity's at 1 nm over 360-830 nm; the
     * rendering's reference takes CIE 13.3's own, from 5 nm sums. */
    vr_cri cri = {.cct = NAN, .Ra = NAN};
    double duv = NAN, cct = NAN;
    if (emitter) {
      double x31[3], uv[2];
      vr_xyz_emitter(t.spectra[i], VR_CIE1931_2DEG, x31);
      vr_xyz_to_uv1960(x31, uv);
      if (!(x31[1] > 0) || vr_cct_from_uv(uv, &cct, &duv, NULL) ||
          vr_cri_compute(t.spectra[i], &cri, NULL))
        cri.Ra = cct = duv = NAN;
    }
    if (json) {
      printf("%s\n  {\"name\": ", i ? "," : "");
      vr_json_string(stdout, t.names[i]);
      printf(", \"XYZ\": [%.6f, %.6f, %.6f], \"xy\": [%.6f, %.6f]", xyz[0], xyz[1], xyz[2], xyy[0],
             xyy[1]);
      if (!emitter)
        printf(", \"Lab\": [%.4f, %.4f, %.4f], \"sRGB8\": [%d, %d, %d], \"out_of_gamut\": %s",
               lab[0], lab[1], lab[2], rgb[0], rgb[1], rgb[2], clipped ? "true" : "false");
      if (emitter) {
        printf(", \"CCT_K\": ");
        vr_json_number(stdout, cct);
        printf(", \"Duv\": ");
        vr_json_number(stdout, duv);
        printf(", \"Ra\": ");
        vr_json_number(stdout, cri.Ra);
        printf(", \"R\": ");
        for (int j = 0; j < VR_CRI_SAMPLES && !isnan(cri.Ra); j++) {
          printf(j ? ", " : "[");
          vr_json_number(stdout, cri.R[j]);
        }
        printf(isnan(cri.Ra) ? "null" : "]");
        printf(", \"cri_dc_ok\": %s", !isnan(cri.Ra) && cri.dc_ok ? "true" : "false");
      }
      printf("}");
    } else if (emitter) {
      printf("%-20.20s %12.6g %12.6g %12.6g %8.5f %8.5f", t.names[i], xyz[0], xyz[1], xyz[2],
             xyy[0], xyy[1]);
      if (isnan(cri.Ra))
        printf(" %8s %8s %6s %6s\n", "-", "-", "-", "-");
      else
        printf(" %8.0f %8.5f %6.1f %6.1f%s\n", cct, duv, cri.Ra, cri.R[8],
               cri.dc_ok ? "" : " (DC > 5.4e-3: Ra not meaningful, CIE 13.3)");
    } else {
      printf("%-20.20s %9.5f %9.5f %9.5f %8.5f %8.5f %8.3f %8.3f %8.3f %3d %3d %3d%s\n", t.names[i],
             xyz[0], xyz[1], xyz[2], xyy[0], xyy[1], lab[0], lab[1], lab[2], rgb[0], rgb[1], rgb[2],
             clipped ? " *" : "");
    }
  }
  if (json) printf("\n]}\n");
  rc = 0;
  goto done;
fail:
  fprintf(stderr, "vr-colour: %s\n", err.message);
done:
  vr_spectrum_table_free(&t);
  vr_spectrum_destroy(illum);
  vr_args_free(&a);
  return rc;
}
