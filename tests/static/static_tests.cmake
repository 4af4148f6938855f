# The tests of static/ owned by the contact-network solver (STATIC.md §S4).
add_library(granstab_static_testing STATIC networks.cpp fd_tangent.cpp)
target_link_libraries(granstab_static_testing PUBLIC granstab_static)
granstab_add_test(test_tangent_fd
  SOURCES test_tangent_fd.cpp
  LIBS granstab_static_testing)
granstab_add_test(test_tangent_invariants
  SOURCES test_tangent_invariants.cpp
  LIBS granstab_static_testing)
granstab_add_test(test_lattice_and_work
  SOURCES test_lattice_and_work.cpp
  LIBS granstab_static_testing)
granstab_add_test(test_stability_thresholds
  SOURCES test_stability_thresholds.cpp
  LIBS granstab_static_testing)
granstab_add_test(test_load_stepping
  SOURCES test_load_stepping.cpp
  LIBS granstab_static_testing granstab_dense_reference)
granstab_add_test(test_hill_and_samples
  SOURCES test_hill_and_samples.cpp
  LIBS granstab_static granstab_dense_reference)
target_compile_definitions(test_hill_and_samples PRIVATE
  GRANSTAB_SAMPLES_DIR="${PROJECT_SOURCE_DIR}/data/samples")
granstab_add_test(test_q1_command
  SOURCES test_q1_command.cpp
  LIBS granstab_test_support)
target_compile_definitions(test_q1_command PRIVATE
  GRANSTAB_SAMPLES_DIR="${PROJECT_SOURCE_DIR}/data/samples")
granstab_add_test(test_closing_contacts
  SOURCES test_closing_contacts.cpp
  LIBS granstab_static)
