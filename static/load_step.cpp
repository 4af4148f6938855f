#include "static/load_step.hpp"

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
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Solves K x = b on the kept dofs with a factor of the reduced K (pinned dofs stay 0). With
// check_pinned, the rows of pinned gear rotations must hold too (see kept_dofs): the predictor's
// test of a status set. The misfit of the pinned rows is compared with the largest size of the
// terms of a row, max_i (|K| |x| + |b|)_i, so that the round-off of K x (O(1e-16 cond(K)) of
// that) never decides it; a genuine misfit (sliding forces doing work in a gear mode) is a
// finite fraction of it. (Before: 1e-8 |b|, which ignores the size of K x.)
// The corrector's backtracking on |R| judges its steps itself. out_of_balance receives the disks
// whose dropped dofs (pinned gear rotations, or all dofs of a disk whose contacts are all open)
// carry such a misfit.
enum class Solve { solved, singular, pinned_out_of_balance };

Solve solve_factored(const Network& net, const SparseMatrix& k, const std::vector<char>& kept,
                     const LuFactor& lu, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                     bool check_pinned, double tolerance,
                     std::vector<int>* out_of_balance = nullptr) {
  const Reduction r = make_reduction(kept);
  Eigen::VectorXd reduced;
  if (!lu.try_solve(reduce(b, r), reduced)) return Solve::singular;
  x = expand(reduced, r, static_cast<int>(k.rows()));
  if (!check_pinned || static_cast<Eigen::Index>(r.reduced_to_full.size()) == k.rows())
    return Solve::solved;
  const Eigen::VectorXd misfit = k * x - b;
  const Eigen::VectorXd size = k.cwiseAbs() * x.cwiseAbs() + b.cwiseAbs();
  const double limit = tolerance * std::max(size.maxCoeff(), 1e-300);
  double worst = 0.0;
  for (std::size_t i = 0; i < kept.size(); ++i)
    if (!kept[i]) worst = std::max(worst, std::abs(misfit[i]));
  if (worst <= limit) return Solve::solved;
  if (out_of_balance) {
    const DofMap& m = net.dofs;
    const auto off = [&](int d) { return d >= 0 && !kept[d] && std::abs(misfit[d]) > limit; };
    for (std::size_t i = 0; i < net.n_disks(); ++i)
      if (off(m.ux[i]) || off(m.uy[i]) || off(m.theta[i]))
        out_of_balance->push_back(static_cast<int>(i));
  }
  return Solve::pinned_out_of_balance;
}

Solve solve_kept(const Network& net, const SparseMatrix& k, const std::vector<char>& kept,
                 const Eigen::VectorXd& b, LuFactor& lu, Eigen::VectorXd& x, Timings* timings,
                 bool check_pinned, double tolerance = 0.0,
                 std::vector<int>* out_of_balance = nullptr) {
  const auto t0 = Clock::now();
  const Solve outcome =
      lu.factorize(reduce(k, make_reduction(kept)))
          ? solve_factored(net, k, kept, lu, b, x, check_pinned, tolerance, out_of_balance)
          : Solve::singular;
  if (timings) {
    timings->factorisation += seconds_since(t0);
    ++timings->factorisations;
    if (!lu.symbolic_reused()) ++timings->symbolic_analyses;
  }
  return outcome;
}

}  // namespace

LuReuse lu_reuse(const SolverOptions& options) {
  LuReuse reuse = default_lu_reuse();
  reuse.krylov = reuse.krylov || options.krylov_solves;
  reuse.refine = reuse.refine && options.refine_solves;
  return reuse;
}

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

