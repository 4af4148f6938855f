// granstab resume CHECKPOINT: continues a run of prepare, biaxial, creep or perturb from the
// checkpoint it wrote (periodically, or on SIGINT / SIGTERM, or at a blow-up). The run goes on
// in the working directory it was started in, with the settings text stored in the checkpoint,
// and its outputs end identical to the bit to those of an uninterrupted run
// (docs/reliability.md).
#include <CLI/CLI.hpp>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include "commands.hpp"
#include "resumable.hpp"

namespace granstab::cli {
namespace {

struct ResumeOptions {
  std::string checkpoint;
  bool quiet = false;
};

void run_resume(const ResumeOptions& o) {
  // Read before changing directory: the path is relative to where resume was started.
  const protocols::Checkpoint checkpoint =
      protocols::Checkpoint::read(std::filesystem::absolute(o.checkpoint));
  const protocols::Invocation invocation = protocols::Invocation::get(checkpoint);
  std::error_code error;
  std::filesystem::current_path(invocation.working_directory, error);
  if (error) {
    throw std::runtime_error(o.checkpoint + ": cannot enter the run's working directory " +
                             invocation.working_directory.string() + ": " + error.message());
  }
  if (invocation.command == "prepare") {
    run_prepare(invocation, o.quiet, &checkpoint);
  } else if (invocation.command == "biaxial") {
    run_biaxial(invocation, o.quiet, &checkpoint);
  } else if (invocation.command == "creep") {
    run_creep(invocation, o.quiet, &checkpoint);
  } else if (invocation.command == "perturb") {
    run_perturb(invocation, o.quiet, &checkpoint);
  } else {
    throw std::runtime_error(o.checkpoint + ": unknown command '" + invocation.command + "'");
  }
}

}  // namespace

void add_resume_command(CLI::App& app) {
  auto options = std::make_shared<ResumeOptions>();
  auto* cmd = app.add_subcommand(
      "resume", "Continue a prepare, biaxial, creep or perturb run from its checkpoint");
  cmd->add_option("CHECKPOINT", options->checkpoint, "checkpoint file written by the run")
      ->required();
  cmd->add_flag("--quiet", options->quiet, "no progress on stderr");
  cmd->callback([options] { run_resume(*options); });
}

}  // namespace granstab::cli
