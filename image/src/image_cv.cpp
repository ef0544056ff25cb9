/* The OpenCV side of vr/image.h: PNG, TIFF and JPEG decoded from and encoded
 * to memory with cv::imdecode / cv::imencode.  image.c does the file I/O, so
 * OpenCV never opens a path and every message can name it.  Nothing thrown
 * in here (cv::Exception, std::bad_alloc, ...) reaches the C caller.
 *
 * Built as the module vr-image-cv.so, which vr_image loads with dlopen when
 * a PNG, TIFF or JPEG is first read or written (image_cv_module.h,
 * image_codecs.c); what it needs of vr_image and vr_core comes through the
 * host table of each call. */
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <limits>
#include <new>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "image_cv_module.h"

namespace {

/* Turns whatever escaped into a status naming the file; called from every
 * catch (...) of this file. */
vr_status fail_exception(const vr_image_cv_host *host, vr_error *err, const char *path,
                         const char *what, vr_status status) {
  try {
    throw;
  } catch (const std::bad_alloc &) {
    return host->error_at(err, VR_E_NOMEM, path, 0, 0, "%s: out of memory", what);
  } catch (const cv::Exception &e) {
    return host->error_at(err, status, path, 0, 0, "%s: OpenCV: %s", what, e.err.c_str());
  } catch (const std::exception &e) {
    return host->error_at(err, status, path, 0, 0, "%s: %s", what, e.what());
  } catch (...) {
    return host->error_at(err, status, path, 0, 0, "%s: unknown C++ exception", what);
  }
}

const char *depth_name(int depth) {
  switch (depth) {
    case CV_8S: return "signed 8-bit";
    case CV_16S: return "signed 16-bit";
    case CV_32S: return "32-bit integer";
    case CV_64F: return "64-bit float";
    case CV_16F: return "16-bit float";
    default: return "unknown";
  }
}

/* OpenCV's own allocator for the decoded picture, but with its memory from
 * vr_image_pixels_alloc: libpng writes tens of megabytes into it once, and
 * in 4 KiB pages each page is a fault (see image.c).  Modelled on OpenCV's
 * StdMatAllocator (modules/core/src/matrix.cpp). */
class PixelsAllocator final : public cv::MatAllocator {
 public:
  explicit PixelsAllocator(const vr_image_cv_host *host) : host_(host) {}
  cv::UMatData *allocate(int dims, const int *sizes, int type, void *data0, size_t *step,
                         cv::AccessFlag, cv::UMatUsageFlags) const override {
    size_t total = CV_ELEM_SIZE(type);
    for (int i = dims - 1; i >= 0; i--) {
      if (step) {
        if (data0 && step[i] != cv::Mat::AUTO_STEP) {
          CV_Assert(total <= step[i]);
          total = step[i];
        } else {
          step[i] = total;
        }
      }
      total *= (size_t)sizes[i];
    }
    void *data = data0 ? data0 : host_->pixels_alloc(total);
    if (!data) throw std::bad_alloc();
    cv::UMatData *u = new cv::UMatData(this);
    u->data = u->origdata = static_cast<uchar *>(data);
    u->size = total;
    if (data0) u->flags |= cv::UMatData::USER_ALLOCATED;
    return u;
  }
  bool allocate(cv::UMatData *u, cv::AccessFlag, cv::UMatUsageFlags) const override {
    return u != nullptr;
  }
  void deallocate(cv::UMatData *u) const override {
    if (!u) return;
    if (!(u->flags & cv::UMatData::USER_ALLOCATED)) std::free(u->origdata);
    delete u;
  }

