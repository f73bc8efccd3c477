# Debian's libglpk-dev ships no CMake config: find the header and the library and wrap them in an
# imported target (the integer program that gives the layout segments whole numbers of cells).
find_path(GLPK_INCLUDE_DIR glpk.h REQUIRED)
find_library(GLPK_LIBRARY glpk REQUIRED)
if(NOT TARGET mspline::glpk)
  add_library(mspline::glpk UNKNOWN IMPORTED)
  set_target_properties(mspline::glpk PROPERTIES
    IMPORTED_LOCATION "${GLPK_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${GLPK_INCLUDE_DIR}")
endif()
message(STATUS "GLPK: ${GLPK_LIBRARY}")
