#include "static/load_step.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_set>

#include "static/backbone.hpp"
#include "static/closing_contacts.hpp"
#include "static/linear_solvers.hpp"
#include "static/tangent.hpp"

namespace granstab::statics {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Solves K dq = b on the kept dofs (pinned dofs stay 0); false if K is singular there.
// Solves K x = b on the kept dofs with a factor of the reduced K. With check_pinned, the rows of
// pinned gear rotations must hold too (see kept_dofs): the predictor's test of a status set. The
// corrector's backtracking on |R| judges its steps itself.
bool solve_factored(const SparseMatrix& k, const std::vector<char>& kept, const LuFactor& lu,
                    const Eigen::VectorXd& b, Eigen::VectorXd& x, bool check_pinned) {
  const Reduction r = make_reduction(kept);
  x = expand(lu.solve(reduce(b, r)), r, static_cast<int>(k.rows()));
  if (!check_pinned || static_cast<Eigen::Index>(r.reduced_to_full.size()) == k.rows())
    return true;
  const Eigen::VectorXd misfit = k * x - b;
  double worst = 0.0;
  for (std::size_t i = 0; i < kept.size(); ++i)
    if (!kept[i]) worst = std::max(worst, std::abs(misfit[i]));
  return worst <= 1e-8 * std::max(b.cwiseAbs().maxCoeff(), 1e-300);
}

bool solve_kept(const SparseMatrix& k, const std::vector<char>& kept, const Eigen::VectorXd& b,
                LuFactor& lu, Eigen::VectorXd& x, Timings* timings, bool check_pinned) {
  const auto t0 = Clock::now();
  const bool ok = lu.factorize(reduce(k, make_reduction(kept))) &&
                  solve_factored(k, kept, lu, b, x, check_pinned);
  if (timings) {
    timings->factorisation += seconds_since(t0);
    ++timings->factorisations;
    if (!lu.symbolic_reused()) ++timings->symbolic_analyses;
  }
  return ok;
}

}  // namespace

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
  LuFactor lu;
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
    if (!solve_kept(k, kept, r, lu, step, timings, false)) break;
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

std::vector<ContactStatus> classify_contacts(const std::vector<ContactState>& states) {
  std::vector<ContactStatus> statuses(states.size());
  for (std::size_t c = 0; c < states.size(); ++c) {
    const ContactState& s = states[c];
    if (s.f_n <= 0.0)
      statuses[c] = ContactStatus::open;
    else if (s.frictional && is_sliding(s.f_t, s.f_n, s.mu))
      statuses[c] = s.f_t > 0.0 ? ContactStatus::slide_positive : ContactStatus::slide_negative;
    else
      statuses[c] = s.frictional ? ContactStatus::stick : ContactStatus::slide_positive;
  }
  return statuses;
}

