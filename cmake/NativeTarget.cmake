# The name a SHELLCONTRACT_NATIVE build (-march=native) gives its target in the build's identity
# (cmake/BuildIdentity.cmake): "native." and a hash of the instruction set and CPU that the
# compiler's -march=native picks on this machine. Such a build may round differently from the
# default one (FMA contraction, wider vectors in Eigen and in the compiler's own vectorization),
# and two such builds from one commit on two CPUs may round differently from each other; the
# identity is what checkpoints and a sweep's job ids compare, so it names the target. "native"
# alone where the compiler does not say what -march=native means (the build then cannot tell two
# CPUs apart).
function(shellcontract_native_tag compiler out)
  set(tag "native")
  # The driver's -### prints the compiler proper's command line without running it: GCC's with
  # the -march, -mtune and every -m<feature> it chose, Clang's with -target-cpu and
  # -target-feature. Nothing else of it (paths, cache sizes) goes into the hash.
  execute_process(COMMAND ${compiler} -march=native "-###" -E -x c++ /dev/null
                  RESULT_VARIABLE rc OUTPUT_VARIABLE text ERROR_VARIABLE text)
  if(rc EQUAL 0)
    string(REGEX MATCHALL "[ \"']-m[A-Za-z0-9=._+-]+|\"-target-(cpu|feature)\" \"[^\"]*\"" flags "${text}")
    if(flags)
      string(SHA256 hash "${flags}")
      string(SUBSTRING "${hash}" 0 8 hash)
      set(tag "native.${hash}")
    endif()
  endif()
  set(${out} "${tag}" PARENT_SCOPE)
endfunction()
