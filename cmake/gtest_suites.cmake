# Registers one ctest test per GoogleTest suite of TEST_BINARY, written to OUTPUT (a ctest include
# file; CMakeLists.txt runs this after each build of the tests). A process per suite, not per
# test: each start of heightmarch-tests costs 0.6-0.8 s of CPU before any test runs, most of it
# loading the 261 shared libraries that OpenImageIO brings (measured with a one-test filter).
# ctest -R SUITE still picks a suite; --gtest_filter picks a test.
execute_process(COMMAND ${TEST_BINARY} --gtest_list_tests OUTPUT_VARIABLE listing RESULT_VARIABLE status
                TIMEOUT 120)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${TEST_BINARY} --gtest_list_tests: ${status}")
endif()
string(REPLACE "\n" ";" lines "${listing}")
set(content "")
foreach(line IN LISTS lines)
  # A suite's line: its name and a dot ("Cli.", "AllIsas/PacketSamplerTest."); tests are indented.
  if(line MATCHES "^([A-Za-z0-9_/]+)\\.")
    set(suite ${CMAKE_MATCH_1})
    string(APPEND content "add_test([=[${suite}]=] [=[${TEST_BINARY}]=] [=[--gtest_filter=${suite}.*]=] --gtest_brief=1)\n"
           "set_tests_properties([=[${suite}]=] PROPERTIES TIMEOUT 1500 LABELS fast)\n")
  endif()
endforeach()
file(WRITE ${OUTPUT} "${content}")
