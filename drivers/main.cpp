// The granstab command line. Subcommands register themselves from drivers/command_*.cpp.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

#include "cli_app.hpp"
#include "dynamic/protocols/run_guard.hpp"
#include "resumable.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "granstab: quasistatic deformation of 2D granular packings, by molecular dynamics "
      "and by contact-network stability analysis"};
  granstab::cli::add_all_commands(app);
  granstab::cli::command_line().assign(argv + 1, argv + argc);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const granstab::protocols::Interrupted& e) {
    // SIGINT / SIGTERM: the checkpoint is written; 128 + signal as a shell would report.
    std::cerr << "granstab: " << e.what() << "\n";
    return e.exit_code();
  } catch (const std::exception& e) {
    // Library errors name the file, line or field; the driver adds only the program name.
    std::cerr << "granstab: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
