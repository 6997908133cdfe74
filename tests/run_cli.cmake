# Runs one terrapatch command line and checks its exit status and output.
#   cmake -DEXE=<path> -DARGS=<args separated by '|'> -DEXPECT_RC=<n>
#         [-DMATCH=<regexes separated by '|'>] -P run_cli.cmake
# Every MATCH regex must be found in stdout + stderr (a '|' cannot appear inside one).
if(NOT DEFINED EXE OR NOT DEFINED EXPECT_RC)
  message(FATAL_ERROR "run_cli.cmake needs -DEXE and -DEXPECT_RC")
endif()
set(args "")
if(DEFINED ARGS AND NOT ARGS STREQUAL "")
  string(REPLACE "|" ";" args "${ARGS}")
endif()
execute_process(COMMAND "${EXE}" ${args}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(all "${out}${err}")
if(NOT rc STREQUAL "${EXPECT_RC}")
  message(FATAL_ERROR "terrapatch ${args}: exit status ${rc}, expected ${EXPECT_RC}\n--- output ---\n${all}")
endif()
if(DEFINED MATCH AND NOT MATCH STREQUAL "")
  string(REPLACE "|" ";" regexes "${MATCH}")
  foreach(re IN LISTS regexes)
    if(NOT all MATCHES "${re}")
      message(FATAL_ERROR "terrapatch ${args}: output does not match '${re}'\n--- output ---\n${all}")
    endif()
  endforeach()
endif()
message(STATUS "terrapatch ${args}: exit status ${rc} as expected")
