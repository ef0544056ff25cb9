/* The ColorChecker shim of vr/chart.h: detection with OpenCV's mcc module on
 * an 8-bit display copy of the photo, and patch read-out from the photo's own
 * values through a homography of the chart layout.  mcc's own patch means
 * (CChecker::getChartsRGB) are not used: they come from the 8-bit copy.
 * mcc 4.6 exposes only the chart's outline (getBox), not the patch polygons,
 * so both entry points place the patches the same way, from a four-corner
 * outline and the layout documented in vr/chart.h.  Nothing thrown in here
 * reaches the C caller. */
#include <cmath>
#include <cstring>
#include <exception>
#include <new>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/mcc.hpp>

#include "vr/image.h"
#include "vr/chart.h"
#include "vr/colorchecker.h"
#include "vr/colour.h"

namespace {

/* mcc's chart model, in its units: the card outline that getBox() returns
 * is 16.75 x 11.25; patches are 2.5 wide at a pitch of 2.75, starting 0.25
 * from the outline (opencv_contrib modules/mcc/src/checker_model.cpp). */
constexpr double kBoxW = 16.75, kBoxH = 11.25;
constexpr double kPatch = 2.5, kPitch = 2.75, kMargin = 0.25;
constexpr int kCols = 6; /* 4 rows of 6 */

vr_status fail_exception(vr_error *err, const char *what) {
  try {
    throw;
  } catch (const std::bad_alloc &) {
    return vr_error_set(err, VR_E_NOMEM, "%s: out of memory", what);
  } catch (const cv::Exception &e) {
    return vr_error_set(err, VR_E_NUMERIC, "%s: OpenCV: %s", what, e.err.c_str());
  } catch (const std::exception &e) {
    return vr_error_set(err, VR_E_NUMERIC, "%s: %s", what, e.what());
  } catch (...) {
    return vr_error_set(err, VR_E_NUMERIC, "%s: unknown C++ exception", what);
  }
}

/* The perspective map taking src[k] to dst[k] (k = 0..3), in double
 * precision (cv::getPerspectiveTransform takes only float points): h33 = 1
 * and the eight other entries from the eight linear equations. */
bool homography(const double src[4][2], const double dst[4][2], cv::Matx33d &h) {
  cv::Matx<double, 8, 8> a;
  cv::Vec<double, 8> b;
  for (int k = 0; k < 4; ++k) {
    const double x = src[k][0], y = src[k][1], u = dst[k][0], v = dst[k][1];
    const double ru[8] = {x, y, 1, 0, 0, 0, -x * u, -y * u};
    const double rv[8] = {0, 0, 0, x, y, 1, -x * v, -y * v};
    for (int j = 0; j < 8; ++j) {
      a(2 * k, j) = ru[j];
      a(2 * k + 1, j) = rv[j];
    }
    b[2 * k] = u;
    b[2 * k + 1] = v;
  }
  cv::Vec<double, 8> m;
  if (!cv::solve(a, b, m, cv::DECOMP_LU)) return false;
  h = cv::Matx33d(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], 1.0);
  return true;
}

cv::Point2d apply(const cv::Matx33d &h, double x, double y) {
  const cv::Vec3d p = h * cv::Vec3d(x, y, 1.0);
  return {p[0] / p[2], p[1] / p[2]};
}

/* Reads the 24 patches given the homography from mcc model units to image
 * coordinates (pixel centres at +0.5). */
