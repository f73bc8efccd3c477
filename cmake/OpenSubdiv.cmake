# Debian's OpenSubdivConfig.cmake references static libraries that the package does not ship,
# so find the headers and the CPU library directly and wrap them in an imported target.
find_path(OPENSUBDIV_INCLUDE_DIR opensubdiv/far/patchTable.h REQUIRED)
find_library(OPENSUBDIV_CPU_LIBRARY osdCPU REQUIRED)
if(NOT TARGET mspline::opensubdiv)
  add_library(mspline::opensubdiv UNKNOWN IMPORTED)
  set_target_properties(mspline::opensubdiv PROPERTIES
    IMPORTED_LOCATION "${OPENSUBDIV_CPU_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${OPENSUBDIV_INCLUDE_DIR}")
endif()
message(STATUS "OpenSubdiv: ${OPENSUBDIV_CPU_LIBRARY}")
