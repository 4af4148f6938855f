include(GoogleTest)
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
  gtest_discover_tests(${name}
    DISCOVERY_MODE PRE_TEST
    WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}
    PROPERTIES ENVIRONMENT "OMP_NUM_THREADS=${T_THREADS}"
               LABELS "${T_LABELS}")
endfunction()
