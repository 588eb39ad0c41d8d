# Writes one CTest test per GoogleTest suite of TEST_EXE into OUT
# (cmake -DTEST_EXE=... -DOUT=... -P discover_suites.cmake; run after each
# link of the test binary). Every test process starts by loading and
# relocating about 270 shared libraries (OpenImageIO's), half a second of
# CPU: one process per suite instead of one per test saves that 400 times.
# The value-parameterised hostile-input suite runs in shards of its own. A
# suite none of whose tests ran (each skipped itself, e.g. RealData without
# ../shared/realdata) is reported as skipped, not as passed.
cmake_minimum_required(VERSION 3.22)
execute_process(COMMAND "${TEST_EXE}" --gtest_list_tests OUTPUT_VARIABLE listing RESULT_VARIABLE rc
                TIMEOUT 60)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${TEST_EXE} --gtest_list_tests failed (${rc})")
endif()
string(REPLACE "\n" ";" lines "${listing}")
set(script "")
set(suites 0)
foreach(line IN LISTS lines)
  # Suite lines are "Name." at column 0; tests are indented.
  if(line MATCHES "^([A-Za-z0-9_]+)\\.$")
    set(suite "${CMAKE_MATCH_1}")
    string(APPEND script
           "add_test(${suite} \"${TEST_EXE}\" --gtest_filter=${suite}.* --gtest_brief=1)\n"
           "set_tests_properties(${suite} PROPERTIES TIMEOUT 600 SKIP_REGULAR_EXPRESSION \"\\\\[  PASSED  \\\\] 0 tests\")\n")
    math(EXPR suites "${suites} + 1")
  endif()
endforeach()
if(suites LESS 10)
  message(FATAL_ERROR "only ${suites} test suites found in ${TEST_EXE}")
endif()
file(WRITE "${OUT}" "${script}")