vr_status sample_chart(const vr_image *img, const cv::Matx33d &h, double fraction, vr_chart *out,
                       vr_error *err) {
  std::memset(out, 0, sizeof *out);
  const double area[4][2] = {{kMargin, kMargin},
                             {kBoxW - kMargin, kMargin},
                             {kBoxW - kMargin, kBoxH - kMargin},
                             {kMargin, kBoxH - kMargin}};
  for (int k = 0; k < 4; ++k) {
    const cv::Point2d p = apply(h, area[k][0], area[k][1]);
    out->corners[k][0] = p.x;
    out->corners[k][1] = p.y;
  }
  const double half = 0.5 * fraction * kPatch;
  for (int i = 0; i < VR_CHART_PATCHES; ++i) {
    const double cx = kMargin + (i % kCols) * kPitch + 0.5 * kPatch;
    const double cy = kMargin + (i / kCols) * kPitch + 0.5 * kPatch;
    const double sq[4][2] = {{cx - half, cy - half},
                             {cx + half, cy - half},
                             {cx + half, cy + half},
                             {cx - half, cy + half}};
    double quad[4][2];
    for (int k = 0; k < 4; ++k) {
      const cv::Point2d p = apply(h, sq[k][0], sq[k][1]);
      quad[k][0] = p.x;
      quad[k][1] = p.y;
      if (!(p.x >= 0 && p.y >= 0 && p.x <= img->width && p.y <= img->height))
        return vr_error_set(err, VR_E_RANGE,
                            "patch %d (%s): its sampled square reaches (%.1f, %.1f), outside "
                            "the %d x %d image", i + 1, vr_colorchecker_name((size_t)i), p.x,
                            p.y, img->width, img->height);
    }
    const cv::Point2d c = apply(h, cx, cy);
    out->center[i][0] = c.x;
    out->center[i][1] = c.y;
    vr_region_stats s;
    vr_status st = vr_region_quad_stats(img, quad, &s, err);
    if (st != VR_OK) return st;
    if (s.pixels == 0)
      return vr_error_set(err, VR_E_RANGE,
                          "patch %d (%s): its sampled square around (%.1f, %.1f) holds no "
                          "pixel centre; the chart is too small in the image", i + 1,
                          vr_colorchecker_name((size_t)i), c.x, c.y);
    out->pixels[i] = s.pixels;
    out->max[i] = s.max;
    for (int k = 0; k < 3; ++k) {
      out->rgb[i][k] = s.mean[k];
      out->sd[i][k] = s.sd[k];
    }
  }
  return VR_OK;
}

/* 8-bit BGR copy for mcc: clamped, sRGB-encoded when linear (through a
 * 16-bit table: 72 million pow() calls for a 24-megapixel photo otherwise). */
cv::Mat display_copy(const vr_image *img, bool linear) {
  std::vector<unsigned char> lut(65536);
  for (int k = 0; k < 65536; ++k) {
    const double v = k / 65535.0;
    lut[(size_t)k] = (unsigned char)std::lround(255.0 * (linear ? vr_srgb_encode(v) : v));
  }
  cv::Mat bgr(img->height, img->width, CV_8UC3);
  if (!img->data) { /* codes (vr_image_read_codes): a byte per code, as below */
    const bool eight = img->bit_depth == 8;
    std::vector<unsigned char> byte(eight ? 256 : 65536);
    for (size_t k = 0; k < byte.size(); ++k) {
      const float v = (float)k / (eight ? 255.0f : 65535.0f); /* the decoder's value */
      byte[k] = lut[(size_t)std::lround(v * 65535.0f)];
    }
    for (int y = 0; y < img->height; ++y) {
      const size_t at = (size_t)y * (size_t)img->width * 3;
      unsigned char *dst = bgr.ptr<unsigned char>(y);
      for (int x = 0; x < img->width; ++x, dst += 3)
        for (int c = 0; c < 3; ++c) {
          const size_t i = at + 3 * (size_t)x + (size_t)(2 - c);
          dst[c] = byte[eight ? static_cast<const unsigned char *>(img->codes)[i]
                              : static_cast<const unsigned short *>(img->codes)[i]];
        }
    }
    return bgr;
  }
  for (int y = 0; y < img->height; ++y) {
    const float *src = img->data + (size_t)y * (size_t)img->width * 3;
    unsigned char *dst = bgr.ptr<unsigned char>(y);
    for (int x = 0; x < img->width; ++x, src += 3, dst += 3)
      for (int c = 0; c < 3; ++c) {
        const float v = src[2 - c];
        const float t = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; /* NaN -> 0 */
        dst[c] = lut[(size_t)std::lround(t * 65535.0f)];
      }
  }
  return bgr;
}

}  // namespace

