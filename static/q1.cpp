#include "static/q1.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "static/backbone.hpp"
#include "static/hill.hpp"
#include "static/linear_solvers.hpp"
#include "static/stability_check.hpp"

namespace granstab::statics {

const char* criterion_name(Criterion c) {
  switch (c) {
    case Criterion::none:
      return "none";
    case Criterion::existence:
      return "existence";
    case Criterion::bifurcation:
      return "bifurcation";
  }
  return "none";
}

const char* step_control_name(StepControl s) {
  return s == StepControl::fixed ? "fixed" : "adaptive";
}

namespace {

// On the cone to round-off (SPEC §1.1): at a converged state the trial force of a sliding
// contact sits exactly on the cone, so its evaluated status alone would say stick.
int count_sliding(const std::vector<ContactState>& states) {
  int n = 0;
  for (const ContactState& s : states)
    if (s.frictional && s.f_n > 0.0 && is_sliding(s.f_t, s.f_n, s.mu)) ++n;
  return n;
}

// states: evaluate_contacts(net, 0).
CurvePoint measure(const Network& net, const std::vector<ContactState>& states, double lambda,
                   const std::array<double, 2>& reference) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  CurvePoint p;
  p.load = lambda;
  const std::array<double, 2> sigma = contact_stress(net, zero, states);
  p.q = sigma[0] != 0.0 ? sigma[1] / sigma[0] - 1.0 : 0.0;
  p.eps1 = 1.0 - net.length[0] / reference[0];
  p.eps2 = 1.0 - net.length[1] / reference[1];
  p.epsv = 1.0 - net.area() / (reference[0] * reference[1]);
  p.n_sliding = count_sliding(states);
  return p;
}

// §S3.3 adaptive: the load increment from the state to the first status event along the rate of
// its check (the statuses of the next increment, the response linear in the load): a sticking
// contact reaching the cone, or a contact opening. Gaps closing are not predicted (the step then
// shows the new contact and is redone). The rate is the check's solution for its 1e-6 step, so
// imposed strains and geometric terms are in it; its round-off (~1e-7 relative) is harmless here.
// s0: evaluate_contacts(net, 0).
double predicted_event(const Network& net, const std::vector<ContactState>& s0, double lambda,
                       double step, const LoadPath& path, const PredictorResult& check) {
  if (!check.ok || check.dq.size() != net.dofs.size) return 0.0;
  Network probe = net;
  path(probe, lambda + 1e-6 * step);
  const double dl = (lambda + 1e-6 * step) - lambda;
  const std::vector<ContactState> s1 = evaluate_contacts(probe, check.dq);
  double t = std::numeric_limits<double>::infinity();
  const auto reach = [&t](double g0, double g1) {  // g0 + g1 x = 0 with g0 >= 0
    if (g1 < 0.0) t = std::min(t, std::max(g0, 0.0) / -g1);
  };
  for (std::size_t c = 0; c < s0.size() && c < check.statuses.size(); ++c) {
    if (!(s0[c].f_n > 0.0) || check.statuses[c] == ContactStatus::open) continue;
    const double b = (s1[c].f_n - s0[c].f_n) / dl;
    reach(s0[c].f_n, b);
    if (!s0[c].frictional || check.statuses[c] != ContactStatus::stick) continue;
    const double a = (s1[c].f_t - s0[c].f_t) / dl;
    reach(s0[c].mu * s0[c].f_n - s0[c].f_t, s0[c].mu * b - a);
    reach(s0[c].mu * s0[c].f_n + s0[c].f_t, s0[c].mu * b + a);
  }
  return t;
}

// §S3.3 adaptive: the step changed no status when no contact closed, and its predictor's statuses
// and those the corrector ended on (each contact's Coulomb return over the whole step) are those
// of the start's check; the end state's check is compared by the caller. A contact that reached
// the cone inside the step and slid shows only in the corrector's: the end state's check may
// find it unloading. (Contacts on the cone at the start that unload stick from the start on.)
bool same_statuses(const PredictorResult& start, const StepResult& s) {
  if (s.new_contacts != 0 || s.predictor.statuses != start.statuses) return false;
  const std::vector<ContactState>& end = s.corrector.states;
  if (end.size() != start.statuses.size()) return false;
  for (std::size_t c = 0; c < end.size(); ++c) {
    const bool open = end[c].status == ContactStatus::open;
    if (open != (start.statuses[c] == ContactStatus::open)) return false;
    if (!open && end[c].frictional && end[c].status != start.statuses[c]) return false;
  }
  return true;
}

// The rows at the multiples of dq strictly inside a step without status change (lo to hi):
// linear interpolation of the measured columns, marked as such; the other columns are hi's (the
// contacts on the cone at hi are those sliding all along, see same_statuses).
void add_interpolated_rows(StabilityResult& result, const CurvePoint& lo, const CurvePoint& hi,
                           double lambda0, double dq) {
  const double first = std::floor((lo.load - lambda0) / dq + 1e-6) + 1.0;
  for (double k = first; lambda0 + k * dq < hi.load - 1e-6 * dq; k += 1.0) {
    CurvePoint p = hi;
    p.load = lambda0 + k * dq;
    const double w = (p.load - lo.load) / (hi.load - lo.load);
    const auto at = [w](double a, double b) { return a + w * (b - a); };
    p.q = at(lo.q, hi.q);
    p.eps1 = at(lo.eps1, hi.eps1);
    p.eps2 = at(lo.eps2, hi.eps2);
    p.epsv = at(lo.epsv, hi.epsv);
    p.hill = std::numeric_limits<double>::quiet_NaN();
    p.newton_iterations = 0;
    p.new_contacts = 0;
    p.interpolated = true;
    result.curve.push_back(p);
    ++result.interpolated_rows;
  }
}

std::string even_crossing_detail(int negative, const char* where) {
  return "K(active set) has " + std::to_string(negative) +
         " real negative eigenvalues with det K > 0 " + where +
         " (an even number crossed zero within one step)";
}

// The Hill indicator of the state, warm-started from the one before (`last`, updated).
double hill_of(const Network& net, HillResult& last) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const std::vector<ContactState> states = evaluate_contacts(net, zero);
  const std::vector<ContactStatus> statuses = classify_contacts(states);
  const SparseMatrix k = assemble_tangent(net, states, statuses);
  const Reduction r = make_reduction(kept_dofs(net, states, statuses));
  HillResult h = hill_indicator(reduce(k, r), &last);
  const double value = h.ok ? h.min_eigenvalue : std::numeric_limits<double>::quiet_NaN();
  last = std::move(h);
  return value;
}

