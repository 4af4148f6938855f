// Timing of the static solver (issue #5): one load step split into assembly, factorisation and
// complementarity, and optionally the whole q1 run, on a shipped periodic sample tiled
// nx x ny times (1 x 1: any sample, walls too). Not part of ctest.
//   bench_static SAMPLE [nx ny] [steps] [q1[-fixed|-statuspattern][-lowrank][-krylov|-exact]
//   [CURVE.csv]]
// -fixed / -statuspattern: SolverOptions::fixed_pattern on / off (symbolic reuse across status
// changes, or the pattern of each status set) instead of its default; -lowrank: with
// LuReuse::low_rank (low-rank updates of a recent LU instead of refactorisations), for the whole
// run (load steps and q1); -krylov / -exact: SolverOptions::krylov_solves on / off (GMRES with
// deferred factorisations, or an LU per solve) instead of its default. Environment:
// GRANSTAB_KRYLOV_TOLERANCE, GRANSTAB_KRYLOV_MAX_ITERATIONS, GRANSTAB_LOWRANK_MAX_COLUMNS,
// GRANSTAB_LOWRANK_MAX_RANK, GRANSTAB_METIS_MIN_DOFS, GRANSTAB_COPY_AFTER_SOLVES override the
// LuReuse limits.
// With CURVE.csv, the q1 run's curve (the columns of granstab q1 that do not depend on timing or
// the Hill indicator) is written there, to compare solver changes. GRANSTAB_TILE_SAVE=FILE writes
// the tiled sample there (a granstab configuration, e.g. for `granstab sic` on the same N).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "common/io/configuration_file.hpp"
#include "static/hill.hpp"
#include "static/linear_solvers.hpp"
#include "static/load_step.hpp"
#include "static/q1.hpp"
#include "tile.hpp"

