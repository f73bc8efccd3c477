# `cmake --install` rules: the libraries, the public headers under include/mspline/, the mspline
# executable and its man page, the CMake package (find_package(mspline) -> mspline::io etc.) and
# the license. Every install rule of the project is here.
include(CMakePackageConfigHelpers)

set(MSPLINE_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/mspline)

# The viewer is not part of the package: it is the `mspline view` command's window, and its
# private GLFW, OpenGL and Dear ImGui libraries would become every consumer's dependencies.
set(mspline_libraries mspline_structure mspline_spline mspline_subd mspline_model mspline_io)
install(TARGETS ${mspline_libraries}
        EXPORT msplineTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS mspline RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
if(BUILD_SHARED_LIBS)
  # Installed, the executable and the libraries find the libraries they need in any prefix.
  set_target_properties(mspline PROPERTIES INSTALL_RPATH "$ORIGIN/../${CMAKE_INSTALL_LIBDIR}")
  set_target_properties(${mspline_libraries} PROPERTIES INSTALL_RPATH "$ORIGIN")
endif()

# Public headers keep their room paths: <mspline/spline/tspline/tspline.h>. Not installed: the
# format internals (io/detail/) and the one header that includes OpenSubdiv's (the subd library
# uses OpenSubdiv privately). scripts/test-install checks that every installed header includes
# only installed headers, the standard library, Eigen and OpenMesh.
foreach(folder structure spline io)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${folder}
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/mspline
          FILES_MATCHING PATTERN "*.h"
          PATTERN "detail" EXCLUDE
          PATTERN "osd_patches.h" EXCLUDE)
endforeach()

install(EXPORT msplineTargets NAMESPACE mspline:: DESTINATION ${MSPLINE_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/msplineConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/msplineConfig.cmake
                              INSTALL_DESTINATION ${MSPLINE_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/msplineConfigVersion.cmake
                                 COMPATIBILITY SameMajorVersion)
# The config re-creates the wrapper targets of CHOLMOD, GLPK and OpenSubdiv with the same files the
# build uses.
install(FILES ${PROJECT_BINARY_DIR}/msplineConfig.cmake ${PROJECT_BINARY_DIR}/msplineConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/Cholmod.cmake ${PROJECT_SOURCE_DIR}/cmake/Glpk.cmake
              ${PROJECT_SOURCE_DIR}/cmake/OpenSubdiv.cmake
        DESTINATION ${MSPLINE_CMAKE_DIR})

install(FILES ${PROJECT_SOURCE_DIR}/LICENSE DESTINATION ${CMAKE_INSTALL_DOCDIR})

# The man page is mspline's --help as help2man formats it; it needs to run the executable, so a
# cross build or a machine without help2man goes without it.
find_program(HELP2MAN help2man)
if(HELP2MAN AND NOT CMAKE_CROSSCOMPILING)
  set(man_page ${PROJECT_BINARY_DIR}/mspline.1)
  # Run as ./mspline from its folder: the usage line then names no build path.
  add_custom_command(
    OUTPUT ${man_page}
    COMMAND ${HELP2MAN} --no-info --name "manifold spline modeling on triangle meshes"
            --include ${PROJECT_SOURCE_DIR}/cmake/mspline.h2m --output ${man_page} ./mspline
    WORKING_DIRECTORY $<TARGET_FILE_DIR:mspline>
    DEPENDS mspline ${PROJECT_SOURCE_DIR}/cmake/mspline.h2m
    COMMENT "Generating the man page mspline.1")
  add_custom_target(mspline_man ALL DEPENDS ${man_page})
  install(FILES ${man_page} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
else()
  message(STATUS "help2man not found: no man page")
endif()
