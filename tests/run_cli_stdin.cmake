# Runs one terrapatch command line with a given standard input and checks its exit status,
# its exact standard output and (optionally) its standard error.
#   cmake -DEXE=<path> -DARGS=<args separated by '|'> -DINPUT=<input lines separated by '|'>
#         -DEXPECT_RC=<n> -DEXPECT_STDOUT=<output lines separated by '|'>
#         [-DSTDERR_MATCH=<regex>] -DINPUT_FILE=<where to write the input> -P run_cli_stdin.cmake
# Every input line gets a newline; stdout must equal EXPECT_STDOUT line for line (no regex).
if(NOT DEFINED EXE OR NOT DEFINED EXPECT_RC OR NOT DEFINED INPUT_FILE)
  message(FATAL_ERROR "run_cli_stdin.cmake needs -DEXE, -DEXPECT_RC and -DINPUT_FILE")
endif()
set(args "")
if(DEFINED ARGS AND NOT ARGS STREQUAL "")
  string(REPLACE "|" ";" args "${ARGS}")
endif()
set(text "")
if(DEFINED INPUT)
  string(REPLACE "|" "\n" text "${INPUT}")
  set(text "${text}\n")
endif()
file(WRITE "${INPUT_FILE}" "${text}")
execute_process(COMMAND "${EXE}" ${args} INPUT_FILE "${INPUT_FILE}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
string(REPLACE "\n" "|" got "${out}")
string(REGEX REPLACE "\\|$" "" got "${got}")
set(report "--- stdout ---\n${out}--- stderr ---\n${err}")
if(NOT rc STREQUAL "${EXPECT_RC}")
  message(FATAL_ERROR "terrapatch ${args}: exit status ${rc}, expected ${EXPECT_RC}\n${report}")
endif()
if(DEFINED EXPECT_STDOUT AND NOT got STREQUAL "${EXPECT_STDOUT}")
  message(FATAL_ERROR "terrapatch ${args}: stdout differs\nexpected: ${EXPECT_STDOUT}\n"
                      "got:      ${got}\n${report}")
endif()
if(DEFINED STDERR_MATCH AND NOT STDERR_MATCH STREQUAL "" AND NOT err MATCHES "${STDERR_MATCH}")
  message(FATAL_ERROR "terrapatch ${args}: stderr does not match '${STDERR_MATCH}'\n${report}")
endif()
message(STATUS "terrapatch ${args}: exit status ${rc} and output as expected")
