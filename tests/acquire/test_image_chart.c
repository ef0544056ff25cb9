/* ColorChecker read-out on synthetic charts: OpenCV mcc does find a cleanly
 * drawn chart (also upside down, also as linear values), the patch means are
 * the drawn colours, the four-corner path gives the same numbers exactly,
 * and images without a chart or with bad corners fail cleanly. */
#include "image_test_util.h"
#include "vr/chart.h"
#include "vr/colour.h"

/* sRGB (8-bit) of the 24 patches, chart order, as tabulated from X-Rite's
 * data in the Wikipedia article "ColorChecker"; they only need to look like
 * the chart to mcc, the tests compare with what was drawn. */
static const int k_srgb8[24][3] = {
    {115, 82, 68},   {194, 150, 130}, {98, 122, 157},  {87, 108, 67},   {133, 128, 177},
    {103, 189, 170}, {214, 126, 44},  {80, 91, 166},   {193, 90, 99},   {94, 60, 108},
    {157, 188, 64},  {224, 163, 46},  {56, 61, 150},   {70, 148, 73},   {175, 54, 60},
    {231, 199, 31},  {187, 86, 149},  {8, 133, 161},   {243, 243, 242}, {200, 200, 200},
    {160, 160, 160}, {122, 122, 121}, {85, 85, 85},    {52, 52, 52}};

/* Geometry of the drawing: 600 x 400, 80-pixel patches, 8-pixel gaps and
 * card margin (a tenth of a patch, as on the real chart), card centred.
 * Card from (32, 20) to (568, 380); patch area from (40, 28) to (560, 372). */
enum { W = 600, H = 400, P = 80, G = 8, X0 = 32, Y0 = 20 };

static void expected_value(int patch, int linear, double rgb[3]) {
  for (int c = 0; c < 3; c++) {
    float v = (float)k_srgb8[patch][c] / 255.0f;
    rgb[c] = linear ? (float)vr_srgb_decode(v) : v;
  }
}

/* Draws the chart; rotated: turned by 180 degrees (dark skin bottom right). */
static void draw_chart(vr_image *img, int rotated, int linear) {
  vr_error err = {0};
  assert_int_equal(vr_image_alloc(img, W, H, &err), VR_OK);
  const float grey = linear ? (float)vr_srgb_decode(128 / 255.0) : 128 / 255.0f;
  const float card = linear ? (float)vr_srgb_decode(20 / 255.0) : 20 / 255.0f;
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      int in_card = x >= X0 && x < W - X0 && y >= Y0 && y < H - Y0;
      for (int c = 0; c < 3; c++) px(img, x, y)[c] = in_card ? card : grey;
    }
  for (int k = 0; k < 24; k++) {
    int r = k / 6, col = k % 6;
    if (rotated) {
      r = 3 - r;
      col = 5 - col;
    }
    double v[3];
    expected_value(k, linear, v);
    for (int y = Y0 + G + r * (P + G); y < Y0 + G + r * (P + G) + P; y++)
      for (int x = X0 + G + col * (P + G); x < X0 + G + col * (P + G) + P; x++)
        for (int c = 0; c < 3; c++) px(img, x, y)[c] = (float)v[c];
  }
}

/* Centre of patch k as drawn (pixel edges at integers). */
static void drawn_centre(int k, int rotated, double xy[2]) {
  int r = k / 6, col = k % 6;
  if (rotated) {
    r = 3 - r;
    col = 5 - col;
  }
  xy[0] = X0 + G + col * (P + G) + P / 2.0;
  xy[1] = Y0 + G + r * (P + G) + P / 2.0;
}

static void check_chart(const vr_chart *ch, int rotated, int linear, double tol, double ctr_tol) {
  for (int k = 0; k < 24; k++) {
    double want[3], xy[2];
    expected_value(k, linear, want);
    drawn_centre(k, rotated, xy);
    for (int c = 0; c < 3; c++) assert_near(ch->rgb[k][c], want[c], tol);
    assert_near(ch->center[k][0], xy[0], ctr_tol);
    assert_near(ch->center[k][1], xy[1], ctr_tol);
    assert_true(ch->pixels[k] > 900); /* about (0.5 * 80)^2 = 1600 */
    assert_near(ch->max[k], fmax(want[0], fmax(want[1], want[2])), tol);
  }
}

