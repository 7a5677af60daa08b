# cmake -P script for the package_consumer test (tests/package/CMakeLists.txt): install into a
# fresh prefix, check what was installed, build the consumer against it and run it.
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

foreach(f lib/libshellcontract.a bin/shellcontract include/shellcontract/sim/run.hpp
          lib/cmake/ShellContract/ShellContractConfig.cmake
          lib/cmake/ShellContract/ShellContractConfigVersion.cmake)
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
file(GLOB_RECURSE headers ${prefix}/include/shellcontract/*.hpp)
foreach(f ${headers})
  file(READ ${f} text)
  if(text MATCHES "#include [<\"](boost/program_options|gtest|benchmark)")
    message(FATAL_ERROR "${f} includes ${CMAKE_MATCH_1}, a CLI- or test-only dependency")
  endif()
endforeach()

set(launcher "")
if(COMPILER_LAUNCHER)
  set(launcher -DCMAKE_CXX_COMPILER_LAUNCHER=${COMPILER_LAUNCHER})
endif()
run(${CMAKE_COMMAND} -S ${CONSUMER_DIR} -B ${WORK_DIR}/build -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_CXX_COMPILER=${CXX_COMPILER} ${launcher} -DCMAKE_PREFIX_PATH=${prefix})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run(${WORK_DIR}/build/app ${MESH} 10)
