#pragma once
// Runs a study's tasks (study_plan.hpp): each task is one `granstab COMMAND ...` child process in
// its own directory, at most `jobs` at a time, a task only after the one it depends on. A task
// that exited 0 gets a `.done` file holding its command line, and is never run again; one that
// was stopped keeps its command's checkpoint and is resumed from it (`granstab resume`). So a
// study killed at any moment continues where it was when run again. Under MPI each rank runs the
// trees of tasks (a root and everything that depends on it) dealt to it round robin.
#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "study_plan.hpp"

namespace granstab::study {

struct RunOptions {
  int jobs = 1;                      // child processes at a time
  int rank = 0, ranks = 1;           // this process's share of the roots: ordinal % ranks == rank
  std::filesystem::path executable;  // the granstab binary the children run
  int threads_per_job = 1;           // OMP_NUM_THREADS of each child
  bool quiet = false;                // no progress lines
  std::vector<bool> selected;        // per task; empty: all (select_points)
};

// The tasks of the points whose value of each key in `only` is one of the listed values ("n" ->
// {"1024"}); an unknown key or value throws std::invalid_argument naming it.
std::vector<bool> select_points(
    const Plan& plan, const std::vector<std::pair<std::string, std::vector<std::string>>>& only);

struct RunSummary {
  std::size_t tasks = 0;        // of this rank
  std::size_t done_before = 0;  // found done
  std::size_t ran = 0;          // run to success now
  std::size_t failed = 0;       // exited non-zero (its `.failed` says how; retried next time)
  std::size_t blocked = 0;      // not run because a task they depend on failed
};

// Throws protocols::Interrupted on SIGINT / SIGTERM after forwarding the signal to the running
// children and waiting for them (their checkpoints are written); std::runtime_error when a
// `.done` task was run with another command line than the study now gives it.
RunSummary run_plan(const Plan& plan, const RunOptions& options);

}  // namespace granstab::study
