# libFuzzer target for the mesh reader (issue 30), on with -DSHELLCONTRACT_LIBFUZZER=ON in a build
# folder configured with clang; docs/design/testing.md says how to build and run it. Only the
# reader's sources are compiled into it (with libFuzzer, ASan and UBSan), not the whole library: a
# small target, quick to build. Their list is SHELLCONTRACT_READER_SOURCES (CMakeLists.txt), the
# one the library's shellcontract_reader objects are built from; the default build links those
# objects alone into reader_fuzzer_replay, so a missing file shows there, not only here.
if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  message(FATAL_ERROR "SHELLCONTRACT_LIBFUZZER needs clang (libFuzzer is clang's): configure a separate "
                      "build folder with -DCMAKE_CXX_COMPILER=clang++")
endif()
set(_fuzz_sanitizers -fsanitize=fuzzer,address,undefined)
add_executable(reader_fuzzer ${PROJECT_SOURCE_DIR}/tests/fuzz/libfuzzer/reader_fuzzer.cpp
                             ${SHELLCONTRACT_READER_SOURCES})
target_include_directories(reader_fuzzer PRIVATE ${PROJECT_SOURCE_DIR}/include ${PROJECT_SOURCE_DIR}/src)
target_include_directories(reader_fuzzer SYSTEM PRIVATE ${TINYGLTF_INCLUDE_DIR} ${NLOHMANN_JSON_INCLUDE_DIR})
target_link_libraries(reader_fuzzer PRIVATE Eigen3::Eigen CGAL::CGAL)
# Eigen's allocator as in the library (CMakeLists.txt): the public headers require it.
target_compile_definitions(reader_fuzzer PRIVATE ${SHELLCONTRACT_EIGEN_DEFINITIONS})
# -O1 -g after the build type's flags (the last -O wins): quick to build, readable reports.
target_compile_options(reader_fuzzer PRIVATE ${_fuzz_sanitizers} -fno-sanitize-recover=undefined
                                             -fno-omit-frame-pointer -O1 -g)
target_link_options(reader_fuzzer PRIVATE ${_fuzz_sanitizers})

# The seed corpus: the octahedron in every format and PLY variant (tests/fuzz/fuzz_inputs.hpp),
# written by a small program, and the named regression files of tests/data/fuzz/regressions.
add_executable(reader_fuzzer_seeds ${PROJECT_SOURCE_DIR}/tests/fuzz/libfuzzer/write_seeds.cpp)
target_include_directories(reader_fuzzer_seeds PRIVATE ${PROJECT_SOURCE_DIR}/tests)

if(SHELLCONTRACT_BUILD_TESTS)
  set(_fuzz_dir ${PROJECT_BINARY_DIR}/libfuzzer)  # not reader_fuzzer: that is the program
  file(MAKE_DIRECTORY ${_fuzz_dir}/corpus ${_fuzz_dir}/artifacts)
  add_test(NAME ReaderLibFuzzer.Seeds COMMAND reader_fuzzer_seeds ${_fuzz_dir}/seeds)
  set_tests_properties(ReaderLibFuzzer.Seeds PROPERTIES FIXTURES_SETUP reader_fuzzer_seeds
                                                     LABELS "long;libfuzzer")
  # 60 s of fuzzing. New inputs that widen the coverage go to corpus/ (kept from run to run); a
  # failing input is written to artifacts/ and fails the test. -malloc_limit_mb: no single
  # allocation over 64 MB for inputs of a few KB (the mutator test's bound is 16 MB + 64 x size).
  add_test(NAME ReaderLibFuzzer.SixtySeconds
    COMMAND reader_fuzzer -max_total_time=60 -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=64
            -print_final_stats=1 -artifact_prefix=${_fuzz_dir}/artifacts/
            ${_fuzz_dir}/corpus ${_fuzz_dir}/seeds ${PROJECT_SOURCE_DIR}/tests/data/fuzz/regressions)
  set_tests_properties(ReaderLibFuzzer.SixtySeconds PROPERTIES FIXTURES_REQUIRED reader_fuzzer_seeds
                                                            LABELS "long;libfuzzer" TIMEOUT 600)
endif()
