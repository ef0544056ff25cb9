/* The files of a render (vr/film.h) from results built by hand: no engine
 * involved.  Expected values:
 *  - sRGB: IEC 61966-2-1:1999, its 4-digit XYZ -> RGB matrix and transfer
 *    curve; encode(0.5) = 1.055 * 0.5^(1/2.4) - 0.055 = 0.735357, so 8-bit
 *    188 (187.5 rounded).  The standard's matrix puts the D65 white
 *    (x, y = 0.3127, 0.3290) at R, G, B = 0.99984, 1.00010, 1.00007: that is
 *    the 2e-4 tolerance on "white = (1, 1, 1)" below.
 *  - Exposure convention of docs/vr-render.md: 100 cd/m² of the white is
 *    display 1.0 at EV 0; Reinhard (2002, eq. 3) L / (1 + L) on luminance.
 *  - Spectral OpenEXR channel names: Fichet, Pacanowski, Wilkie, JCGT 10(3)
 *    2021 ("S0.550,000000nm"). */
#include "../acquire/image_test_util.h"

#include <ctype.h>
#include <openexr.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "vr/colour.h"
#include "vr/falsecolour.h"
#include "vr/film.h"
#include "vr/spectral_exr.h"

enum { W = 4, H = 2, NB = 3 };
static const double BINS[NB] = {450, 550, 650};

typedef struct owned_result {
  vr_render_result r;
  double xyz[W * H * 3], spectral[W * H * NB], bin_nm[NB];
  vr_sensor_reading readings[2];
  double sensor_spectral[2 * NB];
} owned_result;

/* 4 x 2 pixels of the D65 white at luminance Y (cd/m²), three bins of
 * radiance 0.01 * (b + 1) W/(m² sr nm), two sensor readings. */
static void make_result(owned_result *o, double Y) {
  memset(o, 0, sizeof *o);
  double white[3];
  vr_srgb_white(white);
  for (int p = 0; p < W * H; p++) {
    for (int c = 0; c < 3; c++) o->xyz[3 * p + c] = white[c] * Y;
    for (int b = 0; b < NB; b++) o->spectral[p * NB + b] = 0.01 * (b + 1);
  }
  memcpy(o->bin_nm, BINS, sizeof BINS);
  o->readings[0] = (vr_sensor_reading){.sensor = "floor", .illuminance_lx = 111.1, .stderr_lx = 0.2};
  o->readings[1] = (vr_sensor_reading){.sensor = "desk, left", .i = 1, .j = 2,
                                       .position = {1.5, -2, 0.75}, .illuminance_lx = 42.5,
                                       .stderr_lx = 0.5};
  /* The floor with parts and a daylight factor (a path sensor under a sky),
   * the desk without (a photon sensor). */
  const double parts[VR_SENSOR_PARTS] = {50, 30, 5, 4, 12, 10, 0.1};
  memcpy(o->readings[0].part_lx, parts, sizeof parts);
  o->readings[0].df_pct = 6.7, o->readings[0].df_sc_pct = 5;
  o->readings[0].df_erc_pct = 0.5, o->readings[0].df_irc_pct = 1.2;
  for (int q = 0; q < VR_SENSOR_PARTS; q++) o->readings[1].part_lx[q] = NAN;
  o->readings[1].df_pct = o->readings[1].df_sc_pct = o->readings[1].df_erc_pct =
      o->readings[1].df_irc_pct = NAN;
  for (int k = 0; k < 2 * NB; k++) o->sensor_spectral[k] = 0.1 * (k + 1);
  vr_render_result *r = &o->r;
  r->width = W, r->height = H;
  r->xyz = o->xyz;
  r->nbins = NB;
  r->bin_nm = o->bin_nm;
  r->bin_width_nm = 100;
  r->spectral = o->spectral;
  r->nreadings = 2;
  r->readings = o->readings;
  r->sensor_spectral = o->sensor_spectral;
  r->npasses = 2;
  r->passes[0] = (vr_pass_record){"caustic photons", false, "no specular surface \"seen\" through", 0};
  r->passes[1] = (vr_pass_record){"camera", true, "the scene has a camera", 1.25};
  r->rays_camera = 1000, r->rays_shadow = 2000, r->crossings = 7;
  r->rays_created = 3000, r->rays_finished = 3000;
  r->seconds_total = 1.5;
}

static bool exists(const char *path) {
  struct stat st;
  return stat(path, &st) == 0;
}

static char *slurp(const char *path) {
  FILE *f = fopen(path, "rb");
  assert_non_null(f);
  static char buf[1 << 16];
  size_t n = fread(buf, 1, sizeof buf - 1, f);
  fclose(f);
  buf[n] = '\0';
  return buf;
}

