// granstab resume CHECKPOINT: continues a run of prepare, biaxial, creep, perturb or compare from
// the checkpoint it wrote (periodically, or on SIGINT / SIGTERM, or at a blow-up). The run goes on
// in the working directory it was started in, with the settings text stored in the checkpoint,
// and its outputs end identical to the bit to those of an uninterrupted run; --set may change the
// settings that do not enter the checkpointed state (docs/reliability.md).
#include <CLI/CLI.hpp>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"
#include "resumable.hpp"

namespace granstab::cli {
namespace {

struct ResumeOptions {
  std::string checkpoint;
  std::vector<std::string> overrides;
  bool quiet = false;
};

void run_resume(const ResumeOptions& o) {
  // Read before changing directory: the path is relative to where resume was started.
  const std::filesystem::path path = std::filesystem::absolute(o.checkpoint);
  const protocols::Checkpoint checkpoint = protocols::Checkpoint::read(path);
  protocols::Invocation invocation = protocols::Invocation::get(checkpoint);
  invocation.add_resume_overrides(o.overrides);
  std::error_code error;
  std::filesystem::current_path(invocation.working_directory, error);
  if (error) {
    throw std::runtime_error(o.checkpoint + ": cannot enter the run's working directory " +
                             invocation.working_directory.string() + ": " + error.message());
  }
  protocols::remove_stale_temporaries(invocation.named_outputs());  // compare: its own
  if (invocation.command == "prepare") {
    run_prepare(invocation, o.quiet, &checkpoint);
  } else if (invocation.command == "biaxial") {
    run_biaxial(invocation, o.quiet, &checkpoint);
  } else if (invocation.command == "creep") {
    run_creep(invocation, o.quiet, &checkpoint);
  } else if (invocation.command == "perturb") {
    run_perturb(invocation, o.quiet, &checkpoint);
  } else if (invocation.command == "compare") {
    run_compare(invocation, &checkpoint);
  } else {
    throw std::runtime_error(o.checkpoint + ": unknown command '" + invocation.command + "'");
  }
  // The run finished (a stop or a blow-up throws): the checkpoint it was resumed from is stale
  // too, also when the run wrote none of its own or wrote them elsewhere (--set checkpoint.path).
  std::error_code ignored;
  std::filesystem::remove(path, ignored);
}

}  // namespace

void add_resume_command(CLI::App& app) {
  auto options = std::make_shared<ResumeOptions>();
  auto* cmd = app.add_subcommand(
      "resume", "Continue a prepare, biaxial, creep, perturb or compare run from its checkpoint");
  cmd->add_option("CHECKPOINT", options->checkpoint, "checkpoint file written by the run")
      ->required();
  cmd->add_option("--set", options->overrides,
                  "key=value: change a setting that may change in the middle of a run "
                  "(engine.dt_fraction, sanity.*, checkpoint.*; docs/reliability.md)");
  cmd->add_flag("--quiet", options->quiet, "no progress on stderr");
  cmd->callback([options] { run_resume(*options); });
}

}  // namespace granstab::cli
