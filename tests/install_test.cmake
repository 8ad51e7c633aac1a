# The test "install": `cmake --install` into a fresh prefix, then an outside
# build of docs/example_api.c against it both ways a C user would, with plain
# -std=c11: pkg-config (the README's line, `cc -std=c11 example_api.c
# $(pkg-config --cflags --libs elasticarm) -lm`) and a CMake project with
# find_package(elasticarm) (tests/install/CMakeLists.txt); each program is run (example_api exits non-zero on a wrong answer). Also:
# every installed header compiles with -std=c11 -Wpedantic -Werror as
# <elasticarm/ea_*.h>, the header's EA_VERSION_STRING equals the library's
# ea_version() and project()'s version, and the installed CLI, run from a
# folder without data/, prints that version and finds the installed arm file.
# A shared build (the default) is tested both ways against the shared library
# and against the static one installed beside it (STATIC=ON): pkg-config
# --static with libelasticarm.a, and elasticarm::elasticarm_static; each such
# program must not need libelasticarm.so. With PYTHON (Debian's python3) and
# PYDIR (the package's folder under the prefix): the installed Python package
# imports with PYTHONPATH=P/PYDIR, loads P's library and arm file and solves.
#
# cmake -DBUILD=... -DSRC=... -DWORK=... -DCC=... -DPKG_CONFIG=... -DVERSION=...
#       [-DEXTRA_FLAGS=...] [-DSHARED=ON -DSTATIC=ON] [-DPYTHON=... -DPYDIR=...]
#       -P install_test.cmake
cmake_minimum_required(VERSION 3.18)
foreach(v BUILD SRC WORK CC PKG_CONFIG VERSION)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "install_test.cmake: -D${v}=... missing")
  endif()
endforeach()
separate_arguments(EXTRA UNIX_COMMAND "${EXTRA_FLAGS}")

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${ARGN}\n${out}\n${err}")
  endif()
  set(OUT "${out}" PARENT_SCOPE)
endfunction()

set(P ${WORK}/prefix)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK}/empty)

# 1. Install.
run("cmake --install" ${CMAKE_COMMAND} --install ${BUILD} --prefix ${P})
foreach(f bin/elasticarm share/elasticarm/elasticarm.yaml include/elasticarm/ea_model.h
    include/elasticarm/ea_version.h lib/pkgconfig/elasticarm.pc
    lib/cmake/elasticarm/elasticarmConfig.cmake share/doc/elasticarm/example_api.c)
  if(NOT EXISTS ${P}/${f})
    message(FATAL_ERROR "not installed: ${P}/${f}")
  endif()
endforeach()
set(ENV{LD_LIBRARY_PATH} "${P}/lib:$ENV{LD_LIBRARY_PATH}") # a shared build

# 2. The installed CLI, away from the source tree and without $EA_ARM_FILE.
unset(ENV{EA_ARM_FILE})
execute_process(COMMAND ${P}/bin/elasticarm --version WORKING_DIRECTORY ${WORK}/empty
  RESULT_VARIABLE rc OUTPUT_VARIABLE out)
if(NOT rc EQUAL 0 OR NOT out STREQUAL "elasticarm ${VERSION}\n")
  message(FATAL_ERROR "elasticarm --version: exit ${rc}, '${out}', expected 'elasticarm ${VERSION}'")
endif()
execute_process(COMMAND ${P}/bin/elasticarm --help WORKING_DIRECTORY ${WORK}/empty
  OUTPUT_VARIABLE out)
if(NOT out MATCHES "found as: share/elasticarm/ beside")
  message(FATAL_ERROR "installed CLI does not use the installed arm file:\n${out}")
endif()
run("installed CLI statics" ${P}/bin/elasticarm statics --cable-length 0.45 --cable-angle-deg -25)