static void read_png(const char *path, vr_image *img) {
  vr_error err = {0};
  assert_int_equal(vr_image_read(path, img, &err), VR_OK);
  assert_int_equal(img->bit_depth, 8);
  assert_int_equal(img->width, W);
  assert_int_equal(img->height, H);
}

static void png_white_ev0_is_255(void **state) {
  (void)state;
  owned_result o;
  make_result(&o, 100);
  vr_error err = {0};
  assert_int_equal(vr_film_write(&o.r, in_dir("w"), NULL, &err), VR_OK);
  vr_image img = {0};
  read_png(in_dir("w.png"), &img);
  for (int i = 0; i < W * H * 3; i++) assert_near(img.data[i] * 255.0, 255, 1e-3);
  vr_image_free(&img);
}

/* A uniform 100 cd/m2 film at exposure ev, written with tonemap as `name`:
 * every PNG value must be png (within one step). */
static void png_of_100_cd_is(const char *name, const char *tonemap, double ev, int png) {
  owned_result o;
  make_result(&o, 100);
  o.r.exposure_ev = ev;
  vr_error err = {0};
  char file[64];
  assert_int_equal(vr_film_write(&o.r, in_dir(name), tonemap, &err), VR_OK);
  snprintf(file, sizeof file, "%s.png", name);
  vr_image img = {0};
  read_png(in_dir(file), &img);
  for (int i = 0; i < W * H * 3; i++) assert_near(img.data[i] * 255.0, png, 1.0 + 1e-3);
  vr_image_free(&img);
}

static void png_ev_minus_one_is_half(void **state) {
  (void)state;
  assert_near(vr_srgb_encode(0.5), 0.735357, 1e-6);
  png_of_100_cd_is("half", "clip", -1, 188);
}

/* --tonemap filmic: Narkowicz's fit of the ACES curve (K. Narkowicz,
 * "ACES Filmic Tone Mapping Curve", 2016), f(x) = x (2.51 x + 0.03) /
 * (x (2.43 x + 0.59) + 0.14), on each channel of rgb x 2^EV / 100; the
 * values below are that formula worked by hand.  100 cd/m2 at EV 0: x = 1,
 * f = 2.54 / 3.16 = 0.803797 (PNG 232 after the sRGB curve); mid grey
 * 0.18 gives 0.266899; the shoulder reaches 1 at x = 7.2417. */
static void filmic_follows_the_aces_fit(void **state) {
  (void)state;
  png_of_100_cd_is("fm", "filmic", 0, 232);
  vr_error err = {0};
  double grey[3] = {100, 100, 100}, out[3];
  vr_film_display(grey, 100, 0, VR_TONEMAP_FILMIC, out);
  for (int c = 0; c < 3; c++) assert_near(out[c], 2.54 / 3.16, 1e-12);
  double mid[3] = {18, 18, 18};
  vr_film_display(mid, 18, 0, VR_TONEMAP_FILMIC, out);
  assert_near(out[1], 0.2668989203894968, 1e-12);
  /* The exposure scales the input: 50 cd/m2 at EV +1 is 100 at EV 0. */
  double half[3] = {50, 50, 50};
  vr_film_display(half, 50, 1, VR_TONEMAP_FILMIC, out);
  assert_near(out[0], 2.54 / 3.16, 1e-12);
  /* Per channel: a saturated orange x = 4, 2.5, 1 goes towards white. */
  double rgb[3] = {400, 250, 100};
  vr_film_display(rgb, 300, 0, VR_TONEMAP_FILMIC, out);
  assert_near(out[0], 0.9734171097148379, 1e-12);
  assert_near(out[1], 0.9381044487427465, 1e-12);
  assert_near(out[2], 0.8037974683544302, 1e-12);
  /* The shoulder: just below x = 7.2417 under 1, above it 1; negative
   * (out of gamut), zero and infinite channels give 0, 0 and 1. */
  double below[3] = {724, 0, -5}, above[3] = {725, 1e300, INFINITY};
  vr_film_display(below, 300, 0, VR_TONEMAP_FILMIC, out);
  assert_true(out[0] < 1.0 && out[0] > 0.9999);
  assert_near(out[1], 0, 0);
  assert_near(out[2], 0, 0);
  vr_film_display(above, 300, 0, VR_TONEMAP_FILMIC, out);
  for (int c = 0; c < 3; c++) assert_near(out[c], 1.0, 0);
  vr_tonemap tm;
  assert_int_equal(vr_tonemap_parse("FILMIC", &tm, &err), VR_OK);
  assert_int_equal(tm, VR_TONEMAP_FILMIC);
}