PredictorResult predict(const Network& net, const SolverOptions& options, Timings* timings,
                        const Eigen::VectorXd* rhs, const PredictorResult* warm) {
  const auto loop_start = Clock::now();
  PredictorResult p;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const std::vector<ContactState> states = evaluate_contacts(net, zero);
  const Eigen::VectorXd r0 = rhs ? *rhs : residual(net, zero, states);
  p.statuses = classify_contacts(states);
  if (warm && warm->ok && warm->statuses.size() == states.size()) {
    for (std::size_t c = 0; c < states.size(); ++c)
      if (p.statuses[c] != ContactStatus::open) p.statuses[c] = warm->statuses[c];
  }
  p.ever_sliding.assign(states.size(), 0);
  const double k_n = net.material.k_n, k_t = net.material.k_t;
  std::unordered_set<std::string> seen;
  std::shared_ptr<LuFactor> factor;
  p.failure = "iterations";
  for (int it = 0; it < options.max_status_iterations; ++it) {
    p.iterations = it + 1;
    if (timings) ++timings->status_iterations;
    const std::string key(reinterpret_cast<const char*>(p.statuses.data()), p.statuses.size());
    if (!seen.insert(key).second) {
      p.failure = "cycle";
      break;
    }
    if (it == 0 && warm && warm->factor && warm->statuses == p.statuses &&
        warm->tangent.rows() == net.dofs.size) {
      // Same state and statuses as the stability check that accepted it: reuse its factor
      // (its K_load differs by the load increment of the check only, O(1e-6 dq P A0)).
      p.tangent = warm->tangent;
      p.kept = warm->kept;
      factor = warm->factor;
      const auto t0 = Clock::now();
      const bool solved = solve_factored(p.tangent, p.kept, *factor, r0, p.dq, true);
      if (timings) timings->factorisation += seconds_since(t0);
      if (!solved) {
        p.failure = "singular";
        break;
      }
    } else {
      auto t0 = Clock::now();
      TangentParts parts;
      parts.fixed_pattern = options.fixed_pattern;
      p.tangent = assemble_tangent(net, states, p.statuses, parts);
      p.kept = kept_dofs(net, states, p.statuses);
      if (timings) timings->assembly += seconds_since(t0);
      factor = std::make_shared<LuFactor>();
      if (!solve_kept(p.tangent, p.kept, r0, *factor, p.dq, timings, true)) {
        p.failure = "singular";
        break;
      }
    }
    // Complementarity checks on the linearised increment (§S3.1).
    bool consistent = true;
    for (std::size_t c = 0; c < states.size(); ++c) {
      const ContactState& s = states[c];
      if (s.f_n <= 0.0) continue;  // closing gaps are events for the corrector
      const ContactRows& row = s.rows;
      double bn_dq = 0.0, bt_dq = 0.0;
      for (int a = 0; a < n_local; ++a)
        if (row.dof[a] >= 0) {
          bn_dq += row.bn[a] * p.dq[row.dof[a]];
          bt_dq += row.bt0[a] * p.dq[row.dof[a]];
        }
      const double d_fn = -k_n * bn_dq, f_n = s.f_n + d_fn;
      ContactStatus next = p.statuses[c];
      if (f_n < 0.0) {
        next = ContactStatus::open;
      } else if (!s.frictional) {
        next = ContactStatus::slide_positive;
      } else if (p.statuses[c] == ContactStatus::open || p.statuses[c] == ContactStatus::stick) {
        const double f_t = s.f_t - k_t * bt_dq;
        next = std::abs(f_t) > s.mu * f_n
                   ? (f_t > 0.0 ? ContactStatus::slide_positive : ContactStatus::slide_negative)
                   : ContactStatus::stick;
      } else {
        // Plastic multiplier: dF_T = -K_T (B_T dq + s lambda) = s mu dF_N.
        const double sign = p.statuses[c] == ContactStatus::slide_positive ? 1.0 : -1.0;
        const double lambda = -s.mu * d_fn / k_t - sign * bt_dq;
        if (lambda < 0.0) next = ContactStatus::stick;
      }
      if (next != p.statuses[c]) {
        consistent = false;
        p.statuses[c] = next;
      }
      if (s.frictional && (next == ContactStatus::slide_positive ||
                           next == ContactStatus::slide_negative))
        p.ever_sliding[c] = 1;
    }
    if (consistent) {
      p.ok = true;
      p.failure.clear();
      p.determinant_sign = factor->determinant_sign();
      p.factor = factor;
      break;
    }
  }
  if (timings) timings->complementarity += seconds_since(loop_start);
  return p;
}

void advance(Network& net, const Eigen::VectorXd& dq, const std::vector<ContactState>& states) {
  const DofMap& m = net.dofs;
  const std::array<double, 2> e = cell_extension(net, dq);
  for (std::size_t i = 0; i < net.n_disks(); ++i) {
    net.x[i] = (1.0 + e[0]) * net.x[i] + (m.ux[i] >= 0 ? dq[m.ux[i]] : 0.0);
    net.y[i] = (1.0 + e[1]) * net.y[i] + (m.uy[i] >= 0 ? dq[m.uy[i]] : 0.0);
    if (m.theta[i] >= 0) net.theta[i] += dq[m.theta[i]];
  }
  for (int a = 0; a < 2; ++a) net.length[a] *= 1.0 + e[a];
  net.loading.e_imposed = {0.0, 0.0};
  Contacts kept;
  kept.reserve(net.contacts.size());
  for (std::size_t c = 0; c < net.contacts.size(); ++c) {
    if (states[c].f_n <= 0.0) continue;
    kept.add(net.contacts.i[c], net.contacts.j[c], net.contacts.k1[c], net.contacts.k2[c],
             states[c].delta_t, states[c].status);
  }
  net.contacts = std::move(kept);
}

