// The granstab command line: thin subcommands over the libraries (no physics here).
#include <CLI/CLI.hpp>
#include <iostream>

int main(int argc, char** argv) {
  CLI::App app{"granstab: quasistatic deformation of 2D granular packings, by molecular dynamics "
               "and by contact-network stability analysis"};
  app.require_subcommand(1);
  auto* version = app.add_subcommand("version", "Print the granstab version");
  version->callback([] { std::cout << "granstab " << GRANSTAB_VERSION << "\n"; });
  CLI11_PARSE(app, argc, argv);
  return 0;
}
