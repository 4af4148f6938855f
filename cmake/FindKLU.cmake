# Finds KLU (SuiteSparse >= 7 config first, then a plain search as on Debian 12).
# Defines the imported target SuiteSparse::KLU.
if(TARGET SuiteSparse::KLU)
  set(KLU_FOUND TRUE)
  return()
endif()
find_package(KLU CONFIG QUIET)
if(KLU_FOUND AND TARGET SuiteSparse::KLU)
  return()
endif()

find_path(KLU_INCLUDE_DIR klu.h PATH_SUFFIXES suitesparse)
find_library(KLU_LIBRARY klu)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(KLU REQUIRED_VARS KLU_LIBRARY KLU_INCLUDE_DIR)
if(KLU_FOUND)
  add_library(SuiteSparse::KLU UNKNOWN IMPORTED)
  set_target_properties(SuiteSparse::KLU PROPERTIES
    IMPORTED_LOCATION "${KLU_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${KLU_INCLUDE_DIR}")
endif()
mark_as_advanced(KLU_INCLUDE_DIR KLU_LIBRARY)
