# cmake --install build --prefix P: the library, its public headers, the CLI,
# the default arm file, the docs, a pkg-config file and a CMake package.
#
#   P/lib/libelasticarm.so.MAJOR.MINOR (SONAME), .so, and libelasticarm.a
#     (only the .a with -DBUILD_SHARED_LIBS=OFF; no .a with -DEA_BUILD_STATIC_LIB=OFF)
#   P/include/elasticarm/ea_*.h     (-I P/include/elasticarm: #include "ea_model.h")
#   P/bin/elasticarm                (finds P/share/elasticarm/elasticarm.yaml)
#   P/share/elasticarm/elasticarm.yaml
#   P/share/doc/elasticarm/         (README.md, docs/*.md, example_api.c)
#   P/lib/pkgconfig/elasticarm.pc   (pkg-config --cflags --libs elasticarm)
#   P/lib/cmake/elasticarm/         (find_package(elasticarm CONFIG) -> elasticarm::elasticarm,
#                                    and elasticarm::elasticarm_static beside a shared one)
#   P/lib/python3.X/dist-packages/elasticarm/  (the Python package, python/CMakeLists.txt)
include(CMakePackageConfigHelpers)

set(EA_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/elasticarm)
set(EA_INSTALL_PKGCONFIGDIR ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

set(EA_INSTALL_LIBS elasticarm_lib)
if(EA_STATIC_LIB)
  list(APPEND EA_INSTALL_LIBS elasticarm_static)
endif()
install(TARGETS ${EA_INSTALL_LIBS} EXPORT elasticarmTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS elasticarm RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

file(GLOB EA_INSTALL_HEADERS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/model/include/*.h
     ${PROJECT_SOURCE_DIR}/problems/include/*.h ${PROJECT_SOURCE_DIR}/planner/include/*.h)
install(FILES ${EA_INSTALL_HEADERS} ${EA_INC_GENERATED}/ea_version.h
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/elasticarm)

# The CLI looks for <folder of the executable>/../share/elasticarm/elasticarm.yaml.
install(FILES ${PROJECT_SOURCE_DIR}/data/elasticarm.yaml
  DESTINATION ${CMAKE_INSTALL_DATADIR}/elasticarm)

file(GLOB EA_INSTALL_DOCS ${PROJECT_SOURCE_DIR}/docs/*.md)
install(FILES ${PROJECT_SOURCE_DIR}/README.md ${EA_INSTALL_DOCS} ${PROJECT_SOURCE_DIR}/docs/example_api.c
  DESTINATION ${CMAKE_INSTALL_DOCDIR})

# CMake package: elasticarmTargets.cmake (the exported target) and a config
# that finds the dependencies first.
install(EXPORT elasticarmTargets NAMESPACE elasticarm:: DESTINATION ${EA_INSTALL_CMAKEDIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/elasticarmConfig.cmake.in
  ${PROJECT_BINARY_DIR}/elasticarmConfig.cmake INSTALL_DESTINATION ${EA_INSTALL_CMAKEDIR})
# 0.x: a minor version may change the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/elasticarmConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/elasticarmConfig.cmake
  ${PROJECT_BINARY_DIR}/elasticarmConfigVersion.cmake DESTINATION ${EA_INSTALL_CMAKEDIR})

# pkg-config: relocatable (prefix from the .pc file's own folder, so
# `cmake --install build --prefix P` works whatever CMAKE_INSTALL_PREFIX was).
# A static libelasticarm.a is of no use without its dependencies, so they are
# in Requires/Libs; a shared one records them in Requires.private/Libs.private
# (used by pkg-config --static).
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}")
  message(FATAL_ERROR "elasticarm.pc needs a relative CMAKE_INSTALL_LIBDIR")
endif()
file(RELATIVE_PATH EA_PC_TO_PREFIX /prefix/${EA_INSTALL_PKGCONFIGDIR} /prefix)
string(REGEX REPLACE "/$" "" EA_PC_TO_PREFIX "${EA_PC_TO_PREFIX}")
set(EA_PC_DEPS "gsl ipopt nlopt yaml-0.1 lapack")
set(EA_PC_SYSLIBS "-lklu -lldl -lamd -lpthread -lm") # SuiteSparse has no pkg-config module here
if(BUILD_SHARED_LIBS)
  set(EA_PC_REQUIRES "")
  set(EA_PC_REQUIRES_PRIVATE "${EA_PC_DEPS}")
  set(EA_PC_LIBS "")
  set(EA_PC_LIBS_PRIVATE "${EA_PC_SYSLIBS}")
else()
  set(EA_PC_REQUIRES "${EA_PC_DEPS}")
  set(EA_PC_REQUIRES_PRIVATE "")
  set(EA_PC_LIBS " ${EA_PC_SYSLIBS}")
  set(EA_PC_LIBS_PRIVATE "")
endif()
configure_file(${PROJECT_SOURCE_DIR}/cmake/elasticarm.pc.in ${PROJECT_BINARY_DIR}/elasticarm.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/elasticarm.pc DESTINATION ${EA_INSTALL_PKGCONFIGDIR})