// Inverse iteration with the LU factor of K on the kept dofs: converges to the eigenvector of the
// smallest |eigenvalue|, the null vector when K is (nearly) singular.
Eigen::VectorXd softest_mode(const PredictorResult& p) {
  const Reduction r = make_reduction(p.kept);
  const SparseMatrix k = reduce(*p.tangent, r);
  const int n = static_cast<int>(k.rows());
  if (n == 0) return Eigen::VectorXd::Zero(p.tangent->rows());
  LuFactor lu;
  Eigen::VectorXd v = Eigen::VectorXd::Ones(n).normalized();
  if (lu.factorize(k)) {
    for (int it = 0; it < 50; ++it) v = lu.solve(v).normalized();
  } else {
    const HillResult h = hill_indicator(k);
    if (h.ok) v = h.mode;
  }
  return expand(v, r, static_cast<int>(p.tangent->rows()));
}

// The sliding contacts at q1: sliding at the last stable state, or made to slide in some iterate
// of the failed attempt beyond the bracket (which starts from that state).
void record_instability(StabilityResult& result, const Network& net, const PredictorResult& p,
                        const std::vector<char>& beyond) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const std::vector<ContactState> states = evaluate_contacts(net, zero);
  for (std::size_t c = 0; c < states.size(); ++c) {
    const ContactState& s = states[c];
    if (!s.frictional || s.f_n <= 0.0) continue;
    const bool slides_beyond = c < beyond.size() && beyond[c];
    if (!slides_beyond && !is_sliding(s.f_t, s.f_n, s.mu)) continue;
    result.sliding_at_q1.push_back({net.contacts.i[c], net.contacts.j[c], net.contacts.k1[c],
                                    net.contacts.k2[c], s.f_n, s.f_t});
  }
  if (!p.tangent || p.tangent->rows() != net.dofs.size) return;
  const Eigen::VectorXd v = softest_mode(p);
  const DofMap& m = net.dofs;
  result.mode.assign(3 * net.n_disks(), 0.0);
  result.mode_disk_active.assign(net.n_disks(), 0);
  const auto kept = [&p](int d) { return d >= 0 && p.kept[d]; };
  for (std::size_t i = 0; i < net.n_disks(); ++i) {
    result.mode_disk_active[i] = kept(m.ux[i]) || kept(m.uy[i]) || kept(m.theta[i]);
    if (m.ux[i] >= 0) result.mode[3 * i] = v[m.ux[i]];
    if (m.uy[i] >= 0) result.mode[3 * i + 1] = v[m.uy[i]];
    if (m.theta[i] >= 0) result.mode[3 * i + 2] = v[m.theta[i]];
  }
  for (int a = 0; a < 2; ++a) result.mode_cell[a] = m.e[a] >= 0 ? v[m.e[a]] : 0.0;
}

}  // namespace