extern "C" vr_status vr_chart_detect(const vr_image *img, bool linear, vr_chart *out,
                                     vr_error *err) {
  if (!out) return vr_error_set(err, VR_E_ARG, "vr_chart_detect: out is NULL");
  std::memset(out, 0, sizeof *out);
  vr_status st = vr_image_check_any(img, "vr_chart_detect", err);
  if (st != VR_OK) return st;
  try {
    const cv::Mat bgr = display_copy(img, linear);
    cv::Ptr<cv::mcc::CCheckerDetector> detector = cv::mcc::CCheckerDetector::create();
    cv::Ptr<cv::mcc::CChecker> checker;
    if (detector->process(bgr, cv::mcc::MCC24, 1)) checker = detector->getBestColorChecker();
    if (!checker)
      return vr_error_set(err, VR_E_NOT_FOUND,
                          "no ColorChecker Classic found in the %d x %d image (OpenCV mcc): "
                          "the whole chart must be visible, sharp and not clipped%s; otherwise "
                          "give its corners to vr_chart_from_grid", img->width, img->height,
                          linear ? "" : " (a linear image needs linear = true)");
    const std::vector<cv::Point2f> box = checker->getBox();
    if (box.size() != 4)
      return vr_error_set(err, VR_E_NUMERIC, "OpenCV mcc returned a chart outline of %zu points",
                          box.size());
    const double model[4][2] = {{0, 0}, {kBoxW, 0}, {kBoxW, kBoxH}, {0, kBoxH}};
    double image[4][2];
    /* OpenCV puts pixel centres on integers, vr/image.h at +0.5. */
    for (int k = 0; k < 4; ++k) {
      image[k][0] = box[(size_t)k].x + 0.5;
      image[k][1] = box[(size_t)k].y + 0.5;
    }
    cv::Matx33d h;
    if (!homography(model, image, h))
      return vr_error_set(err, VR_E_NUMERIC, "OpenCV mcc returned a degenerate chart outline");
    st = sample_chart(img, h, VR_CHART_DEFAULT_FRACTION, out, err);
    if (st != VR_OK) vr_error_prefix(err, "chart found by OpenCV mcc: ");
    return st;
  } catch (...) {
    return fail_exception(err, "vr_chart_detect");
  }
}

extern "C" vr_status vr_chart_from_grid(const vr_image *img, const double corners[4][2],
                                        double fraction, vr_chart *out, vr_error *err) {
  if (!out) return vr_error_set(err, VR_E_ARG, "vr_chart_from_grid: out is NULL");
  std::memset(out, 0, sizeof *out);
  vr_status st = vr_image_check_any(img, "vr_chart_from_grid", err);
  if (st != VR_OK) return st;
  if (!corners) return vr_error_set(err, VR_E_ARG, "vr_chart_from_grid: corners is NULL");
  if (fraction == 0.0) fraction = VR_CHART_DEFAULT_FRACTION;
  if (!(fraction > 0.0 && fraction <= 1.0))
    return vr_error_set(err, VR_E_ARG, "patch fraction %g: must be in (0, 1]", fraction);
  /* Convex and clockwise on screen (y down): patch 1, 6, 24, 19 in turn.
   * Anticlockwise would be a mirrored chart, which a camera cannot see. */
  for (int k = 0; k < 4; ++k) {
    if (!std::isfinite(corners[k][0]) || !std::isfinite(corners[k][1]))
      return vr_error_set(err, VR_E_ARG, "chart corner %d is not a finite number", k + 1);
    const double *a = corners[k], *b = corners[(k + 1) % 4], *c = corners[(k + 2) % 4];
    const double turn = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
    if (!(turn > 0))
      return vr_error_set(err, VR_E_ARG,
                          "chart corners (%.1f, %.1f), (%.1f, %.1f), (%.1f, %.1f), (%.1f, %.1f) "
                          "do not turn clockwise on screen at corner %d: give the outer corners "
                          "of patches 1, 6, 24 and 19 in that order",
                          corners[0][0], corners[0][1], corners[1][0], corners[1][1],
                          corners[2][0], corners[2][1], corners[3][0], corners[3][1],
                          (k + 1) % 4 + 1);
  }
  try {
    const double model[4][2] = {{kMargin, kMargin},
                                {kBoxW - kMargin, kMargin},
                                {kBoxW - kMargin, kBoxH - kMargin},
                                {kMargin, kBoxH - kMargin}};
    cv::Matx33d h;
    if (!homography(model, corners, h))
      return vr_error_set(err, VR_E_ARG, "chart corners: no perspective maps the chart onto them");
    return sample_chart(img, h, fraction, out, err);
  } catch (...) {
    return fail_exception(err, "vr_chart_from_grid");
  }
}
