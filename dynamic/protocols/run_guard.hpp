#pragma once
// What every long protocol run does besides its physics (issue #8, docs/reliability.md):
// periodic checkpoints, a clean stop on SIGINT / SIGTERM, and the physical sanity guards of
// dynamic/sanity.hpp. The protocol loops call LoopHooks at their safe points; the command behind
// them owns one RunGuard and builds the checkpoint (engine state + cursor + its own counters).
#include <chrono>
#include <csignal>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "checkpoint.hpp"
#include "common/io/csv_writer.hpp"
#include "common/run_config.hpp"
#include "dynamic/engine.hpp"
#include "dynamic/sanity.hpp"

namespace granstab::protocols {

struct GuardSettings {
  std::filesystem::path checkpoint;         // [checkpoint] path; default: beside the main output
  std::uint64_t every_steps = 0;            // [checkpoint] every_steps; 0: not by steps
  double every_seconds = 300.0;             // [checkpoint] every_seconds; 0: not by time
  dynamic::SanityLimits sanity;             // [sanity] max_overlap_fraction, max_kinetic_energy
  std::uint64_t sanity_every_steps = 1000;  // [sanity] every_steps
};

// Reads [checkpoint] and [sanity] (docs/reliability.md).
GuardSettings read_guard_settings(RunConfig& rc, const std::filesystem::path& default_checkpoint);

// SIGINT or SIGTERM arrived: the final checkpoint is written. exit_code is 128 + signal.
class Interrupted : public std::runtime_error {
 public:
  Interrupted(int signal, const std::string& what) : std::runtime_error(what), signal_(signal) {}
  int signal() const { return signal_; }
  int exit_code() const { return 128 + signal_; }

 private:
  int signal_;
};

// The state blew up (dynamic/sanity.hpp); the last sane state is in the checkpoint, if any.
class BlewUp : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// How the run was started: what `granstab resume` needs to start it again. The settings text is
// kept whole, so editing the settings file afterwards does not change a resumed run.
struct Invocation {
  std::string command;   // "prepare", "biaxial", ...
  std::string settings;  // the settings path as given ("" for `compare`)
  std::string settings_text;
  std::vector<std::string> overrides;  // --set key=value
  // A command set up by its command line (`compare`): its arguments as given, parsed again by a
  // resume (the overrides among them are also in `overrides`, which a resume may extend).
  std::vector<std::string> arguments;
  std::filesystem::path working_directory;
  // Reads the settings file (throws like RunConfig::from_file when it cannot) and removes the
  // stale temporaries of the outputs it names (remove_stale_temporaries).
  static Invocation start(std::string command, std::string settings,
                          std::vector<std::string> overrides);
  // A command without a settings file: its settings are the overrides alone.
  static Invocation from_arguments(std::string command, std::vector<std::string> arguments,
                                   std::vector<std::string> overrides);
  // The settings exactly as RunConfig::from_file would read them (the overrides alone, named
  // "command line", when there is no settings file).
  RunConfig settings_config() const;
  // The --set overrides of `granstab resume`: only the settings that may change in the middle of
  // a run (resumable_settings); any other key throws std::invalid_argument naming it. They are
  // kept for the checkpoints written after (a later resume keeps them).
  void add_resume_overrides(const std::vector<std::string>& extra);
  // The files and name prefixes the settings give the outputs ([output] csv, sample, summary,
  // hold_sample, save_prefix, vtk; checkpoint.path), resolved like the commands resolve them;
  // empty when there is no settings file or it cannot be read (the command reports that).
  std::vector<std::filesystem::path> named_outputs() const;
  void put(Checkpoint& checkpoint) const;
  static Invocation get(const Checkpoint& checkpoint);
};

// The settings `granstab resume --set` may change: they do not enter the state a checkpoint
// holds, only how the run goes on from it (a smaller time step to retry a run that blew up, the
// sanity limits, when and where checkpoints are written).
inline const std::vector<std::string>& resumable_settings() {
  static const std::vector<std::string> keys{
      "engine.dt_fraction", "sanity.max_overlap_fraction", "sanity.max_kinetic_energy",
      "sanity.every_steps", "checkpoint.every_steps",      "checkpoint.every_seconds",
      "checkpoint.path"};
  return keys;
}

// A kill in the middle of write_file_atomically leaves its hidden temporary ".NAME.tmp-XXXXXX"
// beside NAME. A run, when it starts or resumes, removes those of the names it owns: for each of
// `outputs` (a file or a prefix of names, STEM its name without extension), the temporaries in
// its directory whose NAME is STEM, or begins with "STEM." or "STEM_" (the defaults derived from
// an output, e.g. run.json and run.checkpoint beside run.csv, and the saved states and snapshots
// PREFIX_...). Returns how many were removed.
std::size_t remove_stale_temporaries(const std::vector<std::filesystem::path>& outputs);

// The checksum of an input file, stored in checkpoints so that a resume refuses a changed input.
std::string file_checksum(const std::filesystem::path& path);

class RunGuard {
 public:
  using Builder = std::function<Checkpoint()>;
  // Installs the SIGINT / SIGTERM handlers (they only set a flag); the destructor restores the
  // previous ones.
  RunGuard(GuardSettings settings, std::string label);
  ~RunGuard();
  RunGuard(const RunGuard&) = delete;
  RunGuard& operator=(const RunGuard&) = delete;

  // Called before every checkpoint is written (the command flushes its CSV files, so that the
  // byte sizes in the checkpoint are on disk).
  void on_write(std::function<void()> flush_outputs) { flush_ = std::move(flush_outputs); }

  // Throws BlewUp (after writing the last sane checkpoint) when the state has blown up.
  void check(const Engine& engine);
  // At a safe point: the sanity check when due, an in-memory copy of the checkpoint after each
  // passed check (the last sane state), the checkpoint file when due by steps or time, and on
  // SIGINT / SIGTERM the checkpoint file followed by Interrupted.
  void safe_point(const Engine& engine, const Builder& build);
  // Cheap test whether safe_point would do anything at this step (call it first in loops that
  // reach a safe point every step, so that no Builder is made for nothing).
  bool wants(const Engine& engine) const;
  // The run finished and wrote its outputs: its checkpoint is no longer needed and is removed.
  void finish();

  std::size_t written() const { return written_; }
  const GuardSettings& settings() const { return settings_; }
  static int caught_signal();  // 0 when none

 private:
  void write(const Checkpoint& checkpoint);
  void sanity(const Engine& engine);

  GuardSettings settings_;
  std::string label_;
  std::function<void()> flush_;
  std::optional<Checkpoint> last_sane_;
  std::optional<std::uint64_t> last_sane_step_, last_checked_step_;
  // The step of the last checkpoint written, or of the first safe point (steps are counted from
  // there, so a run does not write one at its start).
  std::optional<std::uint64_t> last_written_step_;
  std::chrono::steady_clock::time_point last_written_time_;
  std::size_t written_ = 0;
  Configuration exported_;  // storage reused by the sanity checks
  struct sigaction old_int_ {
  }, old_term_{};
};

// Resuming a CSV output: the file is cut to the `bytes` a checkpoint recorded (rows written after
// the checkpoint are dropped; they are written again, identically, by the resumed run) and its
// rows are fed back into `csv`, a fresh writer of the same columns, which then holds the same
// text (checked) and rewrites the file. Throws naming the file when it is shorter than `bytes`,
// has another header, or does not end a row there.
void restore_csv(CsvWriter& csv, std::uint64_t bytes);

}  // namespace granstab::protocols