static void reinhard_maps_100_cd_to_half(void **state) {
  (void)state;
  png_of_100_cd_is("rh", "Reinhard", 0, 188);
  owned_result o;
  make_result(&o, 100);
  vr_error err = {0};
  /* A coloured pixel keeps its channel ratios: Y = 300 cd/m² -> L = 3 ->
   * 0.75, every channel scaled by 0.25 / 100. */
  double rgb[3] = {400, 250, 100}, out[3];
  vr_film_display(rgb, 300, 0, VR_TONEMAP_REINHARD, out);
  assert_near(out[0], 1.0, 1e-12);
  assert_near(out[1], 0.625, 1e-12);
  assert_near(out[2], 0.25, 1e-12);
  /* Clip: plain scaling, clamped; black stays black. */
  vr_film_display(rgb, 300, 0, VR_TONEMAP_CLIP, out);
  for (int c = 0; c < 3; c++) assert_near(out[c], 1.0, 0);
  double black[3] = {0, 0, 0};
  vr_film_display(black, 0, 0, VR_TONEMAP_REINHARD, out);
  assert_near(out[0] + out[1] + out[2], 0, 0);
  vr_tonemap tm;
  assert_int_equal(vr_tonemap_parse("aces", &tm, &err), VR_E_ARG);
  assert_contains(err.message, "'aces'");
  assert_int_equal(vr_film_write(&o.r, in_dir("bad"), "aces", &err), VR_E_ARG);
  assert_false(exists(in_dir("bad.exr")));
}

static void exr_holds_linear_srgb_in_cd_m2(void **state) {
  (void)state;
  owned_result o;
  make_result(&o, 100);
  vr_error err = {0};
  assert_int_equal(vr_film_write(&o.r, in_dir("lin"), NULL, &err), VR_OK);
  vr_image img = {0};
  assert_int_equal(vr_image_read(in_dir("lin.exr"), &img, &err), VR_OK);
  assert_int_equal(img.bit_depth, 32);
  assert_int_equal(img.width, W);
  double expect[3];
  vr_xyz_to_srgb_linear(o.xyz, expect);
  for (int p = 0; p < W * H; p++)
    for (int c = 0; c < 3; c++) {
      assert_rel(img.data[3 * p + c], expect[c], 1e-6); /* float storage */
      assert_rel(img.data[3 * p + c], 100.0, 2e-4);     /* the standard's matrix */
    }
  /* Luminance from the primaries' Y row gives back the film's Y. */
  double Y = 0.2126 * img.data[0] + 0.7152 * img.data[1] + 0.0722 * img.data[2];
  assert_rel(Y, 100.0, 1e-4);
  vr_image_free(&img);
}

static void spectral_exr_has_bins_and_rgb(void **state) {
  (void)state;
  owned_result o;
  make_result(&o, 100);
  vr_error err = {0};
  assert_int_equal(vr_film_write(&o.r, in_dir("sp"), NULL, &err), VR_OK);
  /* Channel count and names, with OpenEXR itself. */
  exr_context_t ctxt;
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  assert_int_equal(exr_start_read(&ctxt, in_dir("sp.spectral.exr"), &init), EXR_ERR_SUCCESS);
  const exr_attr_chlist_t *ch = NULL;
  assert_int_equal(exr_get_channels(ctxt, 0, &ch), EXR_ERR_SUCCESS);
  assert_int_equal(ch->num_channels, NB + 3);
  bool seen550 = false, seenR = false;
  for (int i = 0; i < ch->num_channels; i++) {
    seen550 |= !strcmp(ch->entries[i].name.str, "S0.550,000000nm");
    seenR |= !strcmp(ch->entries[i].name.str, "R");
  }
  assert_true(seen550);
  assert_true(seenR);
  const exr_attribute_t *units = NULL;
  assert_int_equal(exr_get_attribute_by_name(ctxt, 0, "emissiveUnits", &units), EXR_ERR_SUCCESS);
  /* The reference writer's spelling (ART's OpenEXR wrapper, pbrt-v4). */
  assert_string_equal(units->string->str, "W.m^-2.sr^-1");
  exr_finish(&ctxt);
  /* Values, through our reader. */
  vr_spectral_image sp = {0};
  vr_image rgb = {0};
  assert_int_equal(vr_spectral_exr_read(in_dir("sp.spectral.exr"), &sp, &rgb, &err), VR_OK);
  assert_int_equal(sp.nbands, NB);
  assert_int_equal(sp.kind, VR_SPECTRAL_EMISSIVE);
  for (int b = 0; b < NB; b++) {
    assert_near(sp.wavelengths_nm[b], BINS[b], 1e-9);
    assert_rel(sp.data[(1 * W + 3) * NB + b], 0.01 * (b + 1), 1e-6);
  }
  assert_non_null(rgb.data);
  assert_rel(rgb.data[1], 100.0, 2e-4);
  vr_spectral_image_free(&sp);
  vr_image_free(&rgb);
}

