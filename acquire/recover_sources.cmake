# Sources of the spectral recovery (camera models, Matrix R, bounded and
# regularised methods).  Included by acquire/CMakeLists.txt, which adds them
# to vr_acquire (linked PUBLIC to vr_core and PkgConfig::LAPACKE, with
# acquire/include public).  Absolute paths, so the list works wherever the
# file is included from.
set(VR_RECOVER_SOURCES
  ${CMAKE_CURRENT_LIST_DIR}/src/camera.c
  ${CMAKE_CURRENT_LIST_DIR}/src/recover_linalg.c
  ${CMAKE_CURRENT_LIST_DIR}/src/recover.c
  ${CMAKE_CURRENT_LIST_DIR}/src/recover_qp.c
  ${CMAKE_CURRENT_LIST_DIR}/src/recover_bounded.c
  ${CMAKE_CURRENT_LIST_DIR}/src/recover_regularised.c
  ${CMAKE_CURRENT_LIST_DIR}/src/recover_pixel.c
)
