# Checks the test suite itself: a skipped test must not look like a pass.
#   cmake -DCTEST=<ctest> -DBUILD_DIR=<dir> -DSHARED_DATA=<dir> -DSAMPLE_DATA=<dir>
#         -DALLOW_SKIP=<ON|OFF> -P check_suite.cmake
# Fails when the real data the tests read is not there (the repository's data/, or wherever
# TP_DATA_DIR points), or when any registered test would count exit 77 as a skip although
# skips are not allowed (TP_TESTS_ALLOW_SKIP is OFF, as in `make test` and CI).
foreach(dir IN ITEMS "${SHARED_DATA}" "${SAMPLE_DATA}")
  if(NOT EXISTS "${dir}/PROVENANCE.md")
    message(FATAL_ERROR "${dir}: the test data is not there (the tests that read it fail); "
            "it is the repository's data/ unless -DTP_DATA_DIR says otherwise")
  endif()
endforeach()
if(NOT EXISTS "${SHARED_DATA}/coord/geoconvert_ctest_cases.tsv")
  message(FATAL_ERROR "${SHARED_DATA}/coord: the coordinate test sets are not there")
endif()

execute_process(COMMAND "${CTEST}" --show-only=json-v1 WORKING_DIRECTORY "${BUILD_DIR}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE json ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "ctest --show-only=json-v1 failed (${rc}): ${err}")
endif()
execute_process(COMMAND "${CTEST}" -N WORKING_DIRECTORY "${BUILD_DIR}" OUTPUT_VARIABLE listing)
string(REGEX MATCH "Total Tests: ([0-9]+)" _ "${listing}")
set(ntests "${CMAKE_MATCH_1}")
if(ntests LESS 100)
  message(FATAL_ERROR "only ${ntests} tests are registered: some were left out")
endif()
# (a regular expression, not string(JSON): that re-parses the whole document per call)
string(REGEX MATCHALL "\"SKIP_(RETURN_CODE|REGULAR_EXPRESSION)\"" skippable "${json}")
list(LENGTH skippable nskippable)
if(nskippable GREATER 0 AND NOT ALLOW_SKIP)
  message(FATAL_ERROR "${nskippable} of ${ntests} tests count a skip (exit 77) as not failed; "
          "only a build with -DTP_TESTS_ALLOW_SKIP=ON may do that")
endif()
message(STATUS "${ntests} tests registered, ${nskippable} may skip; data in ${SHARED_DATA}")
