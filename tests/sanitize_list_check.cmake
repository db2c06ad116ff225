# Checks that every name in PACKSIM_SANITIZE_PHYSICS_TESTS (tests/CMakeLists.txt) is a
# registered ctest test with the `sanitize` label. A renamed or removed test, or a renamed
# bundled scenario, would otherwise drop out of the sanitizer pass without a word: the
# gtest filter simply matches nothing.
#   cmake -DBUILD=<build dir> -DNAMES=<names joined by ':'> -P sanitize_list_check.cmake
if(NOT BUILD OR NOT NAMES)
  message(FATAL_ERROR "sanitize_list_check: BUILD and NAMES are required")
endif()
execute_process(COMMAND "${CMAKE_CTEST_COMMAND}" --test-dir "${BUILD}" -N -L sanitize -LE quick
                OUTPUT_VARIABLE listed RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "sanitize_list_check: ctest -N failed (${rc})")
endif()
string(REPLACE ":" ";" names "${NAMES}")
list(LENGTH names expected)
set(missing "")
foreach(name IN LISTS names)
  string(FIND "${listed}" ": ${name}\n" at)
  if(at EQUAL -1)
    list(APPEND missing "${name}")
  endif()
endforeach()
string(REGEX MATCH "Total Tests: ([0-9]+)" _ "${listed}")
set(registered "${CMAKE_MATCH_1}")
if(missing)
  list(JOIN missing "\n  " missing)
  message(FATAL_ERROR "PACKSIM_SANITIZE_PHYSICS_TESTS (tests/CMakeLists.txt) names tests that are "
                      "not registered, so the sanitizer pass no longer runs them:\n  ${missing}\n"
                      "Rename them in the list, or pick replacements as docs/hardening.md describes.")
endif()
if(NOT registered EQUAL expected)
  message(FATAL_ERROR "sanitize_list_check: ${registered} physics tests carry the sanitize label, "
                      "the list names ${expected}")
endif()
message(STATUS "sanitize_list_check: all ${expected} listed physics tests are registered with the sanitize label")
