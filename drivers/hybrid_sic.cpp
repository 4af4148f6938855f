#include "hybrid_sic.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <utility>

#include "common/measurements.hpp"
#include "common/start_state.hpp"
#include "dynamic/protocols/biaxial.hpp"
#include "stability_probe.hpp"

namespace granstab::hybrid {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

bool on_grid(double q, double dq) { return std::abs(q / dq - std::round(q / dq)) < 1e-6; }

SicPoint dynamic_point(const Configuration& state, double q_target, int interval,
                       std::uint64_t steps, bool reached, double dq) {
  const Measurements m = measure(state);
  SicPoint p;
  p.method = Method::dynamics;
  p.q_target = q_target;
  p.q = m.q;
  p.eps1 = m.epsilon_1;
  p.eps2 = m.epsilon_2;
  p.epsv = m.epsilon_v;
  p.n_sliding = static_cast<int>(m.n_sliding);
  p.interval = interval;
  p.md_steps = steps;
  p.on_grid = on_grid(q_target, dq);
  p.reached = reached;
  return p;
}

SicPoint static_point(const statics::CurvePoint& c, int interval, double dq) {
  SicPoint p;
  p.method = Method::static_stepping;
  p.q_target = c.load;
  p.q = c.q;
  p.eps1 = c.eps1;
  p.eps2 = c.eps2;
  p.epsv = c.epsv;
  p.n_sliding = c.n_sliding;
  p.interval = interval;
  p.on_grid = on_grid(c.load, dq);
  p.interpolated = c.interpolated;
  return p;
}

// One SIC increment by MD (SPEC §3.3): sigma_2 = P (1 + q_target) with sigma_1 = P held, then
// the wait for the §3.1 equilibrium; aborted when epsilon_2 passes epsilon_2_max (the sample
// flows). `state` receives the engine's last exported state. Both routes use it, so that the
// hybrid's MD and the pure dynamic reference are the same computation.
protocols::EquilibrationResult md_increment(Engine& engine, double q_target, double pressure,
                                            const SicOptions& o, Configuration& state,
                                            const SicObserver& observer) {
  engine.set_stress_control(0, pressure);
  engine.set_stress_control(1, pressure * (1.0 + q_target));
  const auto check = [&](const Engine& e, const Configuration&, const EquilibriumReport&) {
    const double eps2 = protocols::axial_strain(e);
    if (observer) observer(q_target, eps2, Method::dynamics);
    return eps2 <= o.epsilon_2_max;
  };
  return protocols::run_to_equilibrium(engine, o.equilibration, state, check);
}

std::string failure_reason(const protocols::EquilibrationResult& r) {
  return r.aborted ? "epsilon_2_max" : "no equilibrium";
}

bool beyond_q_max(double q, const SicOptions& o) { return q > o.q_max * (1.0 + 1e-12); }

SicResult pure_dynamic(const Configuration& start, const SicOptions& o,
                       const SicObserver& observer) {
  SicResult result;
  const auto t0 = Clock::now();
  const double pressure = start.stage.sigma_ext[0];
  Engine engine(start, o.engine);
  protocols::begin_biaxial_stage(engine, start.material, pressure);
  Configuration state;
  for (int k = 0;; ++k) {
    const double q = k * o.dq;  // from k, not accumulated: no drift of the targets
    if (beyond_q_max(q, o)) {
      result.stop_reason = "q_max";
      break;
    }
    const auto r = md_increment(engine, q, pressure, o, state, observer);
    result.md_steps += r.steps;
    result.curve.push_back(dynamic_point(state, q, k, r.steps, r.reached, o.dq));
    if (!r.reached) {
      result.stop_reason = failure_reason(r);
      break;
    }
    if (result.curve.back().eps2 >= o.epsilon_2_end) {
      result.stop_reason = "epsilon_2_end";
      break;
    }
  }
  result.final_state = state;
  result.dynamic_seconds = seconds_since(t0);
  return result;
}

SicResult hybrid(const Configuration& start, const SicOptions& o, const SicObserver& observer) {
  SicResult result;
  const double pressure = start.stage.sigma_ext[0];
  Configuration current = start;
  statics::Q1Options so = o.statics;
  so.dq = o.dq;
  so.control = statics::Control::stress;
  so.load_stop = o.q_max;
  so.stop_when = [&](const statics::CurvePoint& p) {
    if (observer) observer(p.load, p.eps2, Method::static_stepping);
    return p.eps2 >= o.epsilon_2_end;
  };
  double q = start.stage.sigma_ext[1] / pressure - 1.0;
  for (int interval = 0;; ++interval) {
    // The static interval from `current` (the sample, or the last MD equilibrium) to its loss of
    // stability. A start the static solver refuses (broken geometry, out of equilibrium beyond
    // the §3.1 tolerances, a polish that does not converge) hands the next increment to the
    // engine, like an unstable one.
    const auto t_static = Clock::now();
    StabilityInterval iv;
    iv.q_start = q;
    iv.eps2_start = interval == 0 ? 0.0 : result.curve.back().eps2;
    Configuration from;
    double q_last = q, eps2_last = iv.eps2_start;
    bool ended_stable = false;
    int freed = 0;
    try {
      if (interval > 0) {
        char source[96];
        std::snprintf(source, sizeof source, "MD equilibrium at q = %.6g", q);
        validate_start_state(current, source, false);
      }
      const statics::StabilityResult s = statics::find_q1(current, so);
      // The start of a later interval is the MD state just recorded (polished within the §3.1
      // tolerances, iv.polish_*): only the first interval records its start.
      for (std::size_t k = interval == 0 ? 0 : 1; k < s.curve.size(); ++k)
        result.curve.push_back(static_point(s.curve[k], interval, o.dq));
      iv.states = static_cast<int>(std::count_if(s.curve.begin(), s.curve.end(),
                                                 [](const auto& c) { return !c.interpolated; }));
      result.static_states += iv.states;
      iv.q_end = s.q1;
      iv.eps2_end = s.curve.back().eps2;
      iv.end =
          s.criterion == statics::Criterion::none ? "target" : statics::criterion_name(s.criterion);
      iv.polish_strain = s.polish.max_strain;
      iv.polish_displacement = s.polish.max_displacement;
      q_last = s.q1;
      eps2_last = iv.eps2_end;
      ended_stable = s.criterion == statics::Criterion::none;
      from = crosscheck::configuration_of_static_state(s.network_at_q1, current);
      // Rattlers stay where the interval began while their cages strain: free those that now
      // overlap a neighbour, so that the engine starts from the static state's forces.
      const std::vector<char> trapped = crosscheck::overlapping_rattlers(s.network_at_q1, from);
      freed = static_cast<int>(std::count(trapped.begin(), trapped.end(), 1));
      if (freed > 0) crosscheck::push_out_rattlers(from, trapped);
    } catch (const std::exception& e) {
      // The user's sample was validated by the caller: its errors are the caller's to report.
      // An MD equilibrium the static solver cannot take (validation, or a polish that does not
      // converge near a rearrangement) is the engine's to continue.
      if (interval == 0) throw;
      iv.q_end = q;
      iv.eps2_end = iv.eps2_start;
      iv.end = std::string("start refused: ") + e.what();
      from = current;
    }
    result.intervals.push_back(iv);
    result.static_seconds += seconds_since(t_static);
    if (ended_stable) {
      current = std::move(from);
      result.stop_reason = eps2_last >= o.epsilon_2_end ? "epsilon_2_end" : "q_max";
      break;
    }

    // The rearrangement: the last stable state with sigma_2 at the next increment, by MD.
    const double q_next = next_increment(q_last, o.dq);
    if (beyond_q_max(q_next, o)) {
      result.stop_reason = "q_max";
      current = std::move(from);
      break;
    }
    const auto t_dynamic = Clock::now();
    Engine engine(from, o.engine);
    Configuration state;
    const auto r = md_increment(engine, q_next, pressure, o, state, observer);
    result.md_steps += r.steps;
    result.dynamic_seconds += seconds_since(t_dynamic);
    result.curve.push_back(dynamic_point(state, q_next, interval, r.steps, r.reached, o.dq));
    Rearrangement jump;
    jump.q_from = q_last;
    jump.q_to = q_next;
    jump.eps2_before = eps2_last;
    jump.eps2_after = result.curve.back().eps2;
    jump.md_steps = r.steps;
    jump.rattlers_freed = freed;
    jump.reached = r.reached;
    jump.before = std::move(from);
    jump.after = state;
    result.rearrangements.push_back(std::move(jump));
    current = std::move(state);
    q = q_next;
    if (!r.reached) {
      result.stop_reason = failure_reason(r);
      break;
    }
    if (result.curve.back().eps2 >= o.epsilon_2_end) {
      result.stop_reason = "epsilon_2_end";
      break;
    }
  }
  result.final_state = std::move(current);
  return result;
}

}  // namespace

const char* method_name(Method m) { return m == Method::static_stepping ? "static" : "dynamic"; }

double next_increment(double q, double dq) { return (std::floor(q / dq + 1e-9) + 1.0) * dq; }

SicResult run_sic(const Configuration& start, const SicOptions& options,
                  const SicObserver& observer) {
  if (!(options.dq > 0.0)) throw std::invalid_argument("sic: dq must be > 0");
  if (!(options.epsilon_2_end > 0.0) && !std::isfinite(options.q_max))
    throw std::invalid_argument("sic: give a finite q_max or epsilon_2_end > 0");
  if (!(start.stage.sigma_ext[0] > 0.0))
    throw std::invalid_argument("sic: the start's sigma_ext[0] must be > 0");
  return options.hybrid ? hybrid(start, options, observer) : pure_dynamic(start, options, observer);
}

}  // namespace granstab::hybrid