static void sensor_table_has_one_row_per_point(void **state) {
  (void)state;
  owned_result o;
  make_result(&o, 100);
  vr_error err = {0};
  assert_int_equal(vr_film_write(&o.r, in_dir("sn"), NULL, &err), VR_OK);
  char *csv = slurp(in_dir("sn.sensors.csv"));
  assert_string_equal(csv,
                      "sensor,i,j,x,y,z,illuminance_lx,stderr_lx,E_450,E_550,E_650,"
                      "sky_component_lx,sun_direct_lx,externally_reflected_sky_lx,"
                      "externally_reflected_sun_lx,internally_reflected_sky_lx,"
                      "internally_reflected_sun_lx,electric_lx,daylight_factor_pct,"
                      "df_sky_component_pct,df_externally_reflected_pct,"
                      "df_internally_reflected_pct\n"
                      "floor,0,0,0,0,0,111.1,0.2,0.1,0.2,0.3,50,30,5,4,12,10,0.1,6.7,5,0.5,1.2\n"
                      "\"desk, left\",1,2,1.5,-2,0.75,42.5,0.5,0.4,0.5,0.6,,,,,,,,,,,\n");
  /* A sensors-only result: no images, the table alone. */
  o.r.width = o.r.height = 0;
  o.r.xyz = NULL;
  assert_int_equal(vr_film_write(&o.r, in_dir("only"), NULL, &err), VR_OK);
  assert_true(exists(in_dir("only.sensors.csv")));
  assert_false(exists(in_dir("only.exr")));
  assert_false(exists(in_dir("only.png")));
  /* No readings: no table. */
  make_result(&o, 100);
  o.r.nreadings = 0;
  assert_int_equal(vr_film_write(&o.r, in_dir("nosn"), NULL, &err), VR_OK);
  assert_true(exists(in_dir("nosn.png")));
  assert_false(exists(in_dir("nosn.sensors.csv")));
}

/* ---- a small JSON checker: RFC 8259 values, nothing else ---- */

static const char *json_value(const char *s);

static const char *json_ws(const char *s) {
  while (*s == ' ' || *s == '\n' || *s == '\t' || *s == '\r') s++;
  return s;
}

static const char *json_string(const char *s) {
  if (*s != '"') return NULL;
  for (s++; *s && *s != '"'; s++) {
    if ((unsigned char)*s < 0x20) return NULL;
    if (*s == '\\' && !*++s) return NULL;
  }
  return *s == '"' ? s + 1 : NULL;
}

static const char *json_list(const char *s, char close, bool keys) {
  s = json_ws(s + 1);
  if (*s == close) return s + 1;
  for (;;) {
    if (keys) {
      if (!(s = json_string(s))) return NULL;
      s = json_ws(s);
      if (*s++ != ':') return NULL;
    }
    if (!(s = json_value(s))) return NULL;
    s = json_ws(s);
    if (*s == close) return s + 1;
    if (*s++ != ',') return NULL;
    s = json_ws(s);
  }
}

static const char *json_value(const char *s) {
  s = json_ws(s);
  if (*s == '{') return json_list(s, '}', true);
  if (*s == '[') return json_list(s, ']', false);
  if (*s == '"') return json_string(s);
  for (const char *lit = "true\0false\0null\0"; *lit; lit += strlen(lit) + 1)
    if (!strncmp(s, lit, strlen(lit))) return s + strlen(lit);
  char *end;
  strtod(s, &end);
  return end > s && (isdigit((unsigned char)*s) || *s == '-') ? end : NULL;
}

static void stats_json_parses_and_has_the_keys(void **state) {
  (void)state;
  owned_result o;
  make_result(&o, 100);
  vr_error err = {0};
  const char *path = in_dir("stats.json");
  assert_int_equal(vr_stats_write_json(&o.r, path, &err), VR_OK);
  const char *js = slurp(path);
  const char *end = json_value(js);
  if (!end || *json_ws(end)) fail_msg("not one JSON value:\n%s", js);
  static const char *const KEYS[] = {
      "\"passes\"",   "\"name\"",      "\"ran\"",          "\"reason\"",     "\"seconds\"",
      "\"rays\"",     "\"camera\"",    "\"shadow\"",       "\"photon\"",     "\"crossings\"",
      "\"created\"",  "\"finished\"",  "\"peak_rss_bytes\"", "\"photons\"",  "\"sensors\"",
      "\"i\"",        "\"j\"",         "\"illuminance_lx\"", "\"stderr_lx\"", "\"seconds_total\"",
      "\"photochromic\"", "\"texels\"", "\"state_min\"",   "\"state_max\""};
  for (size_t k = 0; k < sizeof KEYS / sizeof *KEYS; k++) assert_contains(js, KEYS[k]);
  /* Quotes in a reason are escaped, and the numbers are the result's. */
  assert_contains(js, "no specular surface \\\"seen\\\" through");
  assert_contains(js, "\"camera\": 1000,");
  assert_contains(js, "\"illuminance_lx\": 111.09999999999999");
  assert_contains(js, "\"state_min\": null"); /* no photochromic texels */
  const char *rss = strstr(js, "\"peak_rss_bytes\": ");
  assert_non_null(rss);
  assert_true(strtoll(rss + strlen("\"peak_rss_bytes\": "), NULL, 10) > 0);
  assert_true(vr_peak_rss_bytes() > 1024 * 1024); /* any process holds more than 1 MiB */
}

