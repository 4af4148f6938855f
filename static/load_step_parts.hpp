#pragma once
// What the three parts of a load step share (load_step.cpp, complementarity_loop.cpp,
// corrector.cpp): solves on the kept dofs and the chord iterations. Internal to static/.
#include <chrono>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "static/complementarity.hpp"
#include "static/linear_solvers.hpp"
#include "static/load_step.hpp"

namespace granstab::statics {

using Clock = std::chrono::steady_clock;
inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// A factorisation into lu begun at t0, in timings (if any): its time, its count, and its symbolic
// analysis unless one was reused.
inline void count_factorisation(Timings* timings, Clock::time_point t0, const LuFactor& lu) {
  if (!timings) return;
  timings->factorisation += seconds_since(t0);
  ++timings->factorisations;
  if (!lu.symbolic_reused()) ++timings->symbolic_analyses;
}

enum class Solve { solved, singular, pinned_out_of_balance };

// Solves K x = b on the kept dofs with a factor of the reduced K (pinned dofs stay 0). With a
// test, the rows of pinned gear rotations must hold too (see kept_dofs): the predictor's test of a
// status set. The misfit of the pinned rows is compared with the largest size of the terms of a
// row, max_i (|K| |x| + |b|)_i, so that the round-off of K x (O(1e-16 cond(K)) of that) never
// decides it; a genuine misfit (sliding forces doing work in a gear mode) is a finite fraction of
// it. A step's b = R(0) holds the start's own residual too (the corrector's leftover, the cone
// re-projection of `advance`): given, it is taken off, so that the rows are judged on the step's
// forces alone. It does not shrink with the step as they do: at 5.6e-10 (4.5 times the
// corrector's tolerance) on two dropped disks it failed a step of 4.9e-7, and the run ended in
// its halves (series A, N = 3025, docs/notes/2026-12-06-lone-contacts.md).
// The corrector's backtracking on |R| judges its steps itself. out_of_balance receives the disks
// whose dropped dofs (pinned gear rotations, or all dofs of a disk whose contacts are all open)
// carry such a misfit.
struct PinnedRowTest {
  double tolerance = 0.0;                           // times max_i (|K| |x| + |b|)_i
  const Eigen::VectorXd* start_residual = nullptr;  // part of b that is not the step's
};
Solve solve_factored(const Network& net, const SparseMatrix& k, const std::vector<char>& kept,
                     const LuFactor& lu, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                     const PinnedRowTest* test, std::vector<int>* out_of_balance = nullptr);
// The same after factorising the reduced K into lu (timed and counted in timings), for a K the
// caller no longer needs: lu takes its storage when every dof is kept (Eigen 3.4's SparseMatrix
// has no move operations, so a copy otherwise).
Solve solve_kept(const Network& net, SparseMatrix&& k, const std::vector<char>& kept,
                 const Eigen::VectorXd& b, LuFactor& lu, Eigen::VectorXd& x, Timings* timings,
                 const PinnedRowTest* test, std::vector<int>* out_of_balance = nullptr);
// The same for a shared K (a status iterate's tangent): lu shares it when every dof is kept.
Solve solve_kept(const Network& net, const std::shared_ptr<const SparseMatrix>& k,
                 const std::vector<char>& kept, const Eigen::VectorXd& b, LuFactor& lu,
                 Eigen::VectorXd& x, Timings* timings, const PinnedRowTest* test,
                 std::vector<int>* out_of_balance = nullptr);

// The LCP of resolve_by_lcp (complementarity_loop.cpp) as its sparse system, S dq + W lambda = b,
// phi = g + V dq + K_T lambda (S, W, b on the kept dofs; V a contact's few dofs per row).
struct LcpSystem {
  const SparseMatrix& s;
  const SparseMatrix& w;
  const Eigen::SparseMatrix<double, Eigen::RowMajor, int>& v;
  const Eigen::VectorXd& g;
  const Eigen::VectorXd& b;
  const Eigen::VectorXd& q;  // g + V S^-1 b
  double q_scale;            // solve_lcp's unknowns are lambda K_T / q_scale and phi / q_scale
  double k_t;
};
// That LCP solved by active sets, without its matrix M = K_T I - V S^-1 W, whose n columns cost n
// solves (N = 5600: 400-2200 contacts, ~2-10 s an LCP). On a support a, phi_a = 0, so lambda_a =
// -(g_a + V_a dq) / K_T, where dq solves the tangent with a's contacts sliding, (S - W_a V_a / K_T)
// dq = b + W_a g_a / K_T: one factorisation and one solve. First lambda = 0 (phi = q), then the
// support `in` and, while some unknown is below -tol, the next one of a primal-dual active set
// iteration (out where lambda < -tol, in where phi < -tol; only the worst one flips where that
// support was tried before), max_supports in all. solve_lcp's conditions are tested on its scaled
// unknowns. Empty when none of them solves it, or a solve is not finite.
std::optional<LcpResult> lcp_by_active_sets(const LcpSystem& p, std::vector<char> in, double tol,
                                            int max_supports, const LuReuse& reuse,
                                            Timings* timings);

// Chord iterations with the predictor's factor: the tangent changes by O(step) inside a step, so
// they usually reach the tolerance without a new factorisation. Returns the point reached; the
// full Newton takes over from there when they stall.
Eigen::VectorXd chord_iterations(const Network& net, const PredictorResult& p, Eigen::VectorXd dq,
                                 const ResidualScale& scale, const SolverOptions& options);

}  // namespace granstab::statics
