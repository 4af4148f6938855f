// The predictor of a load step (STATIC.md §S3.1): the complementarity loop over contact
// statuses, its cycle resolution by an LCP, and the settling of floppy rotations.
#include "static/load_step.hpp"
#include "static/load_step_parts.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "static/backbone.hpp"
#include "static/closing_contacts.hpp"
#include "static/complementarity.hpp"
#include "static/linear_solvers.hpp"
#include "static/tangent.hpp"
namespace granstab::statics {

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

// The sliding contacts of the last solved LCP over many contacts, as a guess of the next one's
// support: a step cut back repeats the wide LCP of a status cycle from the same state (n = 2241
// five times on the N = 5600 path), which Lemke solved from scratch each time (~7 s).
// Forgotten at the start of every run (forget_lcp_supports), so that the bits of a run do not
// depend on the runs before it in this thread.
struct LcpSupportMemory {
  std::size_t contacts = 0;  // the network's contact count when it was set
  std::vector<char> sliding;
};
thread_local LcpSupportMemory lcp_memory;
constexpr int lcp_warm_min = 256;  // below, Lemke takes milliseconds
// LCPs of this many contacts or more go by active sets first (lcp_by_active_sets): a support
// tried costs one LU, 30-60 solves' worth (N = 1024 to 5600), M one solve per contact; so n / 32
// supports, within these bounds, are tried before M is formed. At N = 5600 the ones that
// converged took 1-8 supports; over 2168 contacts 32 supports wandered without converging.
constexpr int lcp_active_set_min = 64;
constexpr int lcp_active_set_trials_min = 4;
constexpr int lcp_active_set_trials_max = 16;

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
  SparseMatrix k = assemble_tangent(net, states, out.statuses, parts);
  const std::vector<char> kept = kept_dofs(net, states, out.statuses);
  const Reduction r = make_reduction(kept);
  // An exact LU of its own (no deferred factorisation: the LCP matrix needs n solves with this
  // K), unrefined like the load step's solves: only the statuses leave this function, decided
  // with a width of decision_tolerance far above the refinement's round-off.
  LuReuse reuse = default_lu_reuse();
  reuse.refine = reuse.refine && options.refine_solves;
  LuFactor lu(reuse);
  const auto t0 = Clock::now();
  // Shared with the factor: a guessed support's tangent is S plus the sliding contacts' terms.
  const auto s_matrix = std::make_shared<const SparseMatrix>(reduce(std::move(k), r));
  const bool factored = lu.factorize(s_matrix);  // k is not read again
  count_factorisation(timings, t0, lu);
  if (!factored) {
    out.how = "the tangent with the undecided contacts sticking is singular";
    return out;
  }
  const int n = static_cast<int>(u.size()), nk = static_cast<int>(r.reduced_to_full.size());
  const double k_n = net.material.k_n, k_t = net.material.k_t;
  // W and V have a contact's few dofs per column / row: sparse, so that V S^-1 W costs n^2 times
  // those few terms instead of a dense n x nk x n product (most of an LCP's CPU at N = 1400).
  std::vector<Eigen::Triplet<double>> w_terms, v_terms;
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
      w_terms.emplace_back(i, a, sg * k_t * s.rows.bt0[l]);
      v_terms.emplace_back(a, i, sg * k_t * s.rows.bt0[l] - s.mu * k_n * s.rows.bn[l]);
    }
  }
  SparseMatrix w(nk, n);
  w.setFromTriplets(w_terms.begin(), w_terms.end());
  Eigen::SparseMatrix<double, Eigen::RowMajor, int> v(n, nk);
  v.setFromTriplets(v_terms.begin(), v_terms.end());
  const Eigen::VectorXd b_reduced = reduce(b, r);
  const Eigen::VectorXd dq0 = lu.solve(b_reduced);
  const Eigen::VectorXd q = g + v * dq0;
  // O(1) entries: lambda in units of q_scale / K_T.
  const double q_scale = std::max(q.cwiseAbs().maxCoeff(), 1e-300);
  // The guess: the last wide LCP's sliding set, where it was over these contacts.
  const bool wide = n >= lcp_warm_min;
  const bool remembered = wide && lcp_memory.contacts == states.size();
  std::vector<int> guess;
  for (int a = 0; remembered && a < n; ++a)
    if (lcp_memory.sliding[u[a]]) guess.push_back(a);
  const LcpSystem system{*s_matrix, w, v, g, b_reduced, q, q_scale, k_t};
  std::optional<LcpResult> quick;
  if (n >= lcp_active_set_min) {
    // From the last wide LCP's sliding set, else the cycle's last statuses (with every contact
    // sliding, the tangent of a wide LCP at N = 5600 was near singular and the supports
    // oscillated).
    std::vector<char> start(n, 0);
    for (int a = 0; a < n && !remembered; ++a) start[a] = slides(last[u[a]]) ? 1 : 0;
    for (const int a : guess) start[a] = 1;
    const int trials = std::clamp(n / 32, lcp_active_set_trials_min, lcp_active_set_trials_max);
    quick = lcp_by_active_sets(system, std::move(start), options.decision_tolerance, trials, reuse,
                               timings);
  }
  const LcpResult lcp = quick ? std::move(*quick) : [&] {
    Eigen::MatrixXd y(nk, n);
    for (int a = 0; a < n; ++a) y.col(a) = lu.solve(Eigen::VectorXd(w.col(a)));
    Eigen::MatrixXd m = -(v * y);
    m.diagonal().array() += k_t;
    return solve_lcp(m / k_t, q / q_scale, options.decision_tolerance, max_enumerated,
                     remembered ? &guess : nullptr);
  }();
  if (wide && lcp.outcome == LcpResult::Outcome::solved) {
    lcp_memory.contacts = states.size();
    lcp_memory.sliding.assign(states.size(), 0);
    for (int a = 0; a < n; ++a)
      lcp_memory.sliding[u[a]] = lcp.lambda[a] > options.decision_tolerance;
  }
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