static void nan_pixel_writes_nothing(void **state) {
  (void)state;
  owned_result o;
  make_result(&o, 100);
  o.xyz[3 * (1 * W + 2) + 1] = NAN; /* pixel (2, 1), Y */
  vr_error err = {0};
  int before = test_dir_entries();
  assert_int_equal(vr_film_write(&o.r, in_dir("nan"), NULL, &err), VR_E_RANGE);
  assert_contains(err.message, "pixel (2, 1)");
  assert_contains(err.message, "NaN");
  assert_false(exists(in_dir("nan.exr")));
  assert_false(exists(in_dir("nan.spectral.exr")));
  assert_false(exists(in_dir("nan.png")));
  assert_false(exists(in_dir("nan.sensors.csv")));
  assert_int_equal(test_dir_entries(), before);
  /* A NaN bin is refused the same way, naming its wavelength. */
  make_result(&o, 100);
  o.spectral[(0 * W + 1) * NB + 2] = NAN;
  assert_int_equal(vr_film_write(&o.r, in_dir("nan"), NULL, &err), VR_E_RANGE);
  assert_contains(err.message, "pixel (1, 0)");
  assert_contains(err.message, "650 nm");
  /* So is a NaN reading, naming the sensor. */
  make_result(&o, 100);
  o.readings[1].illuminance_lx = NAN;
  assert_int_equal(vr_film_write(&o.r, in_dir("nan"), NULL, &err), VR_E_RANGE);
  assert_contains(err.message, "desk, left");
  assert_int_equal(test_dir_entries(), before);
  /* Earlier files of the same prefix stay as they were. */
  make_result(&o, 100);
  assert_int_equal(vr_film_write(&o.r, in_dir("keep"), NULL, &err), VR_OK);
  char old[4096];
  const char *kept = slurp(in_dir("keep.sensors.csv"));
  assert_true(strlen(kept) < sizeof old);
  memcpy(old, kept, strlen(kept) + 1);
  o.readings[0].illuminance_lx = 1;
  o.xyz[0] = NAN;
  assert_int_equal(vr_film_write(&o.r, in_dir("keep"), NULL, &err), VR_E_RANGE);
  assert_string_equal(slurp(in_dir("keep.sensors.csv")), old);
  assert_true(exists(in_dir("keep.png")));
}

/* A failure after some files are in place: PREFIX.png is a folder, so the
 * PNG cannot be moved over it; the EXRs already moved are taken back. */
static void failed_output_removes_the_others(void **state) {
  (void)state;
  owned_result o;
  make_result(&o, 100);
  assert_int_equal(mkdir(in_dir("blocked.png"), 0755), 0);
  int before = test_dir_entries();
  vr_error err = {0};
  assert_int_not_equal(vr_film_write(&o.r, in_dir("blocked"), NULL, &err), VR_OK);
  assert_contains(err.message, "blocked.png");
  assert_false(exists(in_dir("blocked.exr")));
  assert_false(exists(in_dir("blocked.spectral.exr")));
  assert_false(exists(in_dir("blocked.sensors.csv")));
  assert_int_equal(test_dir_entries(), before); /* no staging file either */
  rmdir(in_dir("blocked.png"));
  /* A folder that does not exist: an error naming the path, nothing else. */
  assert_int_not_equal(vr_film_write(&o.r, in_dir("none/x"), NULL, &err), VR_OK);
  assert_contains(err.message, "none/x");
  assert_contains(err.message, "No such file");
}

