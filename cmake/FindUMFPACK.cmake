# Finds UMFPACK (SuiteSparse >= 7 config first, then a plain search as on Debian 12).
# Defines the imported target SuiteSparse::UMFPACK.
if(TARGET SuiteSparse::UMFPACK)
  set(UMFPACK_FOUND TRUE)
  return()
endif()
find_package(UMFPACK CONFIG QUIET)
if(UMFPACK_FOUND AND TARGET SuiteSparse::UMFPACK)
  return()
endif()

find_package(CHOLMOD REQUIRED)  # UMFPACK links CHOLMOD for its orderings
find_path(UMFPACK_INCLUDE_DIR umfpack.h PATH_SUFFIXES suitesparse)
find_library(UMFPACK_LIBRARY umfpack)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(UMFPACK REQUIRED_VARS UMFPACK_LIBRARY UMFPACK_INCLUDE_DIR)
if(UMFPACK_FOUND)
  add_library(SuiteSparse::UMFPACK UNKNOWN IMPORTED)
  set_target_properties(SuiteSparse::UMFPACK PROPERTIES
    IMPORTED_LOCATION "${UMFPACK_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${UMFPACK_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES SuiteSparse::CHOLMOD)
endif()
mark_as_advanced(UMFPACK_INCLUDE_DIR UMFPACK_LIBRARY)