 private:
  const vr_image_cv_host *host_;
};

/* Copies one decoded row (any of 1-4 channels, BGR order) into RGB floats
 * and returns how many of its pixels have an alpha below top (opaque is the
 * largest code, or 1.0 for float samples; a NaN alpha is not opaque either).
 * A true division, not a product with 1/top: code k becomes exactly the
 * float nearest k/top, the value a caller computes for the same code. */
template <typename T>
long convert_row(const T *src, int width, int nc, float top, float *dst) {
  long below = 0;
  for (int x = 0; x < width; ++x, src += nc, dst += 3) {
    if (nc <= 2) { /* grey, or grey + alpha */
      dst[0] = dst[1] = dst[2] = (float)src[0] / top;
    } else {       /* BGR or BGRA */
      dst[0] = (float)src[2] / top;
      dst[1] = (float)src[1] / top;
      dst[2] = (float)src[0] / top;
    }
    if ((nc == 2 || nc == 4) && !((float)src[nc - 1] >= top)) ++below;
  }
  return below;
}

/* The alpha of one decoded row (the last of 2 or 4 channels) over top. */
template <typename T>
void alpha_row(const T *src, int width, int nc, float top, float *dst) {
  for (int x = 0; x < width; ++x, src += nc) dst[x] = (float)src[nc - 1] / top;
}

/* Copies one decoded row of 8- or 16-bit codes (1-4 channels, BGR order)
 * into RGB codes and returns how many of its pixels have an alpha below
 * top, as convert_row does. */
template <typename T>
long codes_row(const T *src, int width, int nc, T top, T *dst) {
  long below = 0;
  if (nc == 3) { /* the common case, in a loop of its own */
    for (int x = 0; x < width; ++x, src += 3, dst += 3) {
      const T b = src[0], g = src[1], r = src[2];
      dst[0] = r;
      dst[1] = g;
      dst[2] = b;
    }
    return 0;
  }
  for (int x = 0; x < width; ++x, src += nc, dst += 3) {
    if (nc <= 2) {
      dst[0] = dst[1] = dst[2] = src[0];
    } else {
      dst[0] = src[2];
      dst[1] = src[1];
      dst[2] = src[0];
    }
    if ((nc == 2 || nc == 4) && src[nc - 1] < top) ++below;
  }
  return below;
}

/* BGR to RGB in place, n pixels. */
template <typename T>
void swap_red_blue(T *p, size_t n) {
  for (size_t i = 0; i < n; ++i, p += 3) {
    const T b = p[0];
    p[0] = p[2];
    p[2] = b;
  }
}

/* Clamp to [0,1] and round to nearest: the one quantisation of every
 * integer file this project writes. */
template <typename T>
T quantise(float v, double top) {
  if (!(v > 0.0f)) return 0;
  if (v >= 1.0f) return (T)top;
  return (T)std::floor((double)v * top + 0.5);
}

template <typename T>
void fill_bgr(const vr_image *img, cv::Mat &m, double top) {
  for (int y = 0; y < img->height; ++y) {
    const float *src = img->data + (size_t)y * (size_t)img->width * 3;
    T *dst = m.ptr<T>(y);
    for (int x = 0; x < img->width; ++x, src += 3, dst += 3) {
      dst[0] = quantise<T>(src[2], top);
      dst[1] = quantise<T>(src[1], top);
      dst[2] = quantise<T>(src[0], top);
    }
  }
}

vr_status decode(const vr_image_cv_host *host, const unsigned char *buf, size_t len,
                 const char *path, const char *format, int keep, vr_image *out,
                 vr_error *err) {
  std::memset(out, 0, sizeof *out);
  const bool keep_codes = keep & 1, keep_alpha = keep & 2; /* VR_IMAGE_KEEP_* */
  if (len > (size_t)std::numeric_limits<int>::max())
    return host->error_at(err, VR_E_PARSE, path, 0, 0, "%s file of %zu bytes is too large (2 GiB "
                       "at most)", format, len);
  try {
    const cv::Mat raw(1, (int)len, CV_8U, const_cast<unsigned char *>(buf));
    /* IMREAD_UNCHANGED: keep 16 bits and the channel count, ignore EXIF
     * orientation (pixels as stored). */
    PixelsAllocator pixels(host); /* declared before m: outlives it */
    cv::Mat m;
    m.allocator = &pixels;
    cv::imdecode(raw, cv::IMREAD_UNCHANGED, &m);
    if (m.empty())
      return host->error_at(err, VR_E_PARSE, path, 0, 0,
                         "cannot decode this %s file (truncated, corrupt, or a variant "
                         "OpenCV does not read)", format);
    const int depth = m.depth(), nc = m.channels();
    if (depth != CV_8U && depth != CV_16U && depth != CV_32F)
      return host->error_at(err, VR_E_PARSE, path, 0, 0,
                         "%s with %s samples is not supported (8- or 16-bit integer or "
                         "32-bit float only)", format, depth_name(depth));
    if (nc < 1 || nc > 4)
      return host->error_at(err, VR_E_PARSE, path, 0, 0, "%s with %d channels is not supported",
                         format, nc);
    /* OpenCV hands a PNG's alpha (grey + alpha included, and a tRNS chunk
     * of an RGB or palette PNG) and a TIFF's extra sample as the last of 2
     * or 4 channels; JPEG never has one. */
    long below = 0;
    if (keep_codes && depth != CV_32F && nc == 3 && m.isContinuous() && m.u &&
        m.u->currAllocator == &pixels && m.u->refcount == 1 && m.data == m.u->origdata) {
      /* RGB, the usual photo: the decoded memory itself becomes the codes,
       * blue and red swapped in place, instead of a copy of it. */
      const size_t n = (size_t)m.cols * (size_t)m.rows;
      if (depth == CV_8U)
        swap_red_blue(m.data, n);
      else
        swap_red_blue(reinterpret_cast<unsigned short *>(m.data), n);
      out->codes = m.u->origdata;
      m.u->origdata = nullptr; /* ours now: the allocator frees nothing */
      out->width = m.cols;
      out->height = m.rows;
      out->channels = 3;
      out->bit_depth = depth == CV_8U ? 8 : 16;
      return VR_OK;
    }
    if (keep_codes && depth != CV_32F) {
      const size_t size = depth == CV_8U ? 1 : 2;
      const size_t n = (size_t)m.cols * (size_t)m.rows * 3;
      out->codes = host->pixels_alloc(n * size);
      if (!out->codes)
        return host->error_at(err, VR_E_NOMEM, path, 0, 0, "out of memory for a %d x %d image",
                           m.cols, m.rows);
      out->width = m.cols;
      out->height = m.rows;
      out->channels = 3;
      for (int y = 0; y < m.rows; ++y) {
        const size_t at = (size_t)y * (size_t)m.cols * 3;
        if (depth == CV_8U)
          below += codes_row(m.ptr<unsigned char>(y), m.cols, nc, (unsigned char)255,
                             static_cast<unsigned char *>(out->codes) + at);
        else
          below += codes_row(m.ptr<unsigned short>(y), m.cols, nc, (unsigned short)65535,
                             static_cast<unsigned short *>(out->codes) + at);
      }
      out->bit_depth = depth == CV_8U ? 8 : 16;
      out->alpha = nc == 2 || nc == 4;
      out->transparent = below;
      return VR_OK;
    }
    vr_status st = host->image_alloc(out, m.cols, m.rows, err);
    if (st != VR_OK) {
      host->error_prefix(err, "%s: ", path);
      return st;
    }
    for (int y = 0; y < m.rows; ++y) {
      float *dst = out->data + (size_t)y * (size_t)m.cols * 3;
      if (depth == CV_8U)
        below += convert_row(m.ptr<unsigned char>(y), m.cols, nc, 255.0f, dst);
      else if (depth == CV_16U)
        below += convert_row(m.ptr<unsigned short>(y), m.cols, nc, 65535.0f, dst);
      else
        below += convert_row(m.ptr<float>(y), m.cols, nc, 1.0f, dst);
    }
    out->bit_depth = depth == CV_8U ? 8 : depth == CV_16U ? 16 : 32;
    out->alpha = nc == 2 || nc == 4;
    out->transparent = below;
    if (keep_alpha && out->alpha) {
      out->alpha_data = static_cast<float *>(
          host->pixels_alloc((size_t)m.cols * (size_t)m.rows * sizeof(float)));
      if (!out->alpha_data) {
        host->image_free(out);
        return host->error_at(err, VR_E_NOMEM, path, 0, 0, "out of memory for the alpha channel");
      }
      for (int y = 0; y < m.rows; ++y) {
        float *dst = out->alpha_data + (size_t)y * (size_t)m.cols;
        if (depth == CV_8U)
          alpha_row(m.ptr<unsigned char>(y), m.cols, nc, 255.0f, dst);
        else if (depth == CV_16U)
          alpha_row(m.ptr<unsigned short>(y), m.cols, nc, 65535.0f, dst);
        else
          alpha_row(m.ptr<float>(y), m.cols, nc, 1.0f, dst);
      }
    }
    return VR_OK;
  } catch (...) {
    host->image_free(out);
    return fail_exception(host, err, path, "decoding", VR_E_PARSE);
  }
}

vr_status encode(const vr_image_cv_host *host, const vr_image *img, const char *path,
                 const char *ext, int bits, unsigned char **bytes, size_t *len, vr_error *err) {
  *bytes = nullptr;
  *len = 0;
  try {
    cv::Mat m(img->height, img->width, bits == 16 ? CV_16UC3 : CV_8UC3);
    if (bits == 16)
      fill_bgr<unsigned short>(img, m, 65535.0);
    else
      fill_bgr<unsigned char>(img, m, 255.0);
    std::vector<int> params;
    if (std::strcmp(ext, ".jpg") == 0) params = {cv::IMWRITE_JPEG_QUALITY, 95};
    std::vector<unsigned char> encoded;
    if (!cv::imencode(ext, m, encoded, params) || encoded.empty())
      return host->error_at(err, VR_E_IO, path, 0, 0, "OpenCV could not encode a %d-bit %s image",
                         bits, ext + 1);
    *bytes = static_cast<unsigned char *>(std::malloc(encoded.size()));
    if (!*bytes) return host->error_at(err, VR_E_NOMEM, path, 0, 0, "out of memory");
    std::memcpy(*bytes, encoded.data(), encoded.size());
    *len = encoded.size();
    return VR_OK;
  } catch (...) {
    std::free(*bytes);
    *bytes = nullptr;
    return fail_exception(host, err, path, "encoding", VR_E_IO);
  }
}

}  // namespace

/* The module's one exported symbol (the build hides every other). */
extern "C" __attribute__((visibility("default"))) const vr_image_cv_codecs *
vr_image_cv_module_codecs(void) {
  static const vr_image_cv_codecs table = {VR_IMAGE_CV_ABI, sizeof(vr_image), sizeof(vr_error),
                                           decode, encode};
  return &table;
}
