# Sanitizer and fuzzing builds (issue 8). Included by the top-level CMakeLists.txt when
# AERIAL_SANITIZE or AERIAL_FUZZ is on; both need clang (Debian: clang, libclang-rt-14-dev).
#
#   AERIAL_SANITIZE  every target compiled and linked with AddressSanitizer (with LeakSanitizer)
#                    and UndefinedBehaviorSanitizer; the first finding aborts the process.
#   AERIAL_FUZZ      also the libFuzzer targets of tests/fuzz; every target gets libFuzzer's
#                    coverage instrumentation so that the fuzzers see inside the module.
if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "AERIAL_SANITIZE and AERIAL_FUZZ need clang (libFuzzer, the sanitizer "
                        "runtimes): configure with -DCMAKE_CXX_COMPILER=clang++; this is "
                        "${CMAKE_CXX_COMPILER_ID} ${CMAKE_CXX_COMPILER}")
endif()

set(AERIAL_SANITIZE_FLAGS -fsanitize=address,undefined -fno-sanitize-recover=all
                          -fno-omit-frame-pointer)
add_compile_options(${AERIAL_SANITIZE_FLAGS} -gline-tables-only)
add_link_options(${AERIAL_SANITIZE_FLAGS})
if(AERIAL_FUZZ)
    add_compile_options(-fsanitize=fuzzer-no-link)
endif()

# The runtime options every sanitized process of the test suite runs with (CTest ENVIRONMENT).
# Leaks inside Mesa and LLVM (llvmpipe) are suppressed in tests/sanitize/lsan.supp, never ours.
set(AERIAL_SANITIZE_ENV
    "ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1"
    "UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1"
    "LSAN_OPTIONS=suppressions=${PROJECT_SOURCE_DIR}/tests/sanitize/lsan.supp:print_suppressions=0")

# CTest sets them before it runs any test (a file CTest includes), so that
# `ctest --test-dir build-sanitize` needs nothing else; variables already set win.
file(WRITE ${CMAKE_BINARY_DIR}/aerial_sanitize_env.cmake "")
foreach(assignment IN LISTS AERIAL_SANITIZE_ENV)
    string(REGEX MATCH "^[A-Z_]+" variable "${assignment}")
    string(LENGTH "${variable}=" prefix)
    string(SUBSTRING "${assignment}" ${prefix} -1 value)
    file(APPEND ${CMAKE_BINARY_DIR}/aerial_sanitize_env.cmake
         "if(NOT DEFINED ENV{${variable}})\n    set(ENV{${variable}} \"${value}\")\nendif()\n")
endforeach()
set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES
             ${CMAKE_BINARY_DIR}/aerial_sanitize_env.cmake)
