# cmake -P script for the package_consumer test (tests/package/CMakeLists.txt): install into a
# fresh prefix, check what was installed, build the consumer against it and run it, then the same
# program with pkg-config (pkg_config_consumer.cmake); with the Python module (PYTHON_PACKAGE), run
# the installed `shellcontract sweep`, import the installed package and check its metadata
# (check_dist_info.py).
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  message("${out}")
endfunction()

set(prefix ${WORK_DIR}/prefix)
file(REMOVE_RECURSE ${WORK_DIR})
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

foreach(f lib/libshellcontract.a bin/shellcontract include/shellcontract/run.hpp
          lib/cmake/ShellContract/ShellContractConfig.cmake
          lib/cmake/ShellContract/ShellContractConfigVersion.cmake
          ${LIBDIR}/pkgconfig/shellcontract.pc ${MANDIR}/man1/shellcontract.1)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "not installed: ${f}")
  endif()
endforeach()
# The package must not ask users for the CLI's or the tests' dependencies.
file(GLOB package_files ${prefix}/lib/cmake/ShellContract/*.cmake)
foreach(f ${package_files})
  file(READ ${f} text)
  if(text MATCHES "program_options|GTest|gtest|benchmark|shellcontract_warnings")
    message(FATAL_ERROR "${f} names a CLI- or test-only dependency:\n${CMAKE_MATCH_0}")
  endif()
endforeach()
# The public surface is the facade (docs/architecture.md, "The public surface"): exactly these
# headers and no folder, each including only the others and system headers, so that nothing
# private leaks.
set(facade checkpoint checkpoint_lock error export face_error file_error material mesh mesh_io observer options
    output_files regions repair report run signals simulation_options types validation version)
file(GLOB_RECURSE headers LIST_DIRECTORIES true RELATIVE ${prefix}/include ${prefix}/include/shellcontract/*)
set(expected "")
foreach(h ${facade})
  list(APPEND expected shellcontract/${h}.hpp)
endforeach()
list(SORT headers)
list(SORT expected)
if(NOT headers STREQUAL expected)
  message(FATAL_ERROR "installed headers:\n  ${headers}\nexpected the facade:\n  ${expected}")
endif()
foreach(h ${headers})
  file(READ ${prefix}/include/${h} text)
  if(text MATCHES "#include [<\"](boost/program_options|gtest|benchmark)")
    message(FATAL_ERROR "${h} includes ${CMAKE_MATCH_1}, a CLI- or test-only dependency")
  endif()
  string(REGEX MATCHALL "#include \"[^\"]+\"" quoted "${text}")
  foreach(q ${quoted})
    string(REGEX REPLACE "#include \"([^\"]+)\"" "\\1" target "${q}")
    if(NOT EXISTS ${prefix}/include/${target})
      message(FATAL_ERROR "${h} includes ${target}, which is not installed")
    endif()
  endforeach()
endforeach()

if(PYTHON_PACKAGE)
  set(package ${prefix}/${PYTHON_INSTALL_DIR}/shellcontract)
  file(GLOB core ${package}/_core*.so)
  if(NOT core)
    message(FATAL_ERROR "not installed: the Python module ${package}/_core*.so")
  endif()
  # Every module of the source package (a list kept by hand missed the new ones).
  file(GLOB sources RELATIVE ${PYTHON_SOURCE_DIR} ${PYTHON_SOURCE_DIR}/*.py)
  if(NOT sources)
    message(FATAL_ERROR "no Python modules in ${PYTHON_SOURCE_DIR}")
  endif()
  foreach(f ${sources})
    if(NOT EXISTS ${package}/${f})
      message(FATAL_ERROR "not installed: ${package}/${f}")
    endif()
  endforeach()
  # The Blender add-on's zip, installable as it is (docs/blender.md).
  set(zip ${prefix}/share/shellcontract/shellcontract_blender.zip)
  execute_process(COMMAND ${PYTHON} -m zipfile -l ${zip} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "shellcontract_blender/__init__.py")
    message(FATAL_ERROR "not installed, or not the add-on: ${zip} (${rc})\n${out}\n${err}")
  endif()
  # The installed sweep finds the installed package next to its executable: no PYTHONPATH, no
  # SHELLCONTRACT_CLI, and nothing of the build tree.
  file(WRITE ${WORK_DIR}/sweep.json "{\"meshes\": [\"${MESH}\"], \"grid\": {\"frames\": [3, 4]}}")
  execute_process(
    COMMAND ${CMAKE_COMMAND} -E env --unset=PYTHONPATH --unset=SHELLCONTRACT_CLI
            ${prefix}/bin/shellcontract sweep ${WORK_DIR}/sweep.json -o ${WORK_DIR}/sweep-out --dry-run
    WORKING_DIRECTORY ${WORK_DIR} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "--frames 3" OR NOT out MATCHES "--frames 4")
    message(FATAL_ERROR "installed `shellcontract sweep --dry-run` failed (${rc}):\n${out}\n${err}")
  endif()
  execute_process(
    COMMAND ${CMAKE_COMMAND} -E env PYTHONPATH=${prefix}/${PYTHON_INSTALL_DIR}
            ${PYTHON} -c "import shellcontract; print(shellcontract.__file__)"
    WORKING_DIRECTORY ${WORK_DIR} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  string(FIND "${out}" "${package}/__init__.py" at)
  if(NOT rc EQUAL 0 OR NOT at EQUAL 0)
    message(FATAL_ERROR "the installed package is not the one imported (${rc}):\n${out}\n${err}")
  endif()
  # Its metadata (the dist-info beside it): importlib.metadata and pip see the installed package.
  execute_process(
    COMMAND ${CMAKE_COMMAND} -E env PYTHONPATH=${prefix}/${PYTHON_INSTALL_DIR}
            ${PYTHON} ${CMAKE_CURRENT_LIST_DIR}/check_dist_info.py ${prefix}/${PYTHON_INSTALL_DIR} ${VERSION}
    WORKING_DIRECTORY ${WORK_DIR} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "the installed package's metadata (${rc}):\n${out}\n${err}")
  endif()
  message("${out}")
endif()

set(launcher "")
if(COMPILER_LAUNCHER)
  set(launcher -DCMAKE_CXX_COMPILER_LAUNCHER=${COMPILER_LAUNCHER})
endif()
# Each link command of the consumer is recorded (link-<output>.txt, one argument a line), and its
# compile commands are exported, for the comparison with pkg-config's flags (pkg_config_consumer.cmake).
file(WRITE ${WORK_DIR}/record_link.sh [=[#!/bin/sh
out=link prev=
for a in "$@"; do
  if [ "$prev" = "-o" ]; then out=$a; fi
  prev=$a
done
printf '%s\n' "$@" > "$(dirname "$0")/link-$(basename "$out").txt"
exec "$@"
]=])
file(CHMOD ${WORK_DIR}/record_link.sh PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE)
run(${CMAKE_COMMAND} -S ${CONSUMER_DIR} -B ${WORK_DIR}/build -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_CXX_COMPILER=${CXX_COMPILER} ${launcher} -DCMAKE_PREFIX_PATH=${prefix}
    -DCMAKE_EXPORT_COMPILE_COMMANDS=ON -DCMAKE_CXX_LINKER_LAUNCHER=${WORK_DIR}/record_link.sh)
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run(${WORK_DIR}/build/app ${MESH} 10)
include(${CMAKE_CURRENT_LIST_DIR}/pkg_config_consumer.cmake)
# The consumer compiled with -mavx2 -mfma (consumer/CMakeLists.txt) runs only on a CPU that has
# both; elsewhere it was built, and the test says that it did not run.
if(EXISTS ${WORK_DIR}/build/app_avx2)
  set(cpu_flags "")
  if(EXISTS /proc/cpuinfo)
    file(STRINGS /proc/cpuinfo cpu_flags REGEX "^flags" LIMIT_COUNT 1)
  endif()
  if(cpu_flags MATCHES "[ \t]avx2([ \t]|$)" AND cpu_flags MATCHES "[ \t]fma([ \t]|$)")
    run(${WORK_DIR}/build/app_avx2 ${MESH} 10)
  else()
    message("app_avx2 (-mavx2 -mfma) built but not run: this CPU lacks AVX2 or FMA")
  endif()
else()
  message("app_avx2 (-mavx2 -mfma) not built: not an x86-64 target")
endif()