static void falsecolour_map(void **state) {
  (void)state;
  /* The scale is logarithmic: on 10..10000 cd/m2, 100 sits at 1/3 and
   * 1000 at 2/3 (log10 steps of one decade in three). */
  assert_near(vr_falsecolour_position(100, 10, 10000), 1.0 / 3, 1e-12);
  assert_near(vr_falsecolour_position(1000, 10, 10000), 2.0 / 3, 1e-12);
  assert_near(vr_falsecolour_position(1, 10, 10000), 0.0, 0);
  assert_near(vr_falsecolour_position(1e9, 10, 10000), 1.0, 0);
  /* The film: 4 x 2 pixels of 100 cd/m2, one black. */
  owned_result o;
  make_result(&o, 100);
  for (int c = 0; c < 3; c++) o.xyz[c] = 0;
  vr_film_options fo = {.falsecolour_lo_cd_m2 = 10, .falsecolour_hi_cd_m2 = 10000};
  vr_error err = {0};
  assert_int_equal(vr_film_write_with(&o.r, in_dir("fc"), &fo, &err), VR_OK);
  vr_image img = {0};
  assert_int_equal(vr_image_read(in_dir("fc.falsecolour.png"), &img, &err), VR_OK);
  int LW = vr_falsecolour_legend_width(W);
  assert_int_equal(img.width, W + LW);
  assert_int_equal(img.height, 128);
  float want[3];
  vr_falsecolour_colour(1.0 / 3, want);
  for (int p = 1; p < W * H; p++) {
    int x = p % W, y = p / W;
    for (int c = 0; c < 3; c++)
      assert_near(img.data[3 * ((size_t)y * (size_t)img.width + (size_t)x) + c],
                  want[c], 1.0 / 255 + 1e-6); /* one 8-bit step */
  }
  for (int c = 0; c < 3; c++) assert_near(img.data[c], 0.0, 0);
  /* The legend's bar: the top colour of the scale at the top, the bottom
   * one at the bottom; white label pixels beside it. */
  float top[3], bottom[3];
  vr_falsecolour_colour(1, top);
  vr_falsecolour_colour(0, bottom);
  int bx = W + 6, first = -1, last = -1;
  for (int y = 0; y < img.height; y++) {
    const float *px = img.data + 3 * ((size_t)y * (size_t)img.width + (size_t)bx);
    if (px[0] + px[1] + px[2] > 0 && y > 12) { /* below the unit's label */
      if (first < 0) first = y;
      last = y;
    }
  }
  for (int c = 0; c < 3; c++) {
    assert_near(img.data[3 * ((size_t)first * (size_t)img.width + (size_t)bx) + c], top[c],
                1.0 / 255 + 1e-6);
    assert_near(img.data[3 * ((size_t)last * (size_t)img.width + (size_t)bx) + c], bottom[c],
                1.0 / 255 + 1e-6);
  }
  int white = 0;
  for (int y = 0; y < img.height; y++)
    for (int x = W + LW / 5 + 4; x < img.width; x++)
      white += img.data[3 * ((size_t)y * (size_t)img.width + (size_t)x)] == 1.0f;
  assert_true(white > 50);
  vr_image_free(&img);
  /* A scale without 0 < lo < hi, or a map of a film without an image,
   * writes nothing. */
  fo.falsecolour_lo_cd_m2 = 100, fo.falsecolour_hi_cd_m2 = 10;
  assert_int_equal(vr_film_write_with(&o.r, in_dir("fc2"), &fo, &err), VR_E_ARG);
  assert_non_null(strstr(err.message, "0 < low < high"));
  struct stat sb;
  assert_int_not_equal(stat(in_dir("fc2.png"), &sb), 0);
  o.r.width = o.r.height = 0;
  fo.falsecolour_lo_cd_m2 = 10, fo.falsecolour_hi_cd_m2 = 100;
  assert_int_equal(vr_film_write_with(&o.r, in_dir("fc3"), &fo, &err), VR_E_ARG);
  assert_non_null(strstr(err.message, "no image"));
}

/* ---- the set, its manifest and what killed runs leave (vr/film.h) ---- */

static void copy_file(const char *from, const char *to) {
  FILE *a = fopen(from, "rb"), *b = fopen(to, "wb");
  assert_non_null(a);
  assert_non_null(b);
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, a)) > 0) assert_int_equal(fwrite(buf, 1, n, b), n);
  fclose(a);
  fclose(b);
}

static int lines_seen;
static char last_bad[1024];
static void count_line(void *user, const char *line) {
  (void)user;
  lines_seen++;
  if (strncmp(line, "ok", 2)) snprintf(last_bad, sizeof last_bad, "%s", line);
}

/* The manifest lists the set (the statistics included) with sizes and
 * SHA-256; a file of an older set put back among the new ones (what a kill
 * between the final renames leaves) and a missing file are found. */