namespace {

// B_N dq and B_T(q0) dq of a contact.
std::array<double, 2> contact_rates(const ContactState& s, const Eigen::VectorXd& dq) {
  double bn = 0.0, bt = 0.0;
  for (int a = 0; a < n_local; ++a)
    if (s.rows.dof[a] >= 0) {
      bn += s.rows.bn[a] * dq[s.rows.dof[a]];
      bt += s.rows.bt0[a] * dq[s.rows.dof[a]];
    }
  return {bn, bt};
}

bool slides(ContactStatus s) {
  return s == ContactStatus::slide_positive || s == ContactStatus::slide_negative;
}

ContactStatus slide_status(double sign) {
  return sign > 0.0 ? ContactStatus::slide_positive : ContactStatus::slide_negative;
}

// The status of a closed contact that the increment dq calls for (§S3.1), deciding every
// comparison with a tie width (docs/static.md, "Round-off-robust decisions"): tau is the
// round-off width of the increments' forces, the start forces add their own relative round-off.
// Inside the tie width the current status is kept (a deterministic tie-break, and a hysteresis
// that no round-off can flip). A contact critical at the start (on the cone to 1e-9) is judged by
// the sign of its complementarity increment phi = mu dF_N - s dF_T alone, never by
// |F_T| - mu F_N, which is round-off there.
ContactStatus next_status(const ContactState& s, bool critical, ContactStatus current,
                          const std::array<double, 2>& rate, double k_n, double k_t, double tau,
                          double relative) {
  const double d_fn = -k_n * rate[0], f_n = s.f_n + d_fn;
  const double tau_n = tau + relative * s.f_n;
  if (f_n < -tau_n || (f_n <= tau_n && current == ContactStatus::open)) return ContactStatus::open;
  if (!s.frictional) return ContactStatus::slide_positive;
  const double d_ft = -k_t * rate[1];
  if (!slides(current)) {
    const ContactStatus tie = ContactStatus::stick;  // also for a contact that was open
    if (critical) {
      const double sign = s.f_t > 0.0 ? 1.0 : -1.0;
      const double phi = s.mu * d_fn - sign * d_ft;
      return phi < -tau ? slide_status(sign) : tie;
    }
    const double f_t = s.f_t + d_ft;
    const double excess = std::abs(f_t) - s.mu * f_n;
    const double tau_t = tau + relative * s.mu * s.f_n;
    if (excess > tau_t) return slide_status(f_t);
    return excess < -tau_t ? ContactStatus::stick : tie;
  }
  // Plastic multiplier times K_T: dF_T = -K_T (B_T dq + s lambda) = s mu dF_N.
  const double sign = current == ContactStatus::slide_positive ? 1.0 : -1.0;
  const double k_t_lambda = -s.mu * d_fn - sign * k_t * rate[1];
  return k_t_lambda < -tau ? ContactStatus::stick : current;
}

struct LcpResolution {
  LcpResult::Outcome outcome = LcpResult::Outcome::undecided;
  std::vector<ContactStatus> statuses;
  std::string how;
};

// When the status iteration cycles: the rate problem over the contacts whose status it could not
// settle (undecided, stick <-> slide in direction sign[c]) is an LCP on the Schur complement of
// the tangent with those contacts sticking (STATIC.md §S3.1, second route): with S that tangent,
// W_c = s_c K_T B_T,c^T, V_c = s_c K_T B_T,c - mu K_N B_N,c,
//   S dq + W lambda = b,   phi = g + V dq + K_T lambda >= 0,   lambda >= 0,   lambda^T phi = 0,
// i.e. phi = g + V S^-1 b + (K_T I - V S^-1 W) lambda, g_c = mu F_N - s F_T the distance to the
// cone at the start (0 for a critical contact). All other contacts keep their last status.
LcpResolution resolve_by_lcp(const Network& net, const std::vector<ContactState>& states,
                             const std::vector<char>& critical, const Eigen::VectorXd& b,
                             const std::vector<ContactStatus>& last,
                             const std::vector<char>& undecided, const std::vector<double>& sign,
                             int max_enumerated, const SolverOptions& options, Timings* timings) {
  LcpResolution out;
  std::vector<int> u;
  for (std::size_t c = 0; c < states.size(); ++c)
    if (undecided[c] && states[c].frictional && states[c].f_n > 0.0 &&
        last[c] != ContactStatus::open && sign[c] != 0.0)
      u.push_back(static_cast<int>(c));
  if (u.empty()) {
    out.how = "no frictional contact among the undecided ones";
    return out;
  }
  out.statuses = last;
  for (const int c : u) out.statuses[c] = ContactStatus::stick;
  TangentParts parts;
  parts.fixed_pattern = options.fixed_pattern;
  const SparseMatrix k = assemble_tangent(net, states, out.statuses, parts);
  const std::vector<char> kept = kept_dofs(net, states, out.statuses);
  const Reduction r = make_reduction(kept);
  LuFactor lu;
  const auto t0 = Clock::now();
  const bool factored = lu.factorize(reduce(k, r));
  if (timings) {
    timings->factorisation += seconds_since(t0);
    ++timings->factorisations;
    if (!lu.symbolic_reused()) ++timings->symbolic_analyses;
  }
  if (!factored) {
    out.how = "the tangent with the undecided contacts sticking is singular";
    return out;
  }
  const int n = static_cast<int>(u.size()), nk = static_cast<int>(r.reduced_to_full.size());
  const double k_n = net.material.k_n, k_t = net.material.k_t;
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(nk, n), v = Eigen::MatrixXd::Zero(n, nk);
  Eigen::VectorXd g(n);
  bool pinned_touched = false;
  for (int a = 0; a < n; ++a) {
    const ContactState& s = states[u[a]];
    const double sg = sign[u[a]];
    g[a] = critical[u[a]] ? 0.0 : std::max(0.0, s.mu * s.f_n - sg * s.f_t);
    for (int l = 0; l < n_local; ++l) {
      const int d = s.rows.dof[l];
      if (d < 0) continue;
      const int i = r.full_to_reduced[d];
      if (i < 0) {
        pinned_touched = pinned_touched || s.rows.bt0[l] != 0.0 || s.rows.bn[l] != 0.0;
        continue;
      }
      w(i, a) += sg * k_t * s.rows.bt0[l];
      v(a, i) += sg * k_t * s.rows.bt0[l] - s.mu * k_n * s.rows.bn[l];
    }
  }
  const Eigen::VectorXd dq0 = lu.solve(reduce(b, r));
  Eigen::MatrixXd y(nk, n);
  for (int a = 0; a < n; ++a) y.col(a) = lu.solve(w.col(a));
  Eigen::VectorXd q = g + v * dq0;
  Eigen::MatrixXd m = -v * y;
  m.diagonal().array() += k_t;
  // O(1) entries: lambda in units of q_scale / K_T.
  const double q_scale = std::max(q.cwiseAbs().maxCoeff(), 1e-300);
  const LcpResult lcp = solve_lcp(m / k_t, q / q_scale, options.decision_tolerance, max_enumerated);
  out.how = lcp.how + " over " + std::to_string(n) + " contacts";
  out.outcome = lcp.outcome;
  if (lcp.outcome == LcpResult::Outcome::no_solution && pinned_touched) {
    // The pinned gear rows add equations that the reduced LCP does not see.
    out.outcome = LcpResult::Outcome::undecided;
    out.how += "; undecided contacts touch pinned gear rotations";
  }
  if (out.outcome == LcpResult::Outcome::solved)
    for (int a = 0; a < n; ++a)
      if (lcp.lambda[a] > options.decision_tolerance) out.statuses[u[a]] = slide_status(sign[u[a]]);
  return out;
}

}  // namespace