using namespace granstab;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(
        stderr,
        "usage: %s SAMPLE [nx ny] [steps] [q1[-fixed|-statuspattern][-lowrank][-krylov|-exact] "
        "[CURVE.csv]]\n",
        argv[0]);
    return 2;
  }
  const int nx = argc > 3 ? std::atoi(argv[2]) : 1, ny = argc > 3 ? std::atoi(argv[3]) : 1;
  const int steps = argc > 4 ? std::atoi(argv[4]) : 10;
  const std::string mode = argc > 5 ? argv[5] : "";
  const bool q1 = mode.rfind("q1", 0) == 0;
  const bool fixed = mode.find("-fixed") != std::string::npos;
  const bool status_pattern = mode.find("-statuspattern") != std::string::npos;
  statics::default_lu_reuse().low_rank = q1 && mode.find("-lowrank") != std::string::npos;
  const bool krylov = mode.find("-krylov") != std::string::npos;
  const bool exact = mode.find("-exact") != std::string::npos;
  if (const char* t = std::getenv("GRANSTAB_KRYLOV_TOLERANCE"))
    statics::default_lu_reuse().krylov_tolerance = std::atof(t);
  if (const char* i = std::getenv("GRANSTAB_KRYLOV_MAX_ITERATIONS"))
    statics::default_lu_reuse().max_krylov_iterations = std::atoi(i);
  // The update's limits, to measure how many refusals (too_many) larger ones would keep.
  if (const char* c = std::getenv("GRANSTAB_LOWRANK_MAX_COLUMNS"))
    statics::default_lu_reuse().max_columns = std::atoi(c);
  if (const char* r = std::getenv("GRANSTAB_LOWRANK_MAX_RANK"))
    statics::default_lu_reuse().max_rank = std::atoi(r);
  if (const char* m = std::getenv("GRANSTAB_METIS_MIN_DOFS"))
    statics::default_lu_reuse().metis_min_dofs = std::atoi(m);
  if (const char* c = std::getenv("GRANSTAB_COPY_AFTER_SOLVES"))
    statics::default_lu_reuse().copy_after_solves = std::atoi(c);
  const Configuration config = bench::tile(read_configuration(argv[1]), nx, ny);
  if (const char* save = std::getenv("GRANSTAB_TILE_SAVE")) write_configuration(config, save);
  using Clock = std::chrono::steady_clock;

  statics::Network net = statics::network_from_configuration(config);
  const auto t0 = Clock::now();
  statics::prepare(net, statics::SolverOptions{});
  const double t_prepare = std::chrono::duration<double>(Clock::now() - t0).count();
  statics::Timings timings;
  int done = 0;
  const auto t1 = Clock::now();
  const double sigma1 = net.loading.sigma[0];
  for (int k = 0; k < steps; ++k) {
    net.loading.sigma[1] = sigma1 * (1.0 + 1e-3 * (k + 1));
    const statics::StepResult s = statics::load_step(net, statics::SolverOptions{}, &timings);
    if (!s.ok) break;
    ++done;
  }
  const double t_steps = std::chrono::duration<double>(Clock::now() - t1).count();
  std::printf("N = %zu, dofs = %d, contacts = %zu, prepare %.3f s\n", config.disks.size(),
              net.dofs.size, net.contacts.size(), t_prepare);
  if (done > 0)
    std::printf(
        "%d load steps of dq = 1e-3: %.4f s per step (assembly %.4f, factorisation %.4f, "
        "complementarity loop %.4f incl. its assembly and factorisation, corrector %.4f); "
        "per step %.2f LU factorisations (%.2f symbolic), %.2f status iterations, "
        "%.2f Newton iterations\n",
        done, t_steps / done, timings.assembly / done, timings.factorisation / done,
        timings.complementarity / done, timings.corrector / done,
        double(timings.factorisations) / done, double(timings.symbolic_analyses) / done,
        double(timings.status_iterations) / done, double(timings.newton_iterations) / done);
  statics::lu_statistics() = {};
  statics::negative_eigenvalue_statistics() = {};
  if (q1) {
    statics::Q1Options o;
    o.hill_every = 0;
    // The user's step (`granstab q1 --dq`); 1e-3 otherwise, as in every figure of bench/README.md.
    if (const char* dq = std::getenv("GRANSTAB_Q1_DQ")) o.dq = std::atof(dq);
    // `granstab q1 --steps` and `--max-step-factor`; the library's defaults otherwise.
    if (const char* steps = std::getenv("GRANSTAB_Q1_STEPS"))
      o.steps = std::string(steps) == "fixed" ? statics::StepControl::fixed
                                              : statics::StepControl::adaptive;
    if (const char* factor = std::getenv("GRANSTAB_Q1_MAX_STEP_FACTOR"))
      o.max_step_factor = std::atof(factor);
    // `granstab q1 --stop`: a part of the run (a step control's first states at N = 5600).
    if (const char* stop = std::getenv("GRANSTAB_Q1_STOP")) o.load_stop = std::atof(stop);
    if (fixed || status_pattern) o.solver.fixed_pattern = fixed;
    if (krylov || exact) o.solver.krylov_solves = krylov;
    const auto t2 = Clock::now();
    const statics::StabilityResult r = statics::find_q1(config, o);
    int rejected = 0;
    for (const auto& [reason, n] : r.rejected) rejected += n;
    const statics::Timings& t = r.timings;
    if (argc > 6) {
      std::FILE* f = std::fopen(argv[6], "w");
      if (!f) throw std::runtime_error(std::string("cannot write ") + argv[6]);
      std::fprintf(f,
                   "load,q,epsilon_1,epsilon_2,epsilon_v,n_sliding,det_sign,new_contacts,"
                   "negative_eigenvalues,interpolated\n");
      for (const statics::CurvePoint& p : r.curve)
        std::fprintf(f, "%.17g,%.17g,%.17g,%.17g,%.17g,%d,%d,%d,%d,%d\n", p.load, p.q, p.eps1,
                     p.eps2, p.epsv, p.n_sliding, p.determinant_sign, p.new_contacts,
                     p.negative_eigenvalues, p.interpolated ? 1 : 0);
      std::fclose(f);
    }
    std::printf(
        "q1 = %.9f in [%.9f, %.9f] (%s), %s steps: %d steps + %d rejected, %d interpolated rows, "
        "%.2f s (assembly %.2f, "
        "factorisation %.2f, complementarity loops %.2f, correctors %.2f); "
        "%d LU factorisations (%d symbolic), %d status iterations, %d Newton iterations\n",
        r.q1, r.q1_bracket[0], r.q1_bracket[1], statics::criterion_name(r.criterion),
        statics::step_control_name(r.step_control), r.steps, rejected, r.interpolated_rows,
        std::chrono::duration<double>(Clock::now() - t2).count(), t.assembly, t.factorisation,
        t.complementarity, t.corrector, t.factorisations, t.symbolic_analyses, t.status_iterations,
        t.newton_iterations);
    const statics::LuStatistics& lu = statics::lu_statistics();
    std::printf(
        "LuFactor: %ld numeric factorisations (%ld symbolic analyses, %ld KLU refactorisations), "
        "%ld low-rank updates (mean rank %.1f), %ld updates refused; %ld refined solves (%.2f s "
        "CPU), %ld unrefined\n",
        lu.numeric, lu.symbolic, lu.refactorisations, lu.low_rank,
        lu.low_rank > 0 ? double(lu.rank_sum) / lu.low_rank : 0.0, lu.too_many, lu.solves,
        lu.solve_seconds, lu.unrefined_solves);
    std::printf(
        "LuFactor CPU: symbolic analyses %.2f s, numeric factorisations %.2f s, %ld copies of "
        "factors %.2f s\n",
        lu.symbolic_seconds, lu.numeric_seconds, lu.copies, lu.copy_seconds);
    std::printf(
        "LuFactor deferred: %ld deferred factorisations (%ld factorised later), %ld GMRES solves "
        "(%ld over the bound), %ld iterations, %.2f s CPU\n",
        lu.deferred, lu.deferred_factorised, lu.krylov_solves, lu.krylov_failed,
        lu.krylov_iterations, lu.krylov_seconds);
    const char* phase_names[] = {"other",       "step loop",   "chord",     "corrector",
                                 "check first", "check later", "check sign"};
    static_assert(sizeof(phase_names) / sizeof(phase_names[0]) == statics::LuStatistics::phases);
    for (int ph = 0; ph < statics::LuStatistics::phases; ++ph)
      std::printf(
          "  %-11s: %4ld numeric, %4ld GMRES solves (%4ld over the bound), %6ld iterations, "
          "%.2f s CPU\n",
          phase_names[ph], lu.phase_numeric[ph], lu.phase_krylov_solves[ph],
          lu.phase_krylov_failed[ph], lu.phase_krylov_iterations[ph], lu.phase_krylov_seconds[ph]);
    const statics::NegativeEigenvalueStatistics& e = statics::negative_eigenvalue_statistics();
    std::printf(
        "negative_eigenvalues: %ld calls, symmetric inertia %.2f s CPU; "
        "%ld Arnoldi (%ld confirmed, %ld solves, %.2f s CPU), %ld dense\n",
        e.calls, e.symmetric_seconds, e.arnoldi, e.arnoldi_confirmed, e.arnoldi_solves,
        e.arnoldi_seconds, e.dense);
  }
  return 0;
}
