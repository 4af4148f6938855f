# The tests of static/ owned by the contact-network solver (STATIC.md §S4).
add_library(granstab_static_testing STATIC networks.cpp fd_tangent.cpp)
target_link_libraries(granstab_static_testing PUBLIC granstab_static)
granstab_add_test(test_tangent_fd
  SOURCES test_tangent_fd.cpp
  LIBS granstab_static_testing)