PredictorResult predict(const Network& net, const SolverOptions& options, Timings* timings,
                        const Eigen::VectorXd* rhs, const PredictorResult* warm, bool determinant) {
  const auto loop_start = Clock::now();
  const SolvePhase phase_before = lu_statistics().phase;
  PredictorResult p;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const std::vector<ContactState> states = evaluate_contacts(net, zero);
  const Eigen::VectorXd r0 = rhs ? *rhs : residual(net, zero, states);
  p.statuses = classify_contacts(states);
  if (warm && warm->ok && warm->statuses.size() == states.size()) {
    for (std::size_t c = 0; c < states.size(); ++c)
      if (p.statuses[c] != ContactStatus::open) p.statuses[c] = warm->statuses[c];
  }
  const std::size_t nc = states.size();
  std::vector<char> critical(nc, 0), undecided(nc, 0);
  std::vector<double> slide_sign(nc, 0.0);
  for (std::size_t c = 0; c < nc; ++c) {
    const ContactState& s = states[c];
    critical[c] = s.frictional && s.f_n > 0.0 && is_sliding(s.f_t, s.f_n, s.mu);
    if (critical[c]) slide_sign[c] = s.f_t > 0.0 ? 1.0 : -1.0;
  }
  p.ever_sliding.assign(nc, 0);
  const double k_n = net.material.k_n, k_t = net.material.k_t;
  const double eta = options.decision_tolerance;
  std::unordered_map<std::string, int> seen;  // status vector -> its index in history
  std::vector<std::string> history;
  std::shared_ptr<LuFactor> factor;
  int lcp_rounds = 0;
  p.failure = "iterations";
  for (int it = 0; it < options.max_status_iterations; ++it) {
    p.iterations = it + 1;
    if (timings) ++timings->status_iterations;
    const std::string key(reinterpret_cast<const char*>(p.statuses.data()), p.statuses.size());
    const auto found = seen.find(key);
    if (found != seen.end()) {
      // A cycle proves nothing by itself: decide the statuses it could not settle exactly. First
      // the LCP of the contacts whose status changes within the cycle (small: Lemke); if that
      // finds no solution, the LCP of every contact that changed status in the loop or is
      // critical, i.e. every contact that can change status under an infinitesimal increment
      // (enumerated when Lemke ends on a ray and there are few enough of them).
      std::vector<char> in_cycle(nc, 0);
      for (std::size_t h = found->second; h < history.size(); ++h)
        for (std::size_t c = 0; c < nc; ++c)
          if (history[h][c] != key[c]) in_cycle[c] = 1;
      LcpResolution lcp;
      if (lcp_rounds < options.max_lcp_rounds) {
        lcp = resolve_by_lcp(net, states, critical, r0, p.statuses, in_cycle, slide_sign, 0,
                             options, timings);
        if (lcp.outcome != LcpResult::Outcome::solved) {
          std::vector<char> wide = undecided;
          for (std::size_t c = 0; c < nc; ++c) wide[c] = wide[c] || critical[c];
          lcp = resolve_by_lcp(net, states, critical, r0, p.statuses, wide, slide_sign,
                               options.max_lcp_enumerated, options, timings);
        }
      }
      ++lcp_rounds;
      if (lcp.outcome == LcpResult::Outcome::no_solution) {
        p.failure = "no consistent statuses (LCP: " + lcp.how + ")";
        p.no_solution = true;
        break;
      }
      if (lcp.outcome != LcpResult::Outcome::solved) {
        p.failure = lcp.how.empty() ? "cycle" : "cycle (LCP undecided: " + lcp.how + ")";
        break;
      }
      p.statuses = lcp.statuses;
      seen.clear();
      history.clear();
      const std::string resolved(reinterpret_cast<const char*>(p.statuses.data()),
                                 p.statuses.size());
      seen.emplace(resolved, 0);
      history.push_back(resolved);
    } else {
      seen.emplace(key, static_cast<int>(history.size()));
      history.push_back(key);
    }
    lu_statistics().phase = !determinant ? SolvePhase::step_loop
                            : it == 0    ? SolvePhase::check_first
                                         : SolvePhase::check_later;
    Solve solved = Solve::solved;
    std::vector<int> unbalanced;
    if (it == 0 && warm && warm->factor && warm->statuses == p.statuses &&
        warm->tangent.rows() == net.dofs.size) {
      // Same state and statuses as the stability check that accepted it: reuse its factor
      // (its K_load differs by the load increment of the check only, O(1e-6 dq P A0)).
      p.tangent = warm->tangent;
      p.kept = warm->kept;
      factor = warm->factor;
      const auto t0 = Clock::now();
      solved = solve_factored(net, p.tangent, p.kept, *factor, r0, p.dq, true, eta, &unbalanced);
      if (timings) timings->factorisation += seconds_since(t0);
    } else {
      auto t0 = Clock::now();
      TangentParts parts;
      parts.fixed_pattern = options.fixed_pattern;
      p.tangent = assemble_tangent(net, states, p.statuses, parts);
      p.kept = kept_dofs(net, states, p.statuses);
      if (timings) timings->assembly += seconds_since(t0);
      factor = std::make_shared<LuFactor>(lu_reuse(options));
      solved =
          solve_kept(net, p.tangent, p.kept, r0, *factor, p.dq, timings, true, eta, &unbalanced);
    }
    if (solved == Solve::singular) {
      p.failure = "singular";
      break;
    }
    if (solved == Solve::pinned_out_of_balance) {
      // Not a singular K: these statuses have no solution (kept_dofs, backbone.hpp), so some
      // sliding contact of each unbalanced gear cluster must stick. Which ones is the LCP of
      // those contacts (the others held); if Lemke does not solve it, all of them are tried
      // sticking and the loop (and its LCP, if it cycles) decides which slide again. No
      // enumeration: a cluster can hold every contact (the 16-disk lattice: 48), and 2^18 bases
      // took 0.9 s of the lattice's 1 s q1 for the same result.
      const std::vector<int> stuck =
          sliding_contacts_of_gear_clusters(net, states, p.statuses, unbalanced);
      if (stuck.empty()) {
        p.failure = "dropped rows out of balance";
        break;
      }
      if (!options.resolve_floppy_rotations) {
        p.failure = "pinned rotation rows out of balance";
        p.unbalanced_rotations = true;
        break;
      }
      std::vector<char> cluster(nc, 0);
      std::vector<double> sign(nc, 0.0);
      for (const int c : stuck) {
        cluster[c] = 1;
        sign[c] = p.statuses[c] == ContactStatus::slide_positive ? 1.0 : -1.0;
        undecided[c] = 1;
      }
      const LcpResolution lcp =
          resolve_by_lcp(net, states, critical, r0, p.statuses, cluster, sign, 0, options, timings);
      if (lcp.outcome == LcpResult::Outcome::solved) {
        p.statuses = lcp.statuses;
      } else {
        for (const int c : stuck) p.statuses[c] = ContactStatus::stick;
      }
      continue;
    }
    // Complementarity checks on the linearised increment (§S3.1), with the tie width of this
    // iterate: eta times the largest contact force increment.
    std::vector<std::array<double, 2>> rates(nc);
    double largest = 0.0;
    for (std::size_t c = 0; c < nc; ++c) {
      if (states[c].f_n <= 0.0) continue;
      rates[c] = contact_rates(states[c], p.dq);
      largest = std::max({largest, std::abs(rates[c][0]), std::abs(rates[c][1])});
    }
    const double tau = eta * std::max(k_n, k_t) * largest;
    // A disk whose contacts are all open under these statuses has no dofs in this iterate (see
    // kept_dofs): its increment is undetermined, and the rates of its contacts computed with
    // u = 0 would depend on the translation gauge (which disk is pinned). They stay open; the
    // corrector, which moves every disk, decides whether they close.
    const DofMap& m = net.dofs;
    const auto dropped = [&](int i) { return i >= 0 && m.ux[i] >= 0 && !p.kept[m.ux[i]]; };
    bool consistent = true;
    for (std::size_t c = 0; c < nc; ++c) {
      const ContactState& s = states[c];
      if (s.f_n <= 0.0) continue;  // closing gaps are events for the corrector
      if (p.statuses[c] == ContactStatus::open &&
          (dropped(net.contacts.i[c]) || dropped(net.contacts.j[c])))
        continue;
      const ContactStatus next =
          next_status(s, critical[c], p.statuses[c], rates[c], k_n, k_t, tau, eta);
      if (next != p.statuses[c]) {
        consistent = false;
        undecided[c] = 1;
        p.statuses[c] = next;
      }
      if (s.frictional && slides(next)) {
        p.ever_sliding[c] = 1;
        slide_sign[c] = next == ContactStatus::slide_positive ? 1.0 : -1.0;
      }
    }
    if (consistent) {
      if (determinant || factor->factorised()) {
        // A deferred factorisation is made here (the check's sign, its eigenvalue count and the
        // next step's warm start use it); singular is then found only now.
        const auto t0 = Clock::now();
        if (determinant) lu_statistics().phase = SolvePhase::check_sign;
        p.determinant_sign = factor->determinant_sign();
        if (timings) timings->factorisation += seconds_since(t0);
        if (p.determinant_sign == 0) {
          p.failure = "singular";
          break;
        }
      }
      p.ok = true;
      p.failure.clear();
      p.factor = factor;
      break;
    }
  }
  if (timings) timings->complementarity += seconds_since(loop_start);
  lu_statistics().phase = phase_before;
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
    // Contacts that overlap stay (those of rattlers carry no force but overlap: see
    // evaluate_contact); open ones leave.
    if (!(states[c].frame.h > 0.0)) continue;
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
  step.predictor = predict(net, options, timings, nullptr, warm, false);
  if (!step.predictor.ok) {
    step.failure = "predictor: " + step.predictor.failure;
    return step;
  }
  const auto t0 = Clock::now();
  Network trial = net;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(trial.dofs.size);
  const ResidualScale scale = residual_scale(trial, evaluate_contacts(trial, zero));
  const SolvePhase phase_before = lu_statistics().phase;
  lu_statistics().phase = SolvePhase::chord;
  Eigen::VectorXd dq = chord_iterations(trial, step.predictor, step.predictor.dq, scale, options);
  lu_statistics().phase = SolvePhase::corrector;
  for (int round = 0;; ++round) {
    step.corrector = newton_equilibrium(trial, dq, nullptr, scale, options, timings);
    if (!step.corrector.converged) {
      step.failure = "corrector";
      break;
    }
    const std::vector<NewContact> closing =
        closing_contacts(trial, step.corrector.dq, options.push_rattlers);
    // A listed contact of a rattler carries no force (evaluate_contact); with push_rattlers an
    // active disk that overlaps it pushes it, as if it had just closed.
    // (Two rattlers never push each other, and walls push active disks only, as in
    // closing_contacts.)
    std::vector<int> rattlers;
    const auto rattler = [&trial](int d) { return trial.dofs.is_rattler(d); };
    for (std::size_t c = 0; c < trial.contacts.size() && options.push_rattlers; ++c) {
      const int a = trial.contacts.i[c], b = trial.contacts.j[c];
      if (is_wall(b) || !(step.corrector.states[c].frame.h > 0.0) || rattler(a) == rattler(b))
        continue;
      rattlers.push_back(rattler(a) ? a : b);
    }
    if (closing.empty() && rattlers.empty()) {
      step.ok = true;
      break;
    }
    if (round == options.max_closing_rounds) {
      step.failure = "closing contacts";
      break;
    }
    // New overlaps become contacts with F_T = 0 and the corrector restarts from there (§S3.2).
    // A rattler closed on by an active disk gets dofs now, so that it is pushed along.
    for (const NewContact& c : closing) {
      trial.contacts.add(c.i, c.j, c.k1, c.k2);
      for (const int d : {c.i, c.j})
        if (!is_wall(d) && !trial.dofs.active(d)) rattlers.push_back(d);
    }
    std::sort(rattlers.begin(), rattlers.end());
    rattlers.erase(std::unique(rattlers.begin(), rattlers.end()), rattlers.end());
    step.new_contacts += static_cast<int>(closing.size());
    dq = step.corrector.dq;
    activate_disks(trial, rattlers, dq);
  }
  if (timings) timings->corrector += seconds_since(t0);
  lu_statistics().phase = phase_before;
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
    throw std::runtime_error(
        "static preparation: the equilibrium polish did not converge "
        "(relative residual " +
        std::to_string(polish.residual_history.empty() ? -1.0 : polish.residual_history.back()) +
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
    polish.residual_history.insert(polish.residual_history.end(), exact.residual_history.begin(),
                                   exact.residual_history.end());
  }
  return polish;
}

}  // namespace granstab::statics
