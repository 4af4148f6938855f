#pragma once
// One load step of STATIC.md §S3: preparation (§S3.0), predictor with the complementarity loop
// over contact statuses (§S3.1), Newton corrector on the exact equilibrium (§S3.2).
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "static/linear_solvers.hpp"
#include "static/tangent.hpp"

namespace granstab::statics {

// Moves the loads of net to the value lambda of the load parameter.
using LoadPath = std::function<void(Network& net, double lambda)>;

struct SolverOptions {
  double tolerance = 1e-10;  // relative residual of the corrector and the polish
  // Below this relative residual a Newton iteration that can no longer decrease |R| is taken as
  // converged: round-off of K_N h at large kappa (reported in docs/static.md).
  double stagnation_tolerance = 1e-8;
  int max_newton_iterations = 40;
  // Newton's line search, after a full step that does not decrease |R|: the points just past the
  // last this-many kinks of the contact law on the step (0: halving only; corrector.cpp).
  int kink_trials = 4;
  int max_status_iterations = 200;
  int max_closing_rounds = 5;
  // Relative round-off width of the discrete decisions of the complementarity loop (statuses,
  // the pinned gear rows): a comparison closer than this times the size of its terms keeps the
  // current status (docs/static.md, "Round-off-robust decisions").
  double decision_tolerance = 1e-8;
  // When the status iteration cycles, the undecided contacts are resolved by an exact LCP
  // (Lemke, then enumeration): at most this many times per loop (0: report the cycle).
  int max_lcp_rounds = 3;
  // Largest such LCP whose principal bases are all enumerated when Lemke ends on a ray (2^n
  // small solves): only then can it prove that no consistent status set exists.
  int max_lcp_enumerated = 18;
  // A status set whose dropped rows are out of balance has no solution: pinned gear rotation rows
  // (every contact of a floppy cluster sliding, their forces doing net work in its gear mode:
  // STATIC.md §S3.5, kept_dofs), or the rows of a loaded disk whose contacts all open. Off: the
  // loop ends there (PredictorResult::unbalanced_rows) and the step control halves, as for any
  // status failure (§S3.3). On: the LCP of the cluster's sliding contacts decides which of them
  // stick and the loop goes on; a step's predictor (not the check) lets the open disk go, for the
  // corrector to settle. trace_to_instability turns it on for the attempt at the step floor
  // only, where the rate problem itself must be settled (docs/validation.md, "Static q1: floppy
  // rotations out of balance": on in every step, it takes the finite steps through non-unique
  // solutions and periodic-n100's q1 depends on the labels).
  bool resolve_unbalanced_rows = false;
  // Tangents of the predictor and corrector with a fixed sparsity pattern (TangentParts): one
  // UMFPACK symbolic analysis per contact list instead of one per status set (q1 at N = 5600
  // 196 -> 152 s CPU). Another pivot order, so other round-off; since the rattler fix the same
  // path and q1 on the shipped samples (docs/static.md, Performance).
  bool fixed_pattern = true;
  // Rattlers that an active disk closes on become contacts and get dofs in the same step (they
  // are pushed along instead of being overlapped). Off by default: on periodic-n100 it moves q1
  // above the rigid limit of the start network and makes it depend on the ordering again
  // (docs/static.md, "Rattlers closed on by the cage").
  bool push_rattlers = false;
  // Instead of a new LU per matrix: in a complementarity loop, low-rank updates of the check's LU
  // (LuReuse::low_rank); otherwise, in the loops and the corrector, GMRES preconditioned with the
  // latest LU or update of the thread (LuReuse::krylov). The check's determinant sign and
  // negative-eigenvalue count use an LU or an update, both exact. Matrices below
  // LuReuse::krylov_min_dofs are factorised (KLU's refactorisations are cheaper there).
  // docs/static.md, Performance.
  bool krylov_solves = true;
  // UMFPACK's iterative refinement in the solves of the load step and of the check that are made
  // with an LU of the matrix itself (LuReuse::refine; GMRES and the eigenvalue count never refine).
  // Off: the same path and q1 on the shipped samples, and the refined solves' 6-7 s of CPU in q1
  // at N = 5600 gone (measurements: docs/notes/2026-12-02-static-speed-measurements.md).
  bool refine_solves = false;
};

// The LuFactor reuse of the load step's factorisations: this thread's default plus the options'.
LuReuse lu_reuse(const SolverOptions& options);

// Force, torque and cell-row scales of the relative residual (mean contact force, mean radius,
// prescribed stress times area).
struct ResidualScale {
  double force = 1.0, torque = 1.0, cell = 1.0;
};
ResidualScale residual_scale(const Network& net, const std::vector<ContactState>& states);
double relative_residual(const Network& net, const Eigen::VectorXd& r, const ResidualScale& scale);

struct Timings {
  double assembly = 0.0, factorisation = 0.0, complementarity = 0.0, corrector = 0.0;
  // Counts behind the seconds (bench/static): LU factorisations and the symbolic analyses among
  // them, status iterations of the complementarity loops, Newton iterations of the correctors.
  int factorisations = 0, symbolic_analyses = 0, status_iterations = 0, newton_iterations = 0;
};

struct NewtonResult {
  bool converged = false;
  Eigen::VectorXd dq;
  std::vector<ContactState> states;
  std::vector<double> residual_history;  // relative residual before each iteration
};

// Newton on R(dq) = 0 with a line search on |R| (past the contact law's kinks, then halving; a
// failure is rerun with halving alone: docs/static.md §S3.2); with forced statuses the tangential
// law is frozen (the §S3.0 polish), otherwise it is the exact Coulomb return (the §S3.2 corrector).
NewtonResult newton_equilibrium(const Network& net, Eigen::VectorXd dq,
                                const std::vector<ContactStatus>* forced,
                                const ResidualScale& scale, const SolverOptions& options,
                                Timings* timings = nullptr);

// §S3.0 step 5: stick, or sliding in the direction of F_T when |F_T| >= (1 - 1e-9) mu F_N.
std::vector<ContactStatus> classify_contacts(const std::vector<ContactState>& states);

struct PredictorResult {
  bool ok = false;
  // "singular" (a failed factorisation), "cycle...", "iterations", "no consistent statuses...",
  // "pinned rotation rows out of balance", "dropped rows out of balance"
  std::string failure;
  // The LCP of the undecided contacts proved that no consistent status set exists.
  bool no_solution = false;
  // The loop ended on a status set whose pinned gear rotation rows, or rows of a loaded disk with
  // all its contacts open, are out of balance (SolverOptions::resolve_unbalanced_rows off, or the
  // open disk in a check): no solution for those statuses, not a singular K.
  bool unbalanced_rows = false;
  Eigen::VectorXd dq;
  std::vector<ContactStatus> statuses;  // consistent statuses of the increment
  int determinant_sign = 0;  // of K(statuses) on the kept dofs (0 if not asked for and unknown)
  int iterations = 0;
  // K(statuses) on all dofs, shared and never changed: the step's loop from a state takes its
  // check's as it is, and results move without copying it (Eigen 3.4's SparseMatrix has no move
  // operations, so a SparseMatrix member would make every move of a result a copy).
  std::shared_ptr<const SparseMatrix> tangent;
  std::vector<char> kept;            // dofs kept (floppy rotations pinned)
  std::vector<char> ever_sliding;    // per contact: sliding in some iterate of the loop
  std::shared_ptr<LuFactor> factor;  // LU of K(statuses) on the kept dofs (when ok)
  // R(0) at the state's own load (set by the stability check): a step's loop from this state, to
  // which this result is `warm`, takes it off the misfit of its dropped rows (solve_factored).
  Eigen::VectorXd start_residual;
  // The contacts at the start of the increment (net, dq = 0), as the loop evaluated them: the
  // caller's, which need not evaluate them again.
  std::vector<ContactState> start_states;
};

// Piecewise-linear complementarity problem at the start of the step, by iterating statuses and
// solving the full unsymmetric K with UMFPACK each time; cycles are detected by hashing the
// status vectors, and a cycle is settled by the exact LCP of the contacts whose status changed
// (a solution continues the loop, a proof of no solution sets no_solution). net carries the
// loads of the end of the step.
// With rhs given, it replaces R(0) (the stability check solves for a pure load increment); with
// warm given (a loop run at the same state), the loop starts from its statuses instead of
// classify_contacts, and reuses its factor while the statuses agree. determinant: the sign of
// det K(statuses) is wanted (with deferred factorisations it costs an LU; without, nothing).
// start_states: evaluate_contacts(net, 0) if the caller has it (the same bits; not evaluated
// again).
PredictorResult predict(const Network& net, const SolverOptions& options,
                        Timings* timings = nullptr, const Eigen::VectorXd* rhs = nullptr,
                        const PredictorResult* warm = nullptr, bool determinant = true,
                        std::vector<ContactState>* start_states = nullptr);

// The status cycles' LCPs over many contacts start from the last one's sliding set (a guess that
// Lemke replaces where it fails); a run forgets it first, as it forgets its factorisations.
void forget_lcp_supports();

struct StepResult {
  bool ok = false;
  std::string failure;
  PredictorResult predictor;
  NewtonResult corrector;
  int new_contacts = 0;
};

// Advances net to the equilibrium under its (new) loads; on failure net is unchanged. warm: the
// stability check of this state, to warm-start the complementarity loop (see predict).
// start_states: evaluate_contacts(net, 0) if the caller has it (moved from; see predict).
StepResult load_step(Network& net, const SolverOptions& options, Timings* timings = nullptr,
                     const PredictorResult* warm = nullptr,
                     std::vector<ContactState>* start_states = nullptr);

// Moves the start of the step to dq: positions, rotations, cell lengths, tangential states and
// statuses; open contacts leave the list; sliding ones stay exactly on the cone of the moved
// geometry; imposed extensions are consumed.
void advance(Network& net, const Eigen::VectorXd& dq, const std::vector<ContactState>& states);

// §S3.0: rattlers and dofs, then the equilibrium polished at frozen statuses. Returns the polish's
// Newton result (throws std::runtime_error if the configuration cannot be polished).
NewtonResult prepare(Network& net, const SolverOptions& options);

}  // namespace granstab::statics
