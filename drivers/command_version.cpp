#include <CLI/CLI.hpp>
#include <iostream>

#include "commands.hpp"
#include "provenance.hpp"

namespace granstab::cli {

void add_version_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("version", "Print the granstab version and the BLAS in use");
  cmd->callback([] {
    std::cout << "granstab " << granstab_version() << "\n";
    std::cout << "BLAS: " << blas_library() << "\n";
  });
}

}  // namespace granstab::cli