namespace {

// Chord iterations with the predictor's factor: the tangent changes by O(step) inside a step, so
// they usually reach the tolerance without a new factorisation. Returns the point reached; the
// full Newton takes over from there when they stall.
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

}  // namespace

StepResult load_step(Network& net, const SolverOptions& options, Timings* timings,
                     const PredictorResult* warm) {
  StepResult step;
  step.predictor = predict(net, options, timings, nullptr, warm);
  if (!step.predictor.ok) {
    step.failure = "predictor: " + step.predictor.failure;
    return step;
  }
  const auto t0 = Clock::now();
  Network trial = net;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(trial.dofs.size);
  const ResidualScale scale = residual_scale(trial, evaluate_contacts(trial, zero));
  Eigen::VectorXd dq = chord_iterations(trial, step.predictor, step.predictor.dq, scale, options);
  for (int round = 0;; ++round) {
    step.corrector = newton_equilibrium(trial, dq, nullptr, scale, options, timings);
    if (!step.corrector.converged) {
      step.failure = "corrector";
      break;
    }
    const std::vector<NewContact> closing = closing_contacts(trial, step.corrector.dq);
    if (closing.empty()) {
      step.ok = true;
      break;
    }
    if (round == options.max_closing_rounds) {
      step.failure = "closing contacts";
      break;
    }
    // New overlaps become contacts with F_T = 0 and the corrector restarts from there (§S3.2).
    for (const NewContact& c : closing) trial.contacts.add(c.i, c.j, c.k1, c.k2);
    step.new_contacts += static_cast<int>(closing.size());
    dq = step.corrector.dq;
  }
  if (timings) timings->corrector += seconds_since(t0);
  if (!step.ok) return step;
  advance(trial, step.corrector.dq, step.corrector.states);
  net = std::move(trial);
  return step;
}

NewtonResult prepare(Network& net, const SolverOptions& options) {
  rebuild_degrees_of_freedom(net);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const std::vector<ContactState> states = evaluate_contacts(net, zero);
  const std::vector<ContactStatus> frozen = classify_contacts(states);
  NewtonResult polish =
      newton_equilibrium(net, zero, &frozen, residual_scale(net, states), options);
  if (!polish.converged)
    throw std::runtime_error("static preparation: the equilibrium polish did not converge "
                             "(relative residual " +
                             std::to_string(polish.residual_history.empty()
                                                ? -1.0
                                                : polish.residual_history.back()) +
                             "); is the configuration an equilibrium state?");
  advance(net, polish.dq, polish.states);
  rebuild_degrees_of_freedom(net);
  // An input far from equilibrium can leave a frozen-stick contact outside the cone; the exact
  // law then clips it, so finish with the corrector (a no-op for a polished MD state).
  const Eigen::VectorXd zero2 = Eigen::VectorXd::Zero(net.dofs.size);
  const std::vector<ContactState> after = evaluate_contacts(net, zero2);
  const ResidualScale scale = residual_scale(net, after);
  if (relative_residual(net, residual(net, zero2, after), scale) >= options.tolerance) {
    NewtonResult exact = newton_equilibrium(net, zero2, nullptr, scale, options);
    if (!exact.converged)
      throw std::runtime_error("static preparation: no equilibrium with the exact contact law");
    advance(net, exact.dq, exact.states);
    rebuild_degrees_of_freedom(net);
    polish.residual_history.insert(polish.residual_history.end(),
                                   exact.residual_history.begin(), exact.residual_history.end());
  }
  return polish;
}

}  // namespace granstab::statics
