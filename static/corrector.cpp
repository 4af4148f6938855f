// The corrector of a load step (STATIC.md §S3.2): Newton on the full equilibrium with the exact
// contact law, and the chord iterations that usually spare it a factorisation.
#include "static/load_step.hpp"
#include "static/load_step_parts.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
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

namespace {

// The kinks of the contact law on the segment dq + alpha step, 0 < alpha < 1, among the contacts
// whose status differs at its ends: where the gap closes or opens (h = 0), or where the stick
// trial force meets the cone (mu F_N = |F_T|), each linear in alpha between the ends. Ascending.
std::vector<double> kinks(const Network& net, const Eigen::VectorXd& dq, const Eigen::VectorXd& end,
                          const std::vector<ContactState>& at0,
                          const std::vector<ContactState>& at1,
                          const std::vector<ContactStatus>* forced) {
  std::vector<double> out;
  const auto crossing = [&out](double g0, double g1) {
    if ((g0 > 0.0) == (g1 > 0.0) || g0 == g1) return;
    const double alpha = g0 / (g0 - g1);
    if (alpha > 0.0 && alpha < 1.0) out.push_back(alpha);
  };
  for (std::size_t c = 0; c < at0.size(); ++c) {
    if (at0[c].status == at1[c].status) continue;
    const bool open0 = at0[c].status == ContactStatus::open;
    const bool open1 = at1[c].status == ContactStatus::open;
    if (open0 || open1) {
      crossing(at0[c].frame.h, at1[c].frame.h);
    } else if (!forced && at0[c].frictional) {
      const ContactState s0 = evaluate_contact(net, c, dq, ContactStatus::stick);
      const ContactState s1 = evaluate_contact(net, c, end, ContactStatus::stick);
      crossing(s0.mu * s0.f_n - std::abs(s0.f_t), s1.mu * s1.f_n - std::abs(s1.f_t));
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Newton from dq (newton_equilibrium), with kink_trials as set.
NewtonResult newton_iterations(const Network& net, Eigen::VectorXd dq,
                               const std::vector<ContactStatus>* forced, const ResidualScale& scale,
                               const SolverOptions& options, Timings* timings) {
  NewtonResult result;
  LuFactor lu(lu_reuse(options));
  std::vector<ContactState> states = evaluate_contacts(net, dq, forced);
  Eigen::VectorXd r = residual(net, dq, states);
  double norm = relative_residual(net, r, scale);
  // The round-off floor of the relative residual: a contact force K_N h carries the rounding of
  // the positions it is computed from, eps times the cell's extent (series A, kappa = 1e5:
  // 6.9e-10, where Newton stalled at 2.5e-10 to 4.5e-10; series B 7e-11, periodic-n100 2e-11).
  const double round_off = std::numeric_limits<double>::epsilon() * net.material.k_n *
                           std::max(net.length[0], net.length[1]) / scale.force;
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
    SparseMatrix k = assemble_tangent(net, states, statuses, parts);
    const std::vector<char> kept = kept_dofs(net, states, statuses);
    if (timings) timings->assembly += seconds_since(t0);
    Eigen::VectorXd step;
    if (solve_kept(net, std::move(k), kept, r, lu, step, timings, nullptr) != Solve::solved) break;
    // Backtracking on |R|: the law has kinks (Coulomb return, opening) that a full step may cross.
    // Halving alone creeps towards a kink on the tangent of its near side (the residual halves per
    // iteration, each with an LU); so after the full step come points just past the last kinks
    // on the way, from the farthest back, where the next tangent is the far side's.
    bool decreased = false;
    const auto accept_at = [&](double alpha, std::vector<ContactState>* kept_states) {
      const Eigen::VectorXd trial = dq + alpha * step;
      std::vector<ContactState> trial_states = evaluate_contacts(net, trial, forced);
      const Eigen::VectorXd trial_r = residual(net, trial, trial_states);
      const double trial_norm = relative_residual(net, trial_r, scale);
      if (!(trial_norm < (1.0 - 1e-4 * alpha) * norm)) {
        if (kept_states) *kept_states = std::move(trial_states);
        return false;
      }
      dq = trial;
      states = std::move(trial_states);
      r = trial_r;
      norm = trial_norm;
      decreased = true;
      return true;
    };
    std::vector<ContactState> at_full;
    const double before = norm;
    const bool full_step = accept_at(1.0, &at_full);
    // Within a few times the round-off floor of |R| (round_off), a full Newton step that does not
    // halve |R| shows that floor: no shorter step goes below it and Newton, quadratic above it,
    // gets no further. Series A (kappa = 1e5): 5e-10 after the chord, then 4e-10, 3.9e-10, ... for
    // 5-10 iterations, each with its line search of up to 15 residuals (docs/static.md §S3.2).
    if (norm < options.stagnation_tolerance && norm < 8.0 * round_off && norm > 0.5 * before) {
      if (full_step) result.residual_history.push_back(norm);
      result.converged = true;
      break;
    }
    if (!full_step) {
      const std::size_t trials = static_cast<std::size_t>(std::max(options.kink_trials, 0));
      const std::vector<double> at =
          trials == 0 ? std::vector<double>{} : kinks(net, dq, dq + step, states, at_full, forced);
      // Past kink i by a tenth of the way to the next one (or to the full step).
      for (std::size_t i = at.size(); i > 0 && i + trials > at.size() && !decreased; --i)
        accept_at(at[i - 1] + 0.1 * ((i < at.size() ? at[i] : 1.0) - at[i - 1]), nullptr);
      for (double alpha = 0.5; alpha > 4e-4 && !decreased; alpha *= 0.5) accept_at(alpha, nullptr);
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

}  // namespace

NewtonResult newton_equilibrium(const Network& net, Eigen::VectorXd dq,
                                const std::vector<ContactStatus>* forced,
                                const ResidualScale& scale, const SolverOptions& options,
                                Timings* timings) {
  if (options.kink_trials <= 0)
    return newton_iterations(net, std::move(dq), forced, scale, options, timings);
  NewtonResult result = newton_iterations(net, dq, forced, scale, options, timings);
  if (result.converged) return result;
  // A point past a kink can lead where Newton then stalls, and halving alone may still get through
  // (series A, seed 4, K_T/K_N = 1/2: a step at q = 0.8145). A failure is final only after both.
  SolverOptions halving = options;
  halving.kink_trials = 0;
  return newton_iterations(net, std::move(dq), forced, scale, halving, timings);
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
