/* The published tables compiled in from core/data by cmake/VrEmbed.cmake.
 * Each is a flat row-major array of rows x cols doubles, first column nm. */
#ifndef VR_EMBEDDED_H
#define VR_EMBEDDED_H

#define VR_DECLARE_TABLE(name)       \
  extern const double name[];        \
  extern const unsigned name##_rows; \
  extern const unsigned name##_cols;

VR_DECLARE_TABLE(vr_data_cie1931_2deg)
VR_DECLARE_TABLE(vr_data_cie1964_10deg)
VR_DECLARE_TABLE(vr_data_cie_d_vectors)
VR_DECLARE_TABLE(vr_data_cie_d65)
VR_DECLARE_TABLE(vr_data_cie_d50)
VR_DECLARE_TABLE(vr_data_cie_f_series)
VR_DECLARE_TABLE(vr_data_cie_led_series)
VR_DECLARE_TABLE(vr_data_colorchecker_babelcolor)
VR_DECLARE_TABLE(vr_data_cie_tcs)

#endif