static void manifest_and_verify(void **state) {
  (void)state;
  owned_result o;
  make_result(&o, 100);
  vr_error err = {0};
  vr_film_options fo = {.stats_path = in_dir("man.json"), .run_id = "run-one"};
  assert_int_equal(vr_film_write_with(&o.r, in_dir("man"), &fo, &err), VR_OK);
  const char *m = slurp(in_dir("man.manifest.json"));
  assert_contains(m, "\"run_id\": \"run-one\"");
  const char *names[] = {"\"man.exr\"", "\"man.spectral.exr\"", "\"man.png\"",
                         "\"man.sensors.csv\"", "\"man.json\""};
  for (int i = 0; i < 5; i++) assert_contains(m, names[i]);
  vr_film_check c;
  lines_seen = 0;
  assert_int_equal(vr_film_verify(in_dir("man"), count_line, NULL, &c, &err), VR_OK);
  assert_int_equal(c.files, 5);
  assert_int_equal(c.bad, 0);
  assert_int_equal(lines_seen, 5);
  assert_string_equal(c.run_id, "run-one");
  /* A second run, brighter: its PNG differs; the first run's PNG put back. */
  copy_file(in_dir("man.png"), in_dir("old.png"));
  make_result(&o, 25);
  fo.run_id = "run-two";
  assert_int_equal(vr_film_write_with(&o.r, in_dir("man"), &fo, &err), VR_OK);
  assert_int_equal(vr_film_verify(in_dir("man"), NULL, NULL, &c, &err), VR_OK);
  copy_file(in_dir("old.png"), in_dir("man.png"));
  assert_int_equal(vr_film_verify(in_dir("man"), count_line, NULL, &c, &err), VR_E_RANGE);
  assert_int_equal(c.bad, 1);
  assert_contains(last_bad, "differs");
  assert_contains(last_bad, "man.png");
  assert_contains(err.message, "1 of 5 files do not match");
  assert_contains(err.message, "run-two");
  unlink(in_dir("man.sensors.csv"));
  assert_int_equal(vr_film_verify(in_dir("man"), count_line, NULL, &c, &err), VR_E_RANGE);
  assert_int_equal(c.bad, 2);
  assert_int_equal(vr_film_verify(in_dir("nothing"), NULL, NULL, &c, &err), VR_E_IO);
  assert_contains(err.message, "nothing.manifest.json");
}

/* vr_film_options.outputs: each choice writes exactly its files, and the
 * manifest lists them; a file the result cannot give writes nothing. */
static void outputs_choose_the_files(void **state) {
  (void)state;
  owned_result o;
  make_result(&o, 100);
  static const char *const SUFFIX[] = {".exr", ".spectral.exr", ".png", ".sensors.csv"};
  const unsigned choices[] = {VR_FILM_EXR, VR_FILM_SPECTRAL, VR_FILM_PNG, VR_FILM_SENSORS,
                              VR_FILM_EXR | VR_FILM_SENSORS, VR_FILM_SPECTRAL | VR_FILM_PNG};
  for (size_t c = 0; c < sizeof choices / sizeof choices[0]; c++) {
    char prefix[32], file[64], name[72];
    snprintf(prefix, sizeof prefix, "out%zu", c);
    vr_film_options fo = {.outputs = choices[c]};
    vr_error err = {0};
    assert_int_equal(vr_film_write_with(&o.r, in_dir(prefix), &fo, &err), VR_OK);
    vr_film_check check;
    assert_int_equal(vr_film_verify(in_dir(prefix), NULL, NULL, &check, &err), VR_OK);
    int n = 0;
    for (int k = 0; k < 4; k++) {
      snprintf(file, sizeof file, "%s%s", prefix, SUFFIX[k]);
      snprintf(name, sizeof name, "\"%s\"", file);
      bool want = choices[c] & (1u << k);
      assert_int_equal(exists(in_dir(file)), want);
      snprintf(file, sizeof file, "%s.manifest.json", prefix);
      const char *m = slurp(in_dir(file));
      assert_int_equal(strstr(m, name) != NULL, want);
      n += want;
    }
    assert_int_equal(check.files, n);
  }
  /* What the result cannot give: nothing written, the file named. */
  vr_error err = {0};
  vr_film_options fo = {.outputs = VR_FILM_SENSORS};
  o.r.nreadings = 0;
  assert_int_equal(vr_film_write_with(&o.r, in_dir("none"), &fo, &err), VR_E_ARG);
  assert_contains(err.message, "sensor table");
  o.r.nreadings = 2;
  o.r.width = o.r.height = 0;
  fo.outputs = VR_FILM_PNG | VR_FILM_SENSORS;
  assert_int_equal(vr_film_write_with(&o.r, in_dir("none"), &fo, &err), VR_E_ARG);
  assert_contains(err.message, "PNG");
  o.r.width = W, o.r.height = H, o.r.spectral = NULL;
  fo.outputs = VR_FILM_SPECTRAL;
  assert_int_equal(vr_film_write_with(&o.r, in_dir("none"), &fo, &err), VR_E_ARG);
  assert_contains(err.message, "no spectral bins");
  fo.outputs = 1u << 7;
  assert_int_equal(vr_film_write_with(&o.r, in_dir("none"), &fo, &err), VR_E_ARG);
  assert_false(exists(in_dir("none.manifest.json")));
  assert_false(exists(in_dir("none.sensors.csv")));
}