void forget_lcp_supports() { lcp_memory = {}; }

// The contract is in load_step_parts.hpp.
std::optional<LcpResult> lcp_by_active_sets(const LcpSystem& p, std::vector<char> in, double tol,
                                            int max_supports, const LuReuse& reuse,
                                            Timings* timings) {
  const Eigen::Index n = p.q.size();
  LcpResult result;
  result.outcome = LcpResult::Outcome::solved;
  if ((p.q / p.q_scale).minCoeff() >= -tol) {  // lambda = 0, phi = q: solve_lcp's first test
    result.lambda = Eigen::VectorXd::Zero(n);
    result.w = p.q / p.q_scale;
    result.how = "trivial";
    return result;
  }
  // UMFPACK at every size: a KLU factor would join its pattern's spares, whose pivot orders
  // later refactorisations take (klu_factor.cpp), and move the rest of the run by round-off.
  LuReuse own = reuse;
  own.klu_max_dofs = 0;
  std::unordered_set<std::string> seen{std::string(in.begin(), in.end())};
  for (int trial = 0; trial < max_supports; ++trial) {
    // The sliding terms go into S's own entries (a contact's block is in S's pattern), so that
    // the factorisation meets a pattern already analysed.
    SparseMatrix sliding = p.s;
    Eigen::VectorXd w_g = Eigen::VectorXd::Zero(p.s.rows());
    for (Eigen::Index c = 0; c < n; ++c) {
      if (!in[c]) continue;
      for (SparseMatrix::InnerIterator wi(p.w, c); wi; ++wi) {
        w_g[wi.row()] += wi.value() * p.g[c] / p.k_t;
        for (Eigen::SparseMatrix<double, Eigen::RowMajor, int>::InnerIterator vj(p.v, c); vj; ++vj)
          sliding.coeffRef(wi.row(), vj.col()) -= wi.value() * vj.value() / p.k_t;
      }
    }
    sliding.makeCompressed();
    LuFactor lu(own);
    const auto t0 = Clock::now();
    const bool factored = lu.factorize(std::move(sliding));
    count_factorisation(timings, t0, lu);
    if (!factored) return std::nullopt;
    const Eigen::VectorXd dq = lu.solve(p.b + w_g);
    const Eigen::VectorXd phi = p.g + p.v * dq;  // on the support: -K_T lambda
    result.lambda = Eigen::VectorXd::Zero(n);
    result.w = Eigen::VectorXd::Zero(n);
    Eigen::Index worst = -1;
    double worst_value = -tol;
    std::vector<char> next = in;
    for (Eigen::Index c = 0; c < n; ++c) {
      double& unknown = in[c] ? result.lambda[c] : result.w[c];
      unknown = (in[c] ? -phi[c] : phi[c]) / p.q_scale;
      if (!std::isfinite(unknown)) return std::nullopt;
      if (!(unknown < -tol)) continue;
      next[c] = !in[c];
      if (unknown < worst_value) {
        worst = c;
        worst_value = unknown;
      }
    }
    if (worst >= 0) {
      // Flipping every violation at once can cycle (period 3 over 2168 contacts at N = 5600):
      // from a support seen before, only the worst one flips.
      if (!seen.insert(std::string(next.begin(), next.end())).second) {
        next = in;
        next[worst] = !in[worst];
        seen.insert(std::string(next.begin(), next.end()));
      }
      in = std::move(next);
    } else {
      result.lambda = result.lambda.cwiseMax(0.0);
      result.how =
          trial == 0 ? "support guessed" : "active sets (" + std::to_string(trial + 1) + ")";
      return result;
    }
  }
  return std::nullopt;
}

