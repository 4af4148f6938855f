#include "provenance.hpp"

#include <dlfcn.h>

#include <filesystem>
#include <system_error>

namespace granstab::cli {

std::string granstab_version() { return GRANSTAB_VERSION; }

std::string blas_library() {
  void* dgemm = dlsym(RTLD_DEFAULT, "dgemm_");
  Dl_info info{};
  if (dgemm == nullptr || dladdr(dgemm, &info) == 0 || info.dli_fname == nullptr)
    return "not loaded";
  std::error_code error;
  const std::filesystem::path file = std::filesystem::canonical(info.dli_fname, error);
  return error ? std::string(info.dli_fname) : file.string();
}

}  // namespace granstab::cli