/* A killed run's staging folder (its process gone) is removed; a live
 * process's is kept. */
static void stale_staging_is_removed(void **state) {
  (void)state;
  pid_t child = fork();
  assert_true(child >= 0);
  if (child == 0) _exit(0);
  assert_int_equal(waitpid(child, NULL, 0), child);
  char dead[64], live[64], file[128];
  snprintf(dead, sizeof dead, "st.partial.%ld", (long)child);
  snprintf(live, sizeof live, "st.partial.%ld", (long)getppid());
  assert_int_equal(mkdir(in_dir(dead), 0755), 0);
  assert_int_equal(mkdir(in_dir(live), 0755), 0);
  snprintf(file, sizeof file, "%s/st.png", dead);
  write_file(in_dir(file), "half", 4);
  snprintf(file, sizeof file, "stx.json.partial.%ld", (long)child);
  write_file(in_dir(file), "half", 4); /* another name's: not ours to touch */
  char removed[1024];
  assert_int_equal(vr_film_clean_stale(in_dir("st"), removed, sizeof removed), 1);
  assert_contains(removed, dead);
  assert_false(exists(in_dir(dead)));
  assert_true(exists(in_dir(live)));
  assert_true(exists(in_dir(file)));
  assert_int_equal(vr_film_clean_stale(in_dir("stx.json"), NULL, 0), 1);
  assert_false(exists(in_dir(file)));
  rmdir(in_dir(live));
  /* A staging folder named by this process's own id is a previous holder's
   * of the id (ids restart in every container): writing goes on over it. */
  char own[64];
  snprintf(own, sizeof own, "own.partial.%ld", (long)getpid());
  assert_int_equal(mkdir(in_dir(own), 0755), 0);
  snprintf(file, sizeof file, "%s/own.png", own);
  write_file(in_dir(file), "half", 4);
  owned_result o;
  make_result(&o, 100);
  vr_error err = {0};
  assert_int_equal(vr_film_write(&o.r, in_dir("own"), NULL, &err), VR_OK);
  assert_false(exists(in_dir(own)));
  assert_true(exists(in_dir("own.png")));
}

/* --exposure auto: the log-average luminance to mid grey, 18 cd/m2 at EV 0
 * (display 0.18). */
static void auto_exposure(void **state) {
  (void)state;
  owned_result o;
  make_result(&o, 36);
  double ev = 99;
  assert_true(vr_film_auto_exposure(&o.r, &ev));
  assert_near(ev, -1.0, 1e-12);
  /* Half at 4, half at 16 cd/m2: log average 8; black pixels do not count. */
  for (int p = 0; p < W * H; p++)
    for (int c = 0; c < 3; c++) o.xyz[3 * p + c] *= (p % 2 ? 4.0 : 16.0) / 36.0;
  assert_true(vr_film_auto_exposure(&o.r, &ev));
  assert_near(ev, log2(18.0 / 8.0), 1e-12);
  o.xyz[1] = 0, o.xyz[4] = 0; /* pixels 0 (16) and 1 (4) black */
  assert_true(vr_film_auto_exposure(&o.r, &ev));
  assert_near(ev, log2(18.0 / 8.0), 1e-12);
  for (int k = 0; k < W * H * 3; k++) o.xyz[k] = 0;
  ev = 7;
  assert_false(vr_film_auto_exposure(&o.r, &ev));
  assert_near(ev, 7, 0);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(png_white_ev0_is_255),
      cmocka_unit_test(falsecolour_map),
      cmocka_unit_test(png_ev_minus_one_is_half),
      cmocka_unit_test(reinhard_maps_100_cd_to_half),
      cmocka_unit_test(filmic_follows_the_aces_fit),
      cmocka_unit_test(exr_holds_linear_srgb_in_cd_m2),
      cmocka_unit_test(spectral_exr_has_bins_and_rgb),
      cmocka_unit_test(sensor_table_has_one_row_per_point),
      cmocka_unit_test(stats_json_parses_and_has_the_keys),
      cmocka_unit_test(nan_pixel_writes_nothing),
      cmocka_unit_test(failed_output_removes_the_others),
      cmocka_unit_test(manifest_and_verify),
      cmocka_unit_test(outputs_choose_the_files),
      cmocka_unit_test(stale_staging_is_removed),
      cmocka_unit_test(auto_exposure),
  };
  return cmocka_run_group_tests(tests, make_test_dir, remove_test_dir);
}