PredictorResult predict(const Network& net, const SolverOptions& options, Timings* timings,
                        const Eigen::VectorXd* rhs, const PredictorResult* warm, bool determinant,
                        std::vector<ContactState>* start_states) {
  const auto loop_start = Clock::now();
  const SolvePhase phase_before = lu_statistics().phase;
  PredictorResult p;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  p.start_states = start_states ? std::move(*start_states) : evaluate_contacts(net, zero);
  const std::vector<ContactState>& states = p.start_states;
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
  // A step's r0 holds the start's residual, known from the check at that state; the check's
  // increment holds none (check_state).
  PinnedRowTest pinned_test;
  pinned_test.tolerance = eta;
  if (!rhs && warm && warm->start_residual.size() == net.dofs.size)
    pinned_test.start_residual = &warm->start_residual;
  std::unordered_map<std::string, int> seen;  // status vector -> its index in history
  std::vector<std::string> history;
  std::shared_ptr<LuFactor> factor;
  // Where factorisations are deferred (LuReuse::krylov_min_dofs), the iterates of a loop, which
  // share one state and differ in the statuses of a few contacts, are low-rank updates of a
  // recent LU when they can be (the check's first LU, at this state). Otherwise the check's
  // later iterates are deferred, and the others factorised. The check's first: its determinant
  // is wanted, and GMRES preconditioned by the last state's LU mostly failed on it. A step's:
  // deferred, 322 of their 527 GMRES solves in q1 at N = 5600 went over the bound; factorised,
  // their LU is also a nearer preconditioner for the corrector, and that q1 took 12 % less time
  // (as long as before at N = 1024 and 1400; docs/notes/2026-12-06-bench-static-history.md).
  LuReuse reuse = lu_reuse(options);
  LuReuse first = reuse;  // the loop's first factorisation
  if (reuse.krylov) {
    reuse.low_rank = true;
    reuse.low_rank_min_dofs = reuse.krylov_min_dofs;
    first = reuse;
    first.krylov = false;
    reuse.krylov = determinant;
  }
  bool factorised_once = false;
  int lcp_rounds = 0;
  std::string last_resolved;  // the statuses the last LCP round set
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
      const std::string resolved(reinterpret_cast<const char*>(p.statuses.data()),
                                 p.statuses.size());
      if (resolved == last_resolved) {
        // The same statuses as the last round's: the iterates from them are the last round's
        // again (the status update reads the statuses only), so is the cycle they end in, and so
        // is the next LCP's input (slide signs and undecided contacts are set by those iterates).
        // Every round left would repeat this one until max_lcp_rounds: stop with its failure.
        p.failure = "cycle";
        break;
      }
      last_resolved = resolved;
      seen.clear();
      history.clear();
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
    if (it == 0 && warm && warm->factor && warm->statuses == p.statuses && warm->tangent &&
        warm->tangent->rows() == net.dofs.size) {
      // Same state and statuses as the stability check that accepted it: reuse its factor
      // (its K_load differs by the load increment of the check only, O(1e-6 dq P A0)).
      p.tangent = warm->tangent;
      p.kept = warm->kept;
      factor = warm->factor;
      const auto t0 = Clock::now();
      solved =
          solve_factored(net, *p.tangent, p.kept, *factor, r0, p.dq, &pinned_test, &unbalanced);
      if (timings) timings->factorisation += seconds_since(t0);
    } else {
      auto t0 = Clock::now();
      TangentParts parts;
      parts.fixed_pattern = options.fixed_pattern;
      // Swapped in: make_shared<SparseMatrix>(assemble_tangent(...)) would copy it.
      auto tangent = std::make_shared<SparseMatrix>();
      assemble_tangent(net, states, p.statuses, parts).swap(*tangent);
      p.tangent = std::move(tangent);
      p.kept = kept_dofs(net, states, p.statuses);
      if (timings) timings->assembly += seconds_since(t0);
      factor = std::make_shared<LuFactor>(factorised_once ? reuse : first);
      factorised_once = true;
      solved =
          solve_kept(net, p.tangent, p.kept, r0, *factor, p.dq, timings, &pinned_test, &unbalanced);
    }
    if (solved == Solve::singular) {
      // A disk left with one closed contact (its others open under these statuses) has a
      // singular block: one contact holds two of its three dofs. It carries no force in any
      // equilibrium, so in a step (not the check, whose increment is infinitesimal) that contact
      // opens too: the disk is then dropped (kept_dofs) and the corrector lets it go.
      bool opened = false;
      if (!determinant) {
        std::vector<char> closed(nc);
        for (std::size_t c = 0; c < nc; ++c) closed[c] = p.statuses[c] != ContactStatus::open;
        for (const int c : lone_contacts(net, closed)) {
          if (c < 0) continue;
          p.statuses[c] = ContactStatus::open;
          undecided[c] = 1;
          opened = true;
        }
      }
      if (opened) continue;
      p.failure = "singular";
      break;
    }
    if (solved == Solve::pinned_out_of_balance) {
      // Not a singular K: these statuses have no solution (kept_dofs, backbone.hpp).
      const std::vector<int> stuck =
          sliding_contacts_of_gear_clusters(net, states, p.statuses, unbalanced);
      if (stuck.empty()) {
        // No gear cluster: a loaded disk whose contacts all open under these statuses, its dofs
        // dropped. Resolved, a step's predictor lets it go and the corrector, which moves every
        // disk on the full equilibrium, decides whether its contacts close (its rates are those
        // of a near-rattler: the status loop swung ~260 statuses per iterate when they were held
        // closed instead, series B). The check keeps the failure: under an infinitesimal
        // increment a loaded contact cannot open, so there these statuses are no solution.
        if (!options.resolve_unbalanced_rows || rhs) {
          p.failure = "dropped rows out of balance";
          p.unbalanced_rows = true;
          break;
        }
      } else {
        // Some sliding contact of each unbalanced gear cluster must stick. Which ones is the LCP
        // of those contacts (the others held); if Lemke does not solve it, all of them are tried
        // sticking and the loop (and its LCP, if it cycles) decides which slide again. No
        // enumeration: a cluster can hold every contact (the 16-disk lattice: 48), and 2^18
        // bases took 0.9 s of the lattice's 1 s q1 for the same result.
        if (!options.resolve_unbalanced_rows) {
          p.failure = "pinned rotation rows out of balance";
          p.unbalanced_rows = true;
          break;
        }
        std::vector<char> cluster(nc, 0);
        std::vector<double> sign(nc, 0.0);
        for (const int c : stuck) {
          cluster[c] = 1;
          sign[c] = p.statuses[c] == ContactStatus::slide_positive ? 1.0 : -1.0;
          undecided[c] = 1;
        }
        const LcpResolution lcp = resolve_by_lcp(net, states, critical, r0, p.statuses, cluster,
                                                 sign, 0, options, timings);
        if (lcp.outcome == LcpResult::Outcome::solved) {
          p.statuses = lcp.statuses;
        } else {
          for (const int c : stuck) p.statuses[c] = ContactStatus::stick;
        }
        continue;
      }
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

}  // namespace granstab::statics
