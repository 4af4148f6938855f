// The corrector of a load step (STATIC.md §S3.2): Newton on the full equilibrium with the exact
// contact law, and the chord iterations that usually spare it a factorisation.
#include "static/load_step.hpp"
#include "static/load_step_parts.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "static/backbone.hpp"
#include "static/closing_contacts.hpp"
#include "static/complementarity.hpp"
#include "static/linear_solvers.hpp"
#include "static/tangent.hpp"
namespace granstab::statics {

ResidualScale residual_scale(const Network& net, const std::vector<ContactState>& states) {
  ResidualScale s;
  double sum = 0.0;
  int count = 0;
  for (const ContactState& c : states)
    if (c.f_n > 0.0) {
      sum += c.f_n;
      ++count;
    }
  double dead = 0.0;
  for (double f : net.loading.dead) dead = std::max(dead, std::abs(f));
  s.force = count > 0 ? sum / count : (dead > 0.0 ? dead : 1.0);
  double r = 0.0;
  for (double x : net.radius) r += x;
  s.torque = s.force * (net.radius.empty() ? 1.0 : r / net.radius.size());
  const double sigma = std::max(std::abs(net.loading.sigma[0]), std::abs(net.loading.sigma[1]));
  s.cell = (sigma > 0.0 ? sigma : s.force) * net.area();
  return s;
}

double relative_residual(const Network& net, const Eigen::VectorXd& r, const ResidualScale& s) {
  const DofMap& m = net.dofs;
  double worst = 0.0;
  for (std::size_t i = 0; i < net.n_disks(); ++i) {
    if (m.ux[i] >= 0) worst = std::max(worst, std::abs(r[m.ux[i]]) / s.force);
    if (m.uy[i] >= 0) worst = std::max(worst, std::abs(r[m.uy[i]]) / s.force);
    if (m.theta[i] >= 0) worst = std::max(worst, std::abs(r[m.theta[i]]) / s.torque);
  }
  for (int a = 0; a < 2; ++a)
    if (m.e[a] >= 0) worst = std::max(worst, std::abs(r[m.e[a]]) / s.cell);
  return worst;
}

NewtonResult newton_equilibrium(const Network& net, Eigen::VectorXd dq,
                                const std::vector<ContactStatus>* forced,
                                const ResidualScale& scale, const SolverOptions& options,
                                Timings* timings) {
  NewtonResult result;
  LuFactor lu(lu_reuse(options));
  std::vector<ContactState> states = evaluate_contacts(net, dq, forced);
  Eigen::VectorXd r = residual(net, dq, states);
  double norm = relative_residual(net, r, scale);
  for (int it = 0; it < options.max_newton_iterations; ++it) {
    result.residual_history.push_back(norm);
    if (norm < options.tolerance) {
      result.converged = true;
      break;
    }
    if (timings) ++timings->newton_iterations;
    auto t0 = Clock::now();
    std::vector<ContactStatus> statuses(states.size());
    for (std::size_t c = 0; c < states.size(); ++c) statuses[c] = states[c].status;
    TangentParts parts;
    parts.fixed_pattern = options.fixed_pattern;
    const SparseMatrix k = assemble_tangent(net, states, statuses, parts);
    const std::vector<char> kept = kept_dofs(net, states, statuses);
    if (timings) timings->assembly += seconds_since(t0);
    Eigen::VectorXd step;
    if (solve_kept(net, k, kept, r, lu, step, timings, false) != Solve::solved) break;
    // Backtracking on |R|: the law has kinks (Coulomb return, opening) that a full step may cross.
    double alpha = 1.0;
    bool decreased = false;
    for (int b = 0; b < 12; ++b, alpha *= 0.5) {
      const Eigen::VectorXd trial = dq + alpha * step;
      std::vector<ContactState> trial_states = evaluate_contacts(net, trial, forced);
      const Eigen::VectorXd trial_r = residual(net, trial, trial_states);
      const double trial_norm = relative_residual(net, trial_r, scale);
      if (trial_norm < (1.0 - 1e-4 * alpha) * norm) {
        dq = trial;
        states = std::move(trial_states);
        r = trial_r;
        norm = trial_norm;
        decreased = true;
        break;
      }
    }
    if (!decreased) {
      result.converged = norm < options.stagnation_tolerance;
      break;
    }
  }
  if (!result.converged && norm < options.tolerance) {
    result.residual_history.push_back(norm);
    result.converged = true;
  }
  result.dq = dq;
  result.states = std::move(states);
  return result;
}

Eigen::VectorXd chord_iterations(const Network& net, const PredictorResult& p, Eigen::VectorXd dq,
                                 const ResidualScale& scale, const SolverOptions& options) {
  if (!p.factor) return dq;
  const Reduction r = make_reduction(p.kept);
  std::vector<ContactState> states = evaluate_contacts(net, dq);
  Eigen::VectorXd res = residual(net, dq, states);
  double norm = relative_residual(net, res, scale);
  for (int it = 0; it < 8 && norm >= options.tolerance; ++it) {
    const Eigen::VectorXd trial =
        dq + expand(p.factor->solve(reduce(res, r)), r, static_cast<int>(dq.size()));
    states = evaluate_contacts(net, trial);
    const Eigen::VectorXd trial_res = residual(net, trial, states);
    const double trial_norm = relative_residual(net, trial_res, scale);
    if (!(trial_norm < 0.25 * norm)) break;  // too slow: leave it to Newton
    dq = trial;
    res = trial_res;
    norm = trial_norm;
  }
  return dq;
}

}  // namespace granstab::statics
