// granstab study STUDY.toml: runs a grid of pipelines (study_plan.hpp, study_runner.hpp), one
// child process per task, restartable at the task level; --report aggregates the results with
// scripts/study/study_report.py (docs/studies.md). Under `mpirun -np K` (when built with MPI),
// the ranks share the tasks out and rank 0 writes the report.
#include <CLI/CLI.hpp>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "common/atomic_file.hpp"
#include "commands.hpp"
#include "python_script.hpp"
#include "study_plan.hpp"
#include "study_runner.hpp"
#ifdef GRANSTAB_WITH_MPI
#include <mpi.h>
#endif

namespace granstab::cli {
namespace {

namespace fs = std::filesystem;

struct StudyOptions {
  std::string file;
  int jobs = 0;  // 0: the core count (one rank), 1 per rank under MPI
  int threads = 1;
  bool report = false, report_only = false, quiet = false;
  std::string python = "/usr/bin/python3";
  std::vector<std::string> only;  // KEY=V1,V2
};

void write_report(const study::Plan& plan, const StudyOptions& o) {
  run_python_script(o.python, "scripts/study/study_report.py", {plan.out.string()});
}

// The MPI world when launched by mpirun, else rank 0 of 1. MPI is initialised only here, and only
// when an MPI launcher set the environment, so that `granstab study` alone needs no MPI runtime.
// The calls use the PMPI_ names (the standard's profiling interface, same functions): the
// sequential MUMPS that Ipopt brings (libdmumps_seq) exports stub MPI_Init, MPI_Comm_rank and
// MPI_Finalize, and comes first in the binary's library order, so MPI_Init would be its no-op.
struct World {
  int rank = 0, ranks = 1;
  bool mpi = false;
  World() {
#ifdef GRANSTAB_WITH_MPI
    if (std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE") ||
        std::getenv("PMIX_RANK")) {
      PMPI_Init(nullptr, nullptr);
      PMPI_Comm_rank(MPI_COMM_WORLD, &rank);
      PMPI_Comm_size(MPI_COMM_WORLD, &ranks);
      mpi = true;
    }
#endif
  }
  // Sum of `value` over the ranks (every rank waits here for the others).
  long long sum(long long value) const {
#ifdef GRANSTAB_WITH_MPI
    if (mpi) {
      long long total = 0;
      PMPI_Allreduce(&value, &total, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
      return total;
    }
#endif
    return value;
  }
  ~World() {
#ifdef GRANSTAB_WITH_MPI
    if (mpi) PMPI_Finalize();
#endif
  }
};

void run_study(const StudyOptions& o) {
  const study::Plan plan = study::read_plan(o.file);
  World world;
  if (world.rank == 0) {
    fs::create_directories(plan.out);
    write_file_atomically(plan.out / "study.json", study::plan_json(plan));
  }
  long long failed = 0;
  if (!o.report_only) {
    study::RunOptions r;
    r.jobs = o.jobs > 0
                 ? o.jobs
                 : (world.ranks > 1
                        ? 1
                        : static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
    r.rank = world.rank;
    r.ranks = world.ranks;
    r.executable = fs::read_symlink("/proc/self/exe");
    r.threads_per_job = o.threads;
    r.quiet = o.quiet;
    std::vector<std::pair<std::string, std::vector<std::string>>> only;
    for (const std::string& item : o.only) {
      const auto eq = item.find('=');
      if (eq == std::string::npos || eq == 0 || eq + 1 == item.size())
        throw std::invalid_argument("--only " + item + ": expected KEY=VALUE[,VALUE...]");
      std::vector<std::string> values;
      std::stringstream list(item.substr(eq + 1));
      for (std::string v; std::getline(list, v, ',');) values.push_back(v);
      only.emplace_back(item.substr(0, eq), values);
    }
    if (!only.empty()) r.selected = study::select_points(plan, only);
    const study::RunSummary s = study::run_plan(plan, r);
    if (!o.quiet || s.failed > 0)
      std::fprintf(stderr,
                   "study%s: %zu tasks: %zu done before, %zu run now, %zu failed, %zu blocked "
                   "behind a failure\n",
                   world.ranks > 1 ? (" rank " + std::to_string(world.rank)).c_str() : "", s.tasks,
                   s.done_before, s.ran, s.failed, s.blocked);
    failed = world.sum(static_cast<long long>(s.failed + s.blocked));
  }
  if ((o.report || o.report_only) && world.rank == 0) write_report(plan, o);
  if (failed > 0)
    throw std::runtime_error(o.file + ": " + std::to_string(failed) +
                             " tasks failed or were blocked (their .failed and stderr.log say "
                             "why); run the study again to retry them");
}

}  // namespace

void add_study_command(CLI::App& app) {
  auto o = std::make_shared<StudyOptions>();
  auto* cmd = app.add_subcommand(
      "study",
      "Runs a study: a grid of sample sizes x seeds x parameters, each point a pipeline of "
      "commands (docs/studies.md); resumes where it stopped; --report aggregates mean +- rms");
  cmd->add_option("STUDY", o->file, "study file (TOML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--jobs", o->jobs,
                  "commands at a time (default: the core count; 1 per rank under mpirun)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--threads", o->threads, "OMP_NUM_THREADS of each command")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--report", o->report,
                "after the run, write summary.csv/json, mean +- rms curves and plots");
  cmd->add_flag("--report-only", o->report_only, "only the report, of the tasks done so far");
  cmd->add_option("--python", o->python, "Python with numpy and matplotlib, for --report")
      ->capture_default_str();
  cmd->add_option("--only", o->only,
                  "run only the points with these values, KEY=V1,V2 (repeatable; the report "
                  "covers every finished task)");
  cmd->add_flag("--quiet", o->quiet, "no progress on stderr");
  cmd->callback([o] { run_study(*o); });
}

}  // namespace granstab::cli
