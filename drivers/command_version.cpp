#include <dlfcn.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>
#include <string>

#include "commands.hpp"

namespace granstab::cli {
namespace {

// The file that provides dgemm_ in this process: the BLAS under UMFPACK's and CHOLMOD's dense
// fronts, which sets both their speed and their round-off (docs/static.md, "Performance").
std::string blas_library() {
  void* dgemm = dlsym(RTLD_DEFAULT, "dgemm_");
  Dl_info info{};
  if (dgemm == nullptr || dladdr(dgemm, &info) == 0 || info.dli_fname == nullptr)
    return "not loaded";
  std::error_code error;  // the file behind Debian's alternatives link, where it resolves
  const std::filesystem::path file = std::filesystem::canonical(info.dli_fname, error);
  return error ? std::string(info.dli_fname) : file.string();
}

}  // namespace

void add_version_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("version", "Print the granstab version and the BLAS in use");
  cmd->callback([] {
    std::cout << "granstab " << GRANSTAB_VERSION << "\n";
    std::cout << "BLAS: " << blas_library() << "\n";
  });
}

}  // namespace granstab::cli
