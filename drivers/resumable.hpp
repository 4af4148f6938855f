#pragma once
// The protocol commands that checkpoint and can be continued by `granstab resume` (issue #8,
// docs/reliability.md). Each runs either fresh (checkpoint == nullptr) or from a checkpoint it
// wrote; the settings come from the Invocation (the settings text or, for compare, the command
// line kept in the checkpoint).
#include <string>
#include <vector>

#include "dynamic/protocols/checkpoint.hpp"
#include "dynamic/protocols/run_guard.hpp"

namespace granstab::cli {

void run_prepare(const protocols::Invocation& invocation, bool quiet,
                 const protocols::Checkpoint* checkpoint);
void run_biaxial(const protocols::Invocation& invocation, bool quiet,
                 const protocols::Checkpoint* checkpoint);
void run_creep(const protocols::Invocation& invocation, bool quiet,
               const protocols::Checkpoint* checkpoint);
void run_perturb(const protocols::Invocation& invocation, bool quiet,
                 const protocols::Checkpoint* checkpoint);
// The dynamic half of `compare` (its static half is run again on a resume).
void run_compare(const protocols::Invocation& invocation, const protocols::Checkpoint* checkpoint);

// The program's arguments (argv[1..]), kept by main() for the commands that store their command
// line in checkpoints (compare).
inline std::vector<std::string>& command_line() {
  static std::vector<std::string> arguments;
  return arguments;
}

// The hooks every command gives its protocol loops: sanity checks before records, and at safe
// points a checkpoint made by `build(engine, cursor)` when the guard wants one.
template <class Build>
protocols::LoopHooks guard_hooks(protocols::RunGuard& guard, Build& build) {
  protocols::LoopHooks hooks;
  hooks.check = [&guard](const Engine& e) { guard.check(e); };
  hooks.safe_point = [&guard, &build](const Engine& e, const protocols::Cursor& c) {
    if (guard.wants(e)) guard.safe_point(e, [&] { return build(e, c); });
  };
  return hooks;
}

// The part of every checkpoint that is not the command's own: how the run was started, the
// engine's state, the cursor, the input file's checksum and the wall time so far.
inline protocols::Checkpoint checkpoint_head(const protocols::Invocation& invocation,
                                             const Engine& engine, const protocols::Cursor& cursor,
                                             const std::string& input_checksum,
                                             double wall_seconds) {
  protocols::Checkpoint c;
  invocation.put(c);
  c.set("run.input_checksum", input_checksum);
  c.set_number("run.wall_seconds", wall_seconds);
  protocols::put_cursor(c, cursor);
  c.set_configuration("engine", engine.configuration());
  return c;
}

// Refuses to continue when the input file is not the one the run started from.
inline void require_same_input(const protocols::Checkpoint& c, const std::string& input,
                               const std::string& checksum) {
  if (c.text("run.input_checksum") != checksum) {
    throw std::runtime_error(c.source_name() + ": the input " + input +
                             " changed since the run started; cannot resume");
  }
}

}  // namespace granstab::cli