/* Four corners, given by hand: every number follows from the drawing. */
static void chart_from_grid_on_a_drawn_chart(void **state) {
  (void)state;
  vr_image img;
  vr_chart ch;
  vr_error err = {0};
  draw_chart(&img, 0, 0);
  const double corners[4][2] = {{40, 28}, {560, 28}, {560, 372}, {40, 372}};
  assert_int_equal(vr_chart_from_grid(&img, corners, 0, &ch, &err), VR_OK);
  check_chart(&ch, 0, 0, 0.0, 1e-9);
  for (int k = 0; k < 24; k++) {
    assert_int_equal(ch.pixels[k], 40 * 40); /* a 40-pixel square, half the side */
    for (int c = 0; c < 3; c++) assert_near(ch.sd[k][c], 0, 0);
  }
  /* The whole patch (fraction 1) is still inside it: 80 x 80 pixels, same means. */
  assert_int_equal(vr_chart_from_grid(&img, corners, 1.0, &ch, &err), VR_OK);
  check_chart(&ch, 0, 0, 0.0, 1e-9);
  assert_int_equal(ch.pixels[0], 80 * 80);
  vr_image_free(&img);

  /* Upside down: patch 1's corner is now bottom right. */
  draw_chart(&img, 1, 0);
  const double turned[4][2] = {{560, 372}, {40, 372}, {40, 28}, {560, 28}};
  assert_int_equal(vr_chart_from_grid(&img, turned, 0, &ch, &err), VR_OK);
  check_chart(&ch, 1, 0, 0.0, 1e-9);
  vr_image_free(&img);
}

/* mcc finds the drawn chart; its outline is a few pixels off, which the
 * half-patch sample absorbs: means equal to the drawn colours within 1/255
 * (they come out exact), centres within a tenth of a patch (8 px). */
static void mcc_detects_a_drawn_chart(void **state) {
  (void)state;
  for (int rotated = 0; rotated < 2; rotated++)
    for (int linear = 0; linear < 2; linear++) {
      vr_image img;
      vr_chart ch, again;
      vr_error err = {0};
      draw_chart(&img, rotated, linear);
      vr_status st = vr_chart_detect(&img, linear, &ch, &err);
      if (st != VR_OK) fail_msg("rotated %d linear %d: %s", rotated, linear, err.message);
      check_chart(&ch, rotated, linear, 1.0 / 255, 8.0);
      for (int k = 0; k < 24; k++)
        for (int c = 0; c < 3; c++) assert_near(ch.sd[k][c], 0, 1e-6);
      /* The corners it reports read the same patches through the grid path. */
      assert_int_equal(vr_chart_from_grid(&img, (const double(*)[2])ch.corners, 0, &again, &err),
                       VR_OK);
      for (int k = 0; k < 24; k++)
        for (int c = 0; c < 3; c++) assert_near(again.rgb[k][c], ch.rgb[k][c], 1e-12);
      vr_image_free(&img);
    }
}

static void no_chart_is_not_found(void **state) {
  (void)state;
  vr_image img;
  vr_chart ch;
  vr_error err = {0};
  make_coded_image(&img, W, H, 255); /* a busy pattern of colours */
  assert_int_equal(vr_chart_detect(&img, false, &ch, &err), VR_E_NOT_FOUND);
  assert_contains(err.message, "no ColorChecker Classic found in the 600 x 400 image");
  for (size_t i = 0; i < (size_t)W * H * 3; i++) img.data[i] = 0.5f; /* flat grey */
  assert_int_equal(vr_chart_detect(&img, true, &ch, &err), VR_E_NOT_FOUND);
  vr_image_free(&img);
  make_coded_image(&img, 3, 2, 255); /* tiny */
  assert_int_equal(vr_chart_detect(&img, false, &ch, &err), VR_E_NOT_FOUND);
  vr_image_free(&img);
  assert_int_equal(vr_chart_detect(NULL, false, &ch, &err), VR_E_ARG);
}

