# Registers a GoogleTest binary's tests with CTest in groups: one CTest test runs up to
# CHUNK tests of one suite in one process (`--gtest_filter=Suite.A:Suite.B:...`).
#
# Why not one process per test (gtest_discover_tests): a test process of clhair_tests pays
# about 0.2 s to load its libraries and, on the device, 0.5-0.7 s to set up PoCL and build
# its programs from PoCL's cache before its first assertion. Over some 600 tests that was
# about half of the suite's time (bench/suite.md). Within a group the device and its programs
# are set up once.
#
# Suites whose name matches ALONE keep one CTest test per test, named as gtest_discover_tests
# names them (`Suite.Test`): the Oclgrind runs (each spends its time in a child process, and a
# group of them would be the run's longest pole) and the suites that dev.sh splits between the
# Release and the sanitized builds by test name.
#
# Run after every build of the binary (POST_BUILD, like gtest_discover_tests' default), with
#   -D TEST_EXECUTABLE=path  -D OUT=file.cmake  -D ALONE=regex  -D CHUNK=n  -D TIMEOUT=s
#   -D WORKDIR=dir
# OUT is included by CTest through the directory's TEST_INCLUDE_FILES.

foreach(var TEST_EXECUTABLE OUT ALONE CHUNK TIMEOUT WORKDIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "TestGroups.cmake: ${var} is not set")
  endif()
endforeach()

execute_process(COMMAND "${TEST_EXECUTABLE}" --gtest_list_tests
                WORKING_DIRECTORY "${WORKDIR}"
                OUTPUT_VARIABLE listing ERROR_VARIABLE listing_err RESULT_VARIABLE rc
                TIMEOUT 60)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "TestGroups.cmake: ${TEST_EXECUTABLE} --gtest_list_tests failed (${rc}):\n"
                      "${listing}${listing_err}")
endif()

# CMake lists split on ';': keep the listing's lines apart with a placeholder first
string(REPLACE ";" "\\;" listing "${listing}")
string(REPLACE "\n" ";" lines "${listing}")

set(script "# Written by cmake/TestGroups.cmake from ${TEST_EXECUTABLE} --gtest_list_tests\n")
set(suite "")
set(tests "")
set(ngroups 0)

# Writes the add_test lines of the suite gathered so far.
macro(flush_suite)
  if(NOT suite STREQUAL "" AND tests)
    list(LENGTH tests count)
    if(suite MATCHES "${ALONE}")
      foreach(t IN LISTS tests)
        # Oclgrind's tests (ALONE) run for 5-30 s each: start them first (CTest orders a
        # fresh run, without its own measured costs, by COST)
        string(APPEND script
               "add_test([==[${suite}.${t}]==] \"${TEST_EXECUTABLE}\" [==[--gtest_filter=${suite}.${t}]==])\n"
               "set_tests_properties([==[${suite}.${t}]==] PROPERTIES WORKING_DIRECTORY \"${WORKDIR}\""
               " TIMEOUT ${TIMEOUT} COST 50 SKIP_REGULAR_EXPRESSION [==[\\[  SKIPPED \\]]==])\n")
        math(EXPR ngroups "${ngroups} + 1")
      endforeach()
    else()
      math(EXPR nchunks "(${count} + ${CHUNK} - 1) / ${CHUNK}")
      set(i 0)
      set(chunk 1)
      set(filter "")
      set(in_chunk 0)
      foreach(t IN LISTS tests)
        if(filter STREQUAL "")
          set(filter "${suite}.${t}")
        else()
          string(APPEND filter ":${suite}.${t}")
        endif()
        math(EXPR i "${i} + 1")
        math(EXPR in_chunk "${in_chunk} + 1")
        if(in_chunk EQUAL CHUNK OR i EQUAL count)
          if(nchunks EQUAL 1)
            set(name "${suite}.*")
          else()
            set(name "${suite}.* ${chunk}/${nchunks}")
          endif()
          string(APPEND script
                 "add_test([==[${name}]==] \"${TEST_EXECUTABLE}\" [==[--gtest_filter=${filter}]==])\n"
                 "set_tests_properties([==[${name}]==] PROPERTIES WORKING_DIRECTORY \"${WORKDIR}\""
                 " TIMEOUT ${TIMEOUT} COST ${in_chunk})\n")
          math(EXPR ngroups "${ngroups} + 1")
          math(EXPR chunk "${chunk} + 1")
          set(filter "")
          set(in_chunk 0)
        endif()
      endforeach()
    endif()
  endif()
endmacro()

foreach(line IN LISTS lines)
  if(line MATCHES "^  ([^ ]+)")          # a test: "  Name" or "  Name/0  # GetParam() = ..."
    list(APPEND tests "${CMAKE_MATCH_1}")
  elseif(line MATCHES "^([^ ]+)\\.")     # a suite: "Suite." or "Prefix/Suite.  # TypeParam..."
    set(next "${CMAKE_MATCH_1}")  # flush_suite's own matches overwrite CMAKE_MATCH_1
    flush_suite()
    set(suite "${next}")
    set(tests "")
  endif()
endforeach()
flush_suite()

if(ngroups EQUAL 0)
  message(FATAL_ERROR "TestGroups.cmake: ${TEST_EXECUTABLE} lists no tests:\n${listing}")
endif()
file(WRITE "${OUT}.tmp" "${script}")
file(RENAME "${OUT}.tmp" "${OUT}")
