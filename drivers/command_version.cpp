#include <CLI/CLI.hpp>
#include <iostream>

#include "commands.hpp"

namespace granstab::cli {

void add_version_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("version", "Print the granstab version");
  cmd->callback([] { std::cout << "granstab " << GRANSTAB_VERSION << "\n"; });
}

}  // namespace granstab::cli