# 3. Every installed header alone, as <elasticarm/...>, plus the version check.
file(GLOB headers RELATIVE ${P}/include/elasticarm ${P}/include/elasticarm/*.h)
set(c "#include <string.h>\n")
foreach(h ${headers})
  string(APPEND c "#include <elasticarm/${h}>\n")
endforeach()
string(APPEND c "int main(void) {\n  return strcmp(ea_version(), EA_VERSION_STRING) != 0 ||\n"
  "         strcmp(EA_VERSION_STRING, \"${VERSION}\") != 0;\n}\n")
set(EA_ALL_HEADERS ${WORK}/all_headers.c)
file(WRITE ${EA_ALL_HEADERS} "${c}")

# 4. pkg-config, as in the README.
set(ENV{PKG_CONFIG_PATH} "${P}/lib/pkgconfig")
run("pkg-config" ${PKG_CONFIG} --cflags --libs elasticarm)
separate_arguments(pc UNIX_COMMAND "${OUT}")
run("pkg-config --cflags" ${PKG_CONFIG} --cflags elasticarm)
separate_arguments(pc_cflags UNIX_COMMAND "${OUT}")
set(warn -Wall -Wextra -Wpedantic -Werror)
run("cc example_api.c (pkg-config)" ${CC} -std=c11 ${warn} ${EXTRA} -o ${WORK}/example_api_pc
  ${SRC}/docs/example_api.c ${pc} -lm) # the example calls libm itself
run("example_api (pkg-config)" ${WORK}/example_api_pc)
run("cc all_headers.c (pkg-config)" ${CC} -std=c11 ${warn} ${EXTRA} -o ${WORK}/all_headers_pc
  ${EA_ALL_HEADERS} ${pc})
run("all_headers (pkg-config)" ${WORK}/all_headers_pc)

# 5. find_package(elasticarm CONFIG), from a separate CMake project.
run("configure the find_package project" ${CMAKE_COMMAND} -S ${SRC}/tests/install
  -B ${WORK}/consumer -DCMAKE_PREFIX_PATH=${P} -DCMAKE_C_COMPILER=${CC}
  "-DCMAKE_C_FLAGS=${EXTRA_FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${EXTRA_FLAGS}"
  -DEA_EXAMPLE=${SRC}/docs/example_api.c -DEA_ALL_HEADERS=${EA_ALL_HEADERS})
run("build the find_package project" ${CMAKE_COMMAND} --build ${WORK}/consumer)
run("example_api (find_package)" ${WORK}/consumer/example_api)
run("all_headers (find_package)" ${WORK}/consumer/all_headers)

# A program linked against the static library must not need the shared one.
function(check_not_shared what exe)
  execute_process(COMMAND readelf -d ${exe} OUTPUT_VARIABLE dyn RESULT_VARIABLE rc)
  if(rc EQUAL 0 AND dyn MATCHES "libelasticarm\\.so")
    message(FATAL_ERROR "${what} needs libelasticarm.so:\n${dyn}")
  endif()
endfunction()
if(SHARED)
  execute_process(COMMAND readelf -d ${WORK}/example_api_pc OUTPUT_VARIABLE dyn)
  if(NOT dyn MATCHES "libelasticarm\\.so\\.")
    message(FATAL_ERROR "example_api (pkg-config) does not use the shared library:\n${dyn}")
  endif()
endif()

# 6. The static library beside the shared one: pkg-config --static, the archive by path
#    (the linker would take the .so for -lelasticarm), and find_package's static target.
if(STATIC)
  if(NOT EXISTS ${P}/lib/libelasticarm.a)
    message(FATAL_ERROR "not installed: ${P}/lib/libelasticarm.a")
  endif()
  run("pkg-config --static" ${PKG_CONFIG} --static --libs elasticarm)
  separate_arguments(pcs UNIX_COMMAND "${OUT}")
  list(TRANSFORM pcs REPLACE "^-lelasticarm$" "${P}/lib/libelasticarm.a")
  run("cc example_api.c (static)" ${CC} -std=c11 ${warn} ${EXTRA} -o ${WORK}/example_api_static
    ${SRC}/docs/example_api.c ${pc_cflags} ${pcs} -lm)
  check_not_shared("example_api (static)" ${WORK}/example_api_static)
  run("example_api (static)" ${WORK}/example_api_static)
  if(NOT EXISTS ${WORK}/consumer/example_api_static)
    message(FATAL_ERROR "find_package: no elasticarm::elasticarm_static target")
  endif()
  check_not_shared("example_api_static (find_package)" ${WORK}/consumer/example_api_static)
  run("example_api_static (find_package)" ${WORK}/consumer/example_api_static)
endif()

# 7. The installed Python package, as Debian's python3 imports it from the prefix.
if(PYTHON)
  set(ENV{PYTHONPATH} "${P}/${PYDIR}")
  unset(ENV{EA_LIBRARY})
  execute_process(COMMAND ${PYTHON} -c
    "import math, elasticarm as ea; s = ea.statics(cable_length=0.45, cable_angle=math.radians(-25)); print(ea.__file__); print(ea.LIBRARY_PATH); print(ea.default_arm_file()); print(ea.library_version()); print(repr(s.tension_N))"
    WORKING_DIRECTORY ${WORK}/empty RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "import elasticarm from ${P}/${PYDIR} failed (${rc}):\n${out}\n${err}")
  endif()
  string(REPLACE "\n" ";" lines "${out}")
  list(GET lines 0 pkg)
  list(GET lines 1 libpath)
  list(GET lines 2 armpath)
  list(GET lines 3 ver)
  file(REAL_PATH ${libpath} libreal)
  file(REAL_PATH ${P} preal)
  if(NOT pkg MATCHES "^${P}/" OR NOT libreal MATCHES "^${preal}/lib/libelasticarm\\.so"
     OR NOT armpath MATCHES "share/elasticarm/elasticarm.yaml$" OR NOT ver STREQUAL VERSION)
    message(FATAL_ERROR "the installed Python package is not the prefix's:\n${out}")
  endif()
endif()
message(STATUS "installed to ${P}; example_api built and run via pkg-config and find_package")
