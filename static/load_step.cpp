// One load step (STATIC.md §S3): the predictor (complementarity_loop.cpp), the corrector
// (corrector.cpp), and here what ties them: the step itself, advancing the network, preparing a
// start, the solves on the kept dofs.
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

namespace {

// solve_factored on a reduction already made (solve_kept makes it once for both parts).
Solve solve_reduced(const Network& net, const SparseMatrix& k, const std::vector<char>& kept,
                    const Reduction& r, const LuFactor& lu, const Eigen::VectorXd& b,
                    Eigen::VectorXd& x, const PinnedRowTest* test,
                    std::vector<int>* out_of_balance) {
  Eigen::VectorXd reduced;
  if (!lu.try_solve(reduce(b, r), reduced)) return Solve::singular;
  // Sized by kept, not k: a K whose storage solve_kept handed to lu is empty when all are kept.
  x = expand(reduced, r, static_cast<int>(kept.size()));
  if (!test || r.keeps_all()) return Solve::solved;
  // R(x) ~ b - K x: the dropped rows keep -misfit, of which the start's residual is not the step's.
  Eigen::VectorXd misfit = k * x - b;
  if (test->start_residual) misfit += *test->start_residual;
  const Eigen::VectorXd size = k.cwiseAbs() * x.cwiseAbs() + b.cwiseAbs();
  const double limit = test->tolerance * std::max(size.maxCoeff(), 1e-300);
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

// solve_kept with the factorisation given (of K reduced by r): the timings and counts around it,
// then the solve.
template <class Factorise>
Solve timed_solve(const Network& net, const SparseMatrix& k, const std::vector<char>& kept,
                  const Reduction& r, Factorise&& factorise, const Eigen::VectorXd& b, LuFactor& lu,
                  Eigen::VectorXd& x, Timings* timings, const PinnedRowTest* test,
                  std::vector<int>* out_of_balance) {
  const auto t0 = Clock::now();
  const Solve outcome = factorise() ? solve_reduced(net, k, kept, r, lu, b, x, test, out_of_balance)
                                    : Solve::singular;
  count_factorisation(timings, t0, lu);
  return outcome;
}

}  // namespace

Solve solve_factored(const Network& net, const SparseMatrix& k, const std::vector<char>& kept,
                     const LuFactor& lu, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                     const PinnedRowTest* test, std::vector<int>* out_of_balance) {
  return solve_reduced(net, k, kept, make_reduction(kept), lu, b, x, test, out_of_balance);
}

Solve solve_kept(const Network& net, SparseMatrix&& k, const std::vector<char>& kept,
                 const Eigen::VectorXd& b, LuFactor& lu, Eigen::VectorXd& x, Timings* timings,
                 const PinnedRowTest* test, std::vector<int>* out_of_balance) {
  // k, if taken, is read again only when some dof is dropped, and then it was not taken.
  const Reduction r = make_reduction(kept);
  const auto factorise = [&] { return lu.factorize(reduce(std::move(k), r)); };
  return timed_solve(net, k, kept, r, factorise, b, lu, x, timings, test, out_of_balance);
}

Solve solve_kept(const Network& net, const std::shared_ptr<const SparseMatrix>& k,
                 const std::vector<char>& kept, const Eigen::VectorXd& b, LuFactor& lu,
                 Eigen::VectorXd& x, Timings* timings, const PinnedRowTest* test,
                 std::vector<int>* out_of_balance) {
  const Reduction r = make_reduction(kept);
  const auto factorise = [&] {
    return r.keeps_all() ? lu.factorize(k) : lu.factorize(reduce(*k, r));
  };
  return timed_solve(net, *k, kept, r, factorise, b, lu, x, timings, test, out_of_balance);
}

LuReuse lu_reuse(const SolverOptions& options) {
  LuReuse reuse = default_lu_reuse();
  reuse.krylov = reuse.krylov || options.krylov_solves;
  reuse.refine = reuse.refine && options.refine_solves;
  return reuse;
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
  // A contact sliding at the end of the step stays on the cone at the moved geometry: its overlap,
  // recomputed from the rounded new positions, differs by ~1e-15 of the cell's length, i.e. by
  // 1e-9 to 1e-8 of a weakly loaded contact's, which put such contacts just inside the cone
  // (outside is_sliding's 1e-9) and cost the next check a status iteration to slide them again
  // (at N = 5600, 1116 iterations after the check's first in 409 checks). F_T = s mu F_N anew.
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(m.size);
  for (std::size_t c = 0; c < net.contacts.size(); ++c) {
    const ContactStatus status = net.contacts.status[c];
    if (!slides(status)) continue;
    const ContactState s = evaluate_contact(net, c, zero);
    if (!s.frictional || !(s.f_n > 0.0)) continue;
    const double sign = status == ContactStatus::slide_positive ? 1.0 : -1.0;
    net.contacts.delta_t[c] = -sign * s.mu * s.f_n / net.material.k_t;
  }
}

StepResult load_step(Network& net, const SolverOptions& options, Timings* timings,
                     const PredictorResult* warm, std::vector<ContactState>* start_states) {
  StepResult step;
  step.predictor = predict(net, options, timings, nullptr, warm, false, start_states);
  if (!step.predictor.ok) {
    step.failure = "predictor: " + step.predictor.failure;
    return step;
  }
  const auto t0 = Clock::now();
  Network trial = net;
  const ResidualScale scale = residual_scale(trial, step.predictor.start_states);
  const SolvePhase phase_before = lu_statistics().phase;
  lu_statistics().phase = SolvePhase::chord;
  Eigen::VectorXd dq = chord_iterations(trial, step.predictor, step.predictor.dq, scale, options);
  lu_statistics().phase = SolvePhase::corrector;
  std::vector<int> made_rattlers;
  for (int round = 0;; ++round) {
    step.corrector = newton_equilibrium(trial, dq, nullptr, scale, options, timings);
    if (!step.corrector.converged) {
      // A disk left with one closed contact (the others opened in the step) carries no force in
      // any equilibrium, and its dofs make the tangent singular (a translation or rotation that
      // the lone contact does not hold): it steps off that contact and becomes a rattler, as the
      // preparation's rule makes disks with fewer than two force-carrying contacts (SPEC §2), and
      // the corrector reruns.
      std::vector<char> closed(step.corrector.states.size());
      for (std::size_t c = 0; c < closed.size(); ++c)
        closed[c] = step.corrector.states[c].f_n > 0.0;
      const std::vector<int> lone = lone_contacts(trial, closed);
      dq = step.corrector.dq;
      const std::vector<int> loose = step_off_lone_contacts(trial, lone, step.corrector.states, dq);
      if (!loose.empty() && round < options.max_closing_rounds && make_rattlers(trial, loose, dq)) {
        made_rattlers.insert(made_rattlers.end(), loose.begin(), loose.end());
        continue;
      }
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
      // A disk made a rattler in this step stepped off its last contact, but the disks around it
      // moved on in the rounds after. Overlapped twice or more it would be a disk with contacts
      // out of balance at the next preparation, and every later step failed (series A,
      // N = 3025). So it moves clear of them, or, caught by its cage, gets its dofs back and the
      // corrector reruns. The same for an older rattler whose listed contacts the cage closed
      // in the step (caught_rattlers): once it rejoins, the state accepted would otherwise be no
      // equilibrium, by K_N times those overlaps (the same sample, seed 1: relative residuals of
      // 1e-2 to 3e-2 after three steps; its fixed steps stopped at q = 0.7215 after one).
      std::vector<int> to_clear = made_rattlers;
      const std::vector<int> caught = caught_rattlers(trial, step.corrector.states);
      to_clear.insert(to_clear.end(), caught.begin(), caught.end());
      std::vector<int> jammed;
      const bool moved =
          !clear_rattler_overlaps(trial, to_clear, step.corrector.dq, step.corrector.states, jammed)
               .empty();
      if (!jammed.empty() && round < options.max_closing_rounds) {
        dq = step.corrector.dq;
        activate_disks(trial, jammed, dq);
        continue;
      }
      if (moved) step.corrector.states = evaluate_contacts(trial, step.corrector.dq);
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
  // Series A, N = 3025, seed 1, K_T/K_N = 1: three disks against a frictionless wall, each left
  // with one contact in a failed Newton iterate that had moved them 4.3e6 along the wall (their
  // block singular there), became rattlers at that place, outside the cell, and the run went on.
  // No disk may move by more than its radius in one step, rattlers made in it included.
  if (const int i = escaped_disk(net, trial); i >= 0) {
    step.ok = false;
    step.failure = "corrector: disk " + std::to_string(i) +
                   " moves by more than its radius in one step (a floppy mode)";
    return step;
  }
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
