#include "cli_app.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <sstream>

#include "commands.hpp"
#include "resumable.hpp"

namespace granstab::cli {

void add_all_commands(CLI::App& app) {
  app.require_subcommand(1);
  add_version_command(app);
  add_info_command(app);
  add_prepare_command(app);
  add_biaxial_command(app);
  add_creep_command(app);
  add_perturb_command(app);
  add_q1_command(app);
  add_compare_command(app);
  add_sic_command(app);
  add_probe_command(app);
  add_plot_command(app);
  add_resume_command(app);
  add_study_command(app);
}

void run_command_line(const std::vector<std::string>& args, std::string* help) {
  CLI::App app{"granstab"};
  add_all_commands(app);
  command_line() = args;
  std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11's order
  try {
    app.parse(reversed);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() != 0 || !help) throw;
    std::ostringstream out, err;
    app.exit(e, out, err);
    *help = out.str();
  }
}

}  // namespace granstab::cli
