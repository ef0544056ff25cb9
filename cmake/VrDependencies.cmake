# Finds every third-party library of DESIGN.md section 3, once, for all folders.
# A missing library stops the configure step and names the Debian package that
# provides it, so a fresh machine knows what to install.
find_package(PkgConfig REQUIRED)

function(vr_missing what package)
  message(FATAL_ERROR
    "Virtuelium-C needs ${what}, which was not found.\n"
    "On Debian 12 install it with:  apt-get install ${package}\n"
    "(scripts/install-deps.sh installs every dependency at once.)")
endfunction()

# Ceres Solver (non-linear least squares, behind fit/'s C shim).
find_package(Ceres CONFIG QUIET)
if(NOT Ceres_FOUND)
  vr_missing("Ceres Solver" libceres-dev)
endif()

# GSL (special functions, integration, interpolation).
find_package(GSL QUIET)
if(NOT GSL_FOUND)
  vr_missing("GSL" libgsl-dev)
endif()

# LAPACKE (dense linear algebra).
pkg_check_modules(LAPACKE QUIET IMPORTED_TARGET lapacke)
if(NOT LAPACKE_FOUND)
  vr_missing("LAPACKE" liblapacke-dev)
endif()

# OpenCV, including the contrib mcc module for colour-chart detection.
find_package(OpenCV CONFIG QUIET COMPONENTS core imgproc imgcodecs)
if(NOT OpenCV_FOUND)
  vr_missing("OpenCV" libopencv-dev)
endif()
find_package(OpenCV CONFIG QUIET COMPONENTS mcc)
if(NOT OpenCV_FOUND)
  vr_missing("OpenCV's contrib module mcc" libopencv-contrib-dev)
endif()

# OpenEXR 3 (its C API lives in OpenEXR::OpenEXRCore).
find_package(OpenEXR 3 CONFIG QUIET)
if(NOT OpenEXR_FOUND)
  vr_missing("OpenEXR 3" libopenexr-dev)
endif()

# cmocka (unit tests).
pkg_check_modules(CMOCKA QUIET IMPORTED_TARGET cmocka)
if(NOT CMOCKA_FOUND)
  vr_missing("cmocka" libcmocka-dev)
endif()

# SQLite 3 (material database).
find_package(SQLite3 QUIET)
if(NOT SQLite3_FOUND)
  vr_missing("SQLite 3" libsqlite3-dev)
endif()

# libyaml (refractiveindex.info files).
pkg_check_modules(YAML QUIET IMPORTED_TARGET yaml-0.1)
if(NOT YAML_FOUND)
  vr_missing("libyaml" libyaml-dev)
endif()

# libxml2 (BSDF XML of WINDOW, the IGSDB and genBSDF).
find_package(LibXml2 QUIET)
if(NOT LibXml2_FOUND)
  vr_missing("libxml2" libxml2-dev)
endif()

# Embree 3 (ray/triangle intersection).
find_package(embree 3 CONFIG QUIET)
if(NOT embree_FOUND)
  vr_missing("Embree 3" libembree-dev)
endif()

# Assimp (OBJ, PLY, glTF meshes).
find_package(assimp CONFIG QUIET)
if(NOT assimp_FOUND)
  vr_missing("Assimp" libassimp-dev)
endif()

# Open MPI (several machines).  Required unless -DVR_MPI=OFF asks for the
# one-process configuration (a build of its own, as scripts/test.sh's
# no-MPI stage): a missing package never turns MPI off quietly, so a build
# that was meant to run on several ranks is never tested without them.
option(VR_MPI "Build vr-render with MPI (sub-domains on several ranks)" ON)
if(VR_MPI)
  find_package(MPI QUIET COMPONENTS C)
  if(NOT MPI_C_FOUND)
    message(FATAL_ERROR "MPI not found (apt-get install libopenmpi-dev openmpi-bin, as "
                        "scripts/install-deps.sh does), or configure with -DVR_MPI=OFF for a "
                        "vr-render that runs in one process only")
  endif()
endif()

# cairo (plots in reports).
pkg_check_modules(CAIRO QUIET IMPORTED_TARGET cairo)
if(NOT CAIRO_FOUND)
  vr_missing("cairo" libcairo2-dev)
endif()

message(STATUS "Virtuelium-C dependencies: Ceres ${Ceres_VERSION}, GSL ${GSL_VERSION}, "
               "LAPACKE ${LAPACKE_VERSION}, OpenCV ${OpenCV_VERSION}, OpenEXR ${OpenEXR_VERSION}, "
               "cmocka ${CMOCKA_VERSION}, SQLite ${SQLite3_VERSION}, libyaml ${YAML_VERSION}, libxml2 ${LIBXML2_VERSION_STRING}, "
               "Embree ${embree_VERSION}, Assimp ${assimp_VERSION}, MPI ${MPI_C_VERSION} (used: ${VR_MPI}), cairo ${CAIRO_VERSION}")