StabilityResult trace_to_instability(Network net, double lambda0, const LoadPath& path,
                                     const std::array<double, 2>& reference_length,
                                     const Q1Options& options) {
  if (!(options.dq > 0.0) || !(options.dq_min > 0.0) || options.dq_min > options.dq)
    throw std::invalid_argument("Q1Options: need 0 < dq_min <= dq");
  StabilityResult result;
  result.step_control = options.steps;
  // Deferred factorisations are preconditioned by earlier ones, wide LCPs start from an earlier
  // support: start every run from none, so that a run gives the same bits whatever ran before
  // it in this thread.
  forget_factorisations();
  forget_lcp_supports();
  path(net, lambda0);
  result.polish = polish_start(net, options.solver);
  double lambda = lambda0;
  double step = options.dq;
  // The contacts of the state (evaluate_contacts(net, 0)): its check, its row and its event use
  // them.
  std::vector<ContactState> contacts = evaluate_contacts(net, Eigen::VectorXd::Zero(net.dofs.size));
  CurvePoint point = measure(net, contacts, lambda, reference_length);
  if (options.on_accepted) options.on_accepted(lambda, net);

  // The start itself may already be unstable (no increment has a stable consistent solution).
  // Floppy rotations out of balance are settled exactly there, as at the step floor below (a
  // loaded disk whose contacts all open stays a failure of a check: §S3.5).
  SolverOptions exact = options.solver;
  exact.resolve_unbalanced_rows = true;
  PredictorResult check =
      check_state(net, contacts, lambda, step, path, options.solver, &result.timings);
  if (check.unbalanced_rows)
    check = check_state(net, contacts, lambda, step, path, exact, &result.timings);
  Spectrum spectrum = spectrum_of(net, contacts, check, options.count_negative_eigenvalues);
  int negative = spectrum.negative;
  point.determinant_sign = check.determinant_sign;
  point.negative_eigenvalues = negative;
  HillResult hill_last;
  int states = 0;  // accepted states in the curve (not the interpolated rows)
  // Logged at the start and at every hill_every-th accepted state after it.
  auto hill_due = [&] { return options.hill_every > 0 && states % options.hill_every == 0; };
  if (hill_due()) point.hill = hill_of(net, hill_last);
  result.curve.push_back(point);
  ++states;
  Criterion failure = Criterion::none;
  std::string detail;
  if (!stable(check, negative)) {
    failure = check.ok ? Criterion::bifurcation : Criterion::existence;
    detail = !check.ok                     ? "predictor at the start: " + check.failure
             : check.determinant_sign <= 0 ? std::string("det K <= 0 at the start")
                                           : even_crossing_detail(negative, "at the start");
    result.q1 = lambda;
    result.q1_bracket = {lambda, lambda};
    result.criterion = failure;
    result.detail = detail;
    record_instability(result, net, check, check.ever_sliding);
    result.network_at_q1 = net;
    return result;
  }
  PredictorResult last_check = check;
  int attempts = 0;
  bool quiet = false;  // the last accepted step changed no status
  const auto report_progress = [&](double at) {
    if (options.on_progress)
      options.on_progress(
          {at, states, attempts, result.curve.back().n_sliding, step, false, quiet});
  };
  report_progress(lambda);

  const double dq = options.dq;
  const bool adaptive = options.steps == StepControl::adaptive;
  // Above dq (a relative margin: loads are sums of steps) a step must change no status.
  const double dq_above = dq * (1.0 + 1e-9);
  const double max_step = adaptive ? std::max(1.0, options.max_step_factor) * dq : dq;
  const double inf = std::numeric_limits<double>::infinity();
  double event_below = inf;  // adaptive: a status change is known to happen below this load
  int successes_since_cut = 0;
  // The load that the latest cut step (at most dq) failed to reach, while every step accepted
  // since then changed no status; otherwise inf. Such steps are elastic on one status set, so the
  // state they reach lies on the failed step's path (to the O(step^2) of the tangential measure)
  // and an attempt at that load from there fails again (63 of 64 did in series A's q1). So it is
  // halved before it is made, except at the floor, where the bracket needs the failure: the end
  // bracket takes one attempt per halving instead of two.
  double failed_load = inf;
  std::vector<char> beyond;  // contacts the latest failed attempt made slide
  // A status set with dropped rows out of balance (floppy rotations, a loaded disk whose contacts
  // all open) has no solution, like any inconsistent set:
  // the step is halved (§S3.3), and smaller steps usually reach other statuses. Only the attempt
  // at the floor settles them exactly (SolverOptions::resolve_unbalanced_rows) before the
  // failure may count as q1: there the rate problem itself is decided. (Settling them in every
  // step takes larger steps through non-unique finite-step solutions: docs/validation.md.) The
  // halvings closed in on that load, and the settled step crossed it: the step returns to dq at
  // once, not by doublings from the floor (26 more states per such crossing on series A). After
  // other cuts it still doubles: returning to dq there took periodic-n100 at mu = 0.15 onto the
  // path that stops at 0.299 (dq = 1e-3), with more rejected steps.
  bool at_floor_exact = false;
  while (result.steps < options.max_steps && lambda < options.load_stop) {
    const SolverOptions& solver = at_floor_exact ? exact : options.solver;
    Network trial = net;
    path(trial, lambda + step);
    // The state's contacts, where the path moved loads that they do not read.
    std::vector<ContactState> start;
    if (same_contacts(net, trial)) start = contacts;
    const StepResult s =
        load_step(trial, solver, &result.timings, &last_check, start.empty() ? nullptr : &start);
    ++attempts;
    bool accepted = false;
    bool unbalanced = s.predictor.unbalanced_rows;
    beyond = s.predictor.ever_sliding;
    Spectrum next;
    std::vector<ContactState> trial_contacts;  // evaluate_contacts(trial, 0), once checked
    const bool big = step > dq_above;
    if (s.ok && big && !same_statuses(last_check, s)) {
      detail = "status change in a step above dq";  // redone at dq below, no check needed
    } else if (s.ok) {
      rebuild_degrees_of_freedom(trial);
      trial_contacts = evaluate_contacts(trial, Eigen::VectorXd::Zero(trial.dofs.size));
      PredictorResult trial_check =
          check_state(trial, trial_contacts, lambda + step, step, path, solver, &result.timings);
      check = std::move(trial_check);
      unbalanced = check.unbalanced_rows;
      next =
          spectrum_of(trial, trial_contacts, check, options.count_negative_eigenvalues, &spectrum);
      negative = next.negative;
      if (big && check.ok && check.statuses != last_check.statuses) {
        detail = "status change in a step above dq";
        beyond.clear();
      } else if (stable(check, negative)) {
        accepted = true;
      } else if (check.ok) {
        failure = Criterion::bifurcation;
        detail = check.determinant_sign <= 0 ? "det K(active set) <= 0 beyond the bracket"
                                             : even_crossing_detail(negative, "beyond the bracket");
      } else {
        failure = Criterion::existence;
        detail = "no consistent statuses beyond the bracket: " + check.failure;
      }
      if (!accepted) beyond.clear();  // the failed check ran on another contact list
    } else {
      failure = Criterion::existence;
      detail = s.failure;
    }
    if (accepted) {
      const bool settled_at_floor = at_floor_exact;
      at_floor_exact = false;
      net = std::move(trial);
      contacts = std::move(trial_contacts);
      const double step_taken = step;
      lambda += step;
      ++result.steps;
      CurvePoint p = measure(net, contacts, lambda, reference_length);
      p.determinant_sign = check.determinant_sign;
      p.negative_eigenvalues = negative;
      p.newton_iterations = static_cast<int>(s.corrector.residual_history.size()) - 1;
      p.new_contacts = s.new_contacts;
      if (hill_due()) p.hill = hill_of(net, hill_last);
      const CurvePoint before = result.curve.back();  // a copy: the rows go into the same vector
      if (step_taken > dq_above) add_interpolated_rows(result, before, p, lambda0, dq);
      result.curve.push_back(p);
      ++states;
      if (options.on_accepted) options.on_accepted(lambda, net);
      if (options.stop_when && options.stop_when(result.curve.back())) break;
      quiet = same_statuses(last_check, s) && check.statuses == last_check.statuses;
      const double stable_to =
          adaptive ? stable_span(spectrum, last_check, next, check, quiet, step_taken) : 0.0;
      const bool grow = adaptive && step_taken >= dq / (1.0 + 1e-9) && stable_to >= 2.0 * dq;
      const double event = grow ? predicted_event(net, contacts, lambda, step, path, check) : 0.0;
      last_check = std::move(check);  // check is set again before it is read
      spectrum = std::move(next);     // with its witness; a deferred count reads last_check's K
      report_progress(lambda);
      if (lambda >= event_below - 1e-6 * dq) event_below = inf;  // passed it
      if (grow) {
        // Adaptive: up to the multiple of dq before the predicted event (a margin for the
        // nonlinearity of the path), halfway to an unpredicted one known to lie ahead, not beyond
        // the first multiple of dq at or past load_stop (where fixed steps end too).
        double span = std::min({max_step, stable_to, 0.98 * event, 0.5 * (event_below - lambda)});
        span = std::floor((lambda + span - lambda0) / dq + 1e-6) * dq + lambda0 - lambda;
        if (options.load_stop < lambda + span)
          span = std::ceil((options.load_stop - lambda) / dq - 1e-6) * dq;
        step = std::max(dq, span);
        successes_since_cut = 0;
      } else if (step > dq_above || settled_at_floor) {
        // Back to dq after a step above it, and after a floor step that settled rows (above).
        step = dq;
        successes_since_cut = 0;
      } else if (++successes_since_cut >= 2 && step < dq) {
        // Grow back after cuts, never beyond the user's step.
        step = std::min(dq, 2.0 * step);
        successes_since_cut = 0;
      }
      if (!quiet || lambda >= failed_load - 1e-9 * dq) failed_load = inf;
      if (lambda + step >= failed_load - 1e-9 * dq) {
        while (lambda + step >= failed_load - 1e-9 * dq && step * 0.5 >= options.dq_min)
          step *= 0.5;
        successes_since_cut = 0;
      }
      continue;
    }
    ++result.rejected[detail];
    report_progress(lambda);
    if (step > dq_above) {
      // Adaptive: a step above dq that reached its end but changed a status the rates did not
      // predict (a gap closing, the path's nonlinearity), or whose end state fails the check, is
      // bisected towards that on the dq grid; one that found no end state is redone at dq. Events
      // and the bracket are then resolved from dq as with fixed steps.
      if (s.ok) event_below = lambda + step;
      const double half =
          std::floor((lambda + 0.5 * step - lambda0) / dq + 1e-6) * dq + lambda0 - lambda;
      step = s.ok ? std::max(dq, half) : dq;
      successes_since_cut = 0;
      continue;
    }
    // §S3.3: halve on failure down to the floor; the bracket is then [lambda, lambda + step].
    failed_load = lambda + step;
    if (step * 0.5 < options.dq_min) {
      if (unbalanced && !at_floor_exact) {
        at_floor_exact = true;  // the same attempt again, settling the unbalanced rows
        continue;
      }
      result.q1 = lambda;
      result.q1_bracket = {lambda, lambda + step};
      result.criterion = failure;
      result.detail = detail;
      record_instability(result, net, last_check, beyond);
      result.network_at_q1 = net;
      result.attempts = attempts;
      return result;
    }
    step *= 0.5;
    successes_since_cut = 0;
  }
  result.q1 = lambda;
  result.q1_bracket = {lambda, std::numeric_limits<double>::infinity()};
  result.criterion = Criterion::none;
  result.detail = "stopped while stable";
  result.network_at_q1 = net;
  result.attempts = attempts;
  return result;
}

