include(GoogleTest)

# One precompiled <gtest/gtest.h> for every test executable: parsing it costs ~2.5 s of CPU per
# test source at -O2, nearly half of a typical test's compile (docs/reliability.md, "CI time").
# The tests reuse the header compiled once for granstab_test_pch (REUSE_FROM), which GCC accepts
# only when the flags that define macros match: every test therefore compiles with OpenMP, as the
# tests of dynamic/ do anyway through granstab_dynamic (a header compiled without _OPENMP is
# refused where it is defined). CMake adds -Winvalid-pch, so with GRANSTAB_WERROR a refused header
# fails the build instead of silently costing the time again. GRANSTAB_TEST_PCH=OFF turns it off.
option(GRANSTAB_TEST_PCH "Share one precompiled gtest header between the tests" ON)
if(GRANSTAB_TEST_PCH)
  file(CONFIGURE OUTPUT ${CMAKE_BINARY_DIR}/granstab_test_pch.cpp
       CONTENT "// the precompiled header of the tests (cmake/GranstabTesting.cmake)\n")
  add_library(granstab_test_pch OBJECT ${CMAKE_BINARY_DIR}/granstab_test_pch.cpp)
  target_link_libraries(granstab_test_pch PRIVATE GTest::gtest OpenMP::OpenMP_CXX)
  target_precompile_headers(granstab_test_pch PRIVATE <gtest/gtest.h>)
  # GCC refuses a header compiled with -fPIC in a -fPIE compile: with the Python module on
  # (CMAKE_POSITION_INDEPENDENT_CODE) the header and the tests both compile without either flag.
  set_target_properties(granstab_test_pch PROPERTIES POSITION_INDEPENDENT_CODE OFF)
endif()

# granstab_add_test(NAME SOURCES src... LIBS lib... [THREADS n] [LABELS l...])
# Every test runs with OMP_NUM_THREADS set explicitly (2-core machine; DEPS.md #8) and knows the
# source tree as the compile definition GRANSTAB_SOURCE_DIR (shipped samples live in data/).
function(granstab_add_test name)
  cmake_parse_arguments(T "" "THREADS" "SOURCES;LIBS;LABELS" ${ARGN})
  if(NOT T_THREADS)
    set(T_THREADS 1)
  endif()
  add_executable(${name} ${T_SOURCES})
  target_link_libraries(${name} PRIVATE ${T_LIBS} GTest::gtest GTest::gtest_main)
  target_compile_definitions(${name} PRIVATE GRANSTAB_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  if(GRANSTAB_TEST_PCH)
    target_link_libraries(${name} PRIVATE OpenMP::OpenMP_CXX)
    target_precompile_headers(${name} REUSE_FROM granstab_test_pch)
    set_target_properties(${name} PROPERTIES POSITION_INDEPENDENT_CODE OFF)
  endif()
  gtest_discover_tests(${name}
    DISCOVERY_MODE PRE_TEST
    WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}
    PROPERTIES ENVIRONMENT "OMP_NUM_THREADS=${T_THREADS}"
               LABELS "${T_LABELS}")
endfunction()