static void bad_corners(void **state) {
  (void)state;
  vr_image img;
  vr_chart ch;
  vr_error err = {0};
  draw_chart(&img, 0, 0);
  const double mirrored[4][2] = {{560, 28}, {40, 28}, {40, 372}, {560, 372}};
  assert_int_equal(vr_chart_from_grid(&img, mirrored, 0, &ch, &err), VR_E_ARG);
  assert_contains(err.message, "patches 1, 6, 24 and 19");
  const double crossed[4][2] = {{40, 28}, {560, 372}, {560, 28}, {40, 372}};
  assert_int_equal(vr_chart_from_grid(&img, crossed, 0, &ch, &err), VR_E_ARG);
  const double beyond[4][2] = {{340, 28}, {860, 28}, {860, 372}, {340, 372}};
  assert_int_equal(vr_chart_from_grid(&img, beyond, 0, &ch, &err), VR_E_RANGE);
  assert_contains(err.message, "patch 4 (foliage)");
  assert_contains(err.message, "outside the 600 x 400 image");
  const double tiny[4][2] = {{40, 28}, {43, 28}, {43, 30}, {40, 30}};
  assert_int_equal(vr_chart_from_grid(&img, tiny, 0, &ch, &err), VR_E_RANGE);
  assert_contains(err.message, "no pixel centre");
  const double corners[4][2] = {{40, 28}, {560, 28}, {560, 372}, {40, 372}};
  assert_int_equal(vr_chart_from_grid(&img, corners, 1.5, &ch, &err), VR_E_ARG);
  assert_contains(err.message, "1.5");
  vr_image_free(&img);
}

/* A photo kept as its codes (vr_image_read_codes) gives the chart of the
 * same photo read as floats, number for number: detection (its display
 * copy is made from the codes), the four-corner read-out, and with noise
 * in the drawing so the deviations are not all zero.  8 and 16 bits, the
 * latter also as a linear photo. */
static void chart_from_codes(void **state) {
  (void)state;
  static const struct {
    const char *name;
    int bits, linear;
  } files[] = {{"chart8.png", 8, 0}, {"chart16.png", 16, 0}, {"chart16_linear.png", 16, 1}};
  for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
    vr_image drawn, f, c;
    vr_error err = {0};
    draw_chart(&drawn, 0, files[i].linear);
    for (size_t k = 0; k < (size_t)W * H * 3; k++) /* +-1.5 codes of 8 bits */
      drawn.data[k] = fminf(fmaxf(drawn.data[k] + (float)((k * 2654435761u) % 7) * 0.002f -
                                  0.006f, 0.0f), 1.0f);
    assert_int_equal(vr_image_write_png(in_dir(files[i].name), &drawn, files[i].bits, &err), VR_OK);
    assert_int_equal(vr_image_read(in_dir(files[i].name), &f, &err), VR_OK);
    assert_int_equal(vr_image_read_codes(in_dir(files[i].name), &c, &err), VR_OK);
    assert_null(c.data);
    vr_chart a, b;
    const double corners[4][2] = {{40, 28}, {560, 28}, {560, 372}, {40, 372}};
    assert_int_equal(vr_chart_from_grid(&f, corners, 0, &a, &err), VR_OK);
    assert_int_equal(vr_chart_from_grid(&c, corners, 0, &b, &err), VR_OK);
    assert_memory_equal(&a, &b, sizeof a);
    assert_true(a.sd[0][0] > 0);
    vr_status sa = vr_chart_detect(&f, files[i].linear, &a, &err);
    vr_status sb = vr_chart_detect(&c, files[i].linear, &b, &err);
    assert_int_equal(sb, sa);
    if (sa == VR_OK) assert_memory_equal(&a, &b, sizeof a);
    vr_image_free(&drawn);
    vr_image_free(&f);
    vr_image_free(&c);
    unlink(in_dir(files[i].name));
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(chart_from_grid_on_a_drawn_chart),
      cmocka_unit_test(mcc_detects_a_drawn_chart),
      cmocka_unit_test(no_chart_is_not_found),
      cmocka_unit_test(bad_corners),
      cmocka_unit_test(chart_from_codes),
  };
  return cmocka_run_group_tests(tests, make_test_dir, remove_test_dir);
}

/* OpenCV's imgproc (which mcc calls for its L*a*b* conversion) builds its
 * colour-conversion tables once per process (cv::allocSingleton in
 * color_lab.cpp) and keeps them until exit; LeakSanitizer reports them,
 * the same 9 blocks (4.7 MB) after one detection or after many.  Not a leak
 * of this project: suppressed for this program, with full unwinding on
 * malloc so that the report reaches the OpenCV frame (Debian's OpenCV has no
 * frame pointers).  These hooks are only read by sanitizer runtimes. */
const char *__lsan_default_suppressions(void);
const char *__lsan_default_suppressions(void) { return "leak:cv::hal::cvtBGRtoLab\n"; }
const char *__asan_default_options(void);
const char *__asan_default_options(void) { return "fast_unwind_on_malloc=0"; }
