#pragma once
// One function per subcommand, each in its own drivers/command_<name>.cpp: it declares its options
// on the CLI11 subcommand and sets the callback. Drivers parse, build objects, call the libraries
// and write outputs; no physics lives here.
namespace CLI {
class App;
}

namespace granstab::cli {

void add_version_command(CLI::App& app);
void add_info_command(CLI::App& app);
void add_prepare_command(CLI::App& app);
void add_biaxial_command(CLI::App& app);
void add_creep_command(CLI::App& app);
void add_perturb_command(CLI::App& app);
void add_q1_command(CLI::App& app);
void add_compare_command(CLI::App& app);
void add_sic_command(CLI::App& app);
void add_probe_command(CLI::App& app);
void add_plot_command(CLI::App& app);
void add_resume_command(CLI::App& app);
void add_study_command(CLI::App& app);

}  // namespace granstab::cli
