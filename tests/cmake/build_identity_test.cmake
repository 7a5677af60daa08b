# cmake -P: a SHELLCONTRACT_NATIVE build's identity names its target (cmake/BuildIdentity.cmake,
# cmake/NativeTarget.cmake). Before, a -march=native build printed the default build's identity,
# `shellcontract 0.2.0+g<commit> (avx2 kernels)`, and its checkpoints and job ids were taken for
# the default build's although its results may round differently.
#   -DSOURCE_DIR=the checkout  -DGIT=git (may be empty)  -DCXX=the C++ compiler  -DWORK=a folder
cmake_minimum_required(VERSION 3.20)  # the policies of the project (CMP0054: quoted if() arguments)
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")

# The header BuildIdentity.cmake writes for NATIVE and GIT (and TOOLCHAIN, a fourth argument),
# as its SHELLCONTRACT_BUILD_SOURCE.
function(build_source native git out)
  set(toolchain "${ARGV3}")
  set(header "${WORK}/build_source.hpp")
  file(REMOVE "${header}")
  execute_process(COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${SOURCE_DIR} -DOUT=${header} -DGIT=${git}
                          -DNATIVE=${native} "-DTOOLCHAIN=${toolchain}"
                          -P ${SOURCE_DIR}/cmake/BuildIdentity.cmake
                  RESULT_VARIABLE rc)
  file(READ "${header}" text)
  if(NOT rc EQUAL 0 OR NOT text MATCHES "#define SHELLCONTRACT_BUILD_SOURCE \"([^\"]*)\"")
    message(FATAL_ERROR "BuildIdentity.cmake (exit ${rc}) wrote no build source: ${text}")
  endif()
  set(${out} "${CMAKE_MATCH_1}" PARENT_SCOPE)
endfunction()

build_source("" "${GIT}" plain)
build_source("native.1a2b3c4d" "${GIT}" native)
build_source("native.1a2b3c4d" "" native_no_git)
if(plain MATCHES "native")
  message(FATAL_ERROR "the default build's source names a native target: '${plain}'")
endif()
if(plain STREQUAL "")
  set(expected "native.1a2b3c4d")  # not a git checkout (a source archive)
else()
  set(expected "${plain}.native.1a2b3c4d")
endif()
if(NOT native STREQUAL expected)
  message(FATAL_ERROR "a native build's source is '${native}', expected '${expected}' (the default build's: '${plain}')")
endif()
if(NOT native_no_git STREQUAL "native.1a2b3c4d")
  message(FATAL_ERROR "a native build outside git: '${native_no_git}', expected 'native.1a2b3c4d'")
endif()

# The toolchain (CMakeLists.txt's SHELLCONTRACT_TOOLCHAIN): a Debug build, or another compiler,
# of one commit printed the same identity as the Release build although the batched kernels, which
# rely on the compiler's fused multiply-adds, may round otherwise (review repro F3).
build_source("" "${GIT}" release "GNU 12.2.0 Release  -O3 -DNDEBUG")
build_source("" "${GIT}" debug "GNU 12.2.0 Debug  -g")
build_source("native.1a2b3c4d" "${GIT}" release_native "GNU 12.2.0 Release  -O3 -DNDEBUG")
string(SHA256 release_hash "GNU 12.2.0 Release  -O3 -DNDEBUG")
string(SUBSTRING "${release_hash}" 0 8 release_hash)
if(plain STREQUAL "")
  set(expected_release "tc.${release_hash}")
else()
  set(expected_release "${plain}.tc.${release_hash}")
endif()
if(NOT release STREQUAL expected_release)
  message(FATAL_ERROR "a toolchain's source is '${release}', expected '${expected_release}'")
endif()
if(debug STREQUAL release)
  message(FATAL_ERROR "a Debug and a Release build of one commit have one identity: '${debug}'")
endif()
if(NOT release_native STREQUAL "${expected_release}.native.1a2b3c4d")
  message(FATAL_ERROR "a native build's toolchain: '${release_native}', expected '${expected_release}.native.1a2b3c4d'")
endif()

# The target's name: the hash of what -march=native picks, so two CPUs give two names; "native"
# where the compiler does not say.
include(${SOURCE_DIR}/cmake/NativeTarget.cmake)
function(fake_compiler name stderr_text rc)
  file(WRITE "${WORK}/${name}" "#!/bin/sh\necho '${stderr_text}' >&2\nexit ${rc}\n")
  file(CHMOD "${WORK}/${name}" PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE)
endfunction()
fake_compiler(skylake " cc1plus -E \"-march=skylake\" -mavx2 -mfma -mno-avx512f \"-mtune=generic\"" 0)
fake_compiler(znver3 " cc1plus -E \"-march=znver3\" -mavx2 -mfma -mno-avx512f \"-mtune=generic\"" 0)
fake_compiler(clang " \"-cc1\" \"-target-cpu\" \"icelake-client\" \"-target-feature\" \"+avx2\"" 0)
fake_compiler(refuses "error: unrecognized command-line option '-march=native'" 1)
shellcontract_native_tag(${WORK}/skylake skylake)
shellcontract_native_tag(${WORK}/znver3 znver3)
shellcontract_native_tag(${WORK}/clang clang)
shellcontract_native_tag(${WORK}/refuses refuses)
set(hex8 "[0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f]")  # no {8} in CMake
foreach(tag skylake znver3 clang)
  if(NOT "${${tag}}" MATCHES "^native\\.${hex8}$")
    message(FATAL_ERROR "the ${tag} compiler's target: '${${tag}}', expected native.<8 hex digits>")
  endif()
endforeach()
if(skylake STREQUAL znver3)
  message(FATAL_ERROR "two CPUs' targets have one name: ${skylake}")
endif()
if(NOT refuses STREQUAL "native")
  message(FATAL_ERROR "a compiler that does not say: '${refuses}', expected 'native'")
endif()
shellcontract_native_tag(${CXX} real)
# GCC and Clang (the compilers the project builds with) say what -march=native means.
if(NOT real MATCHES "^native\\.${hex8}$")
  message(FATAL_ERROR "the target of ${CXX} -march=native: '${real}', expected native.<8 hex digits>")
endif()
message(STATUS "default build: '${plain}'; native build: '${native}'; this machine's target with ${CXX}: ${real}")
