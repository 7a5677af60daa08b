# cmake -P script: runs COMMAND (a ;-list), and fails unless its exit code is RC, its output
# matches EXPECT and, where given, does not match REFUSE. For the example's refusals, whose exit
# code and words are what they promise.
execute_process(COMMAND ${COMMAND} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(all "${out}${err}")
if(NOT rc STREQUAL RC)
  message(FATAL_ERROR "exit code ${rc}, expected ${RC}:\n${all}")
endif()
if(NOT all MATCHES "${EXPECT}")
  message(FATAL_ERROR "the output does not say '${EXPECT}':\n${all}")
endif()
if(DEFINED REFUSE AND all MATCHES "${REFUSE}")
  message(FATAL_ERROR "the output says '${REFUSE}':\n${all}")
endif()
