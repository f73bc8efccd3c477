# Debian's libsuitesparse-dev 5.x ships no CMake config for CHOLMOD, so find the header and the
# libraries directly and wrap them in an imported target. BLAS and LAPACK come in through
# libcholmod's own dependencies (libblas.so.3 / liblapack.so.3): Debian's alternatives choose the
# implementation at run time, and scripts/install-deps installs OpenBLAS so they point to it.
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
find_library(CHOLMOD_LIBRARY cholmod REQUIRED)
find_library(SUITESPARSECONFIG_LIBRARY suitesparseconfig REQUIRED)
if(NOT TARGET mspline::cholmod)
  add_library(mspline::cholmod UNKNOWN IMPORTED)
  set_target_properties(mspline::cholmod PROPERTIES
    IMPORTED_LOCATION "${CHOLMOD_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${SUITESPARSECONFIG_LIBRARY}")
endif()
message(STATUS "CHOLMOD: ${CHOLMOD_LIBRARY}")