StartPolish polish_start(Network& net, const SolverOptions& options) {
  const Network before = net;
  const NewtonResult polish = prepare(net, options);
  StartPolish out;
  for (std::size_t i = 0; i < net.n_disks(); ++i) {
    const double u = std::hypot(net.x[i] - before.x[i], net.y[i] - before.y[i]);
    if (u > out.max_displacement) {
      out.max_displacement = u;
      out.max_displacement_disk = i;
    }
    out.max_rotation = std::max(out.max_rotation, std::abs(net.theta[i] - before.theta[i]));
  }
  for (int a = 0; a < 2; ++a)
    out.max_strain = std::max(out.max_strain, std::abs(net.length[a] / before.length[a] - 1.0));
  if (!polish.residual_history.empty()) {
    out.residual_before = polish.residual_history.front();
    out.residual_after = polish.residual_history.back();
  }
  return out;
}

// The static stepping of a configuration under the options' control.
static StabilityResult trace_from(const Configuration& config, const Q1Options& options) {
  Network net = network_from_configuration(config);
  const double sigma1 = config.stage.sigma_ext[0];
  if (!(sigma1 > 0.0)) throw std::invalid_argument("stage.sigma_ext[0]: must be > 0 for q1");
  net.constraints.cell_free = {true, options.control == Control::stress};
  net.constraints.remove_rattlers = true;
  const std::array<double, 2> reference = config.stage.reference_length;
  if (options.control == Control::stress) {
    const LoadPath path = [sigma1](Network& n, double q) {
      n.loading.sigma = {sigma1, sigma1 * (1.0 + q)};
    };
    const double q0 = config.stage.sigma_ext[1] / sigma1 - 1.0;
    return trace_to_instability(std::move(net), q0, path, reference, options);
  }
  // Strain control: e2 of the step takes L2 to L2_ref (1 - epsilon_2).
  const LoadPath path = [reference](Network& n, double eps2) {
    n.loading.e_imposed[1] = reference[1] * (1.0 - eps2) / n.length[1] - 1.0;
  };
  const double eps0 = 1.0 - config.cell.length[1] / reference[1];
  net.loading.sigma = {sigma1, config.stage.sigma_ext[1]};
  return trace_to_instability(std::move(net), eps0, path, reference, options);
}

StabilityResult find_q1(const Configuration& config, const Q1Options& options) {
  StabilityResult r = trace_from(config, options);
  // The end of the run for the progress lines, however it ended.
  if (options.on_progress && !r.curve.empty()) {
    options.on_progress(
        {r.curve.back().load, r.steps + 1, r.attempts, r.curve.back().n_sliding, 0.0, true});
  }
  return r;
}

}  // namespace granstab::statics
