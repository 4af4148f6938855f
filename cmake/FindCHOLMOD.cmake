# Finds CHOLMOD. SuiteSparse >= 7 ships a CMake config; Debian 12 (SuiteSparse 5.12) ships
# neither a config nor a .pc file, so fall back to searching headers and libraries.
# Defines the imported target SuiteSparse::CHOLMOD.
if(TARGET SuiteSparse::CHOLMOD)
  set(CHOLMOD_FOUND TRUE)
  return()
endif()
find_package(CHOLMOD CONFIG QUIET)
if(CHOLMOD_FOUND AND TARGET SuiteSparse::CHOLMOD)
  return()
endif()

find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY cholmod)
find_library(SUITESPARSECONFIG_LIBRARY suitesparseconfig)
foreach(lib amd camd colamd ccolamd)
  string(TOUPPER ${lib} LIB)
  find_library(${LIB}_LIBRARY ${lib})
endforeach()
find_package(BLAS)
find_package(LAPACK)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(CHOLMOD REQUIRED_VARS CHOLMOD_LIBRARY CHOLMOD_INCLUDE_DIR
                                  SUITESPARSECONFIG_LIBRARY AMD_LIBRARY COLAMD_LIBRARY)
if(CHOLMOD_FOUND)
  add_library(SuiteSparse::CHOLMOD UNKNOWN IMPORTED)
  # Eigen includes <cholmod.h> unqualified, so the suitesparse folder itself goes on the path.
  set_target_properties(SuiteSparse::CHOLMOD PROPERTIES
    IMPORTED_LOCATION "${CHOLMOD_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}")
  set(_cholmod_deps ${AMD_LIBRARY} ${COLAMD_LIBRARY} ${SUITESPARSECONFIG_LIBRARY})
  foreach(opt CAMD_LIBRARY CCOLAMD_LIBRARY)
    if(${opt})
      list(APPEND _cholmod_deps ${${opt}})
    endif()
  endforeach()
  list(APPEND _cholmod_deps ${LAPACK_LIBRARIES} ${BLAS_LIBRARIES})
  set_property(TARGET SuiteSparse::CHOLMOD PROPERTY INTERFACE_LINK_LIBRARIES "${_cholmod_deps}")
endif()
mark_as_advanced(CHOLMOD_INCLUDE_DIR CHOLMOD_LIBRARY SUITESPARSECONFIG_LIBRARY)
