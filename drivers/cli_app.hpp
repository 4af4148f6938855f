#pragma once
// The granstab command line as a library: every subcommand registered on one CLI11 app, and one
// run of it on an argument list. The executable (main.cpp) and the Python module
// (python/granstab_module.cpp) both call it, so they give the same outputs and messages.
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace granstab::cli {

// Registers every subcommand of drivers/commands.hpp on app.
void add_all_commands(CLI::App& app);

// Runs `granstab ARGS...` in this process (args without the program name). Throws what the
// command throws: CLI::ParseError for bad options, protocols::Interrupted on SIGINT / SIGTERM
// (checkpoint written), std::exception with the message the executable prints otherwise. `help`
// receives the text of --help (CLI11 reports it as a ParseError with exit code 0).
void run_command_line(const std::vector<std::string>& args, std::string* help = nullptr);

}  // namespace granstab::cli
