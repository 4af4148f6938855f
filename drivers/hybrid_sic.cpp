#include "hybrid_sic.hpp"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "common/io/csv_writer.hpp"
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

bool beyond_q_max(double q, const SicOptions& o) { return q > o.q_max * (1.0 + 1e-12); }

// After an MD wait, its state last on the curve: whether it ends the run (a failure, or the
// epsilon_2 target), with the reason.
bool ends_run(const protocols::EquilibrationResult& r, const SicOptions& o, SicResult& result) {
  if (!r.reached) {
    result.stop_reason = r.aborted ? "epsilon_2_max" : "no equilibrium";
    return true;
  }
  if (result.curve.back().eps2 >= o.epsilon_2_end) {
    result.stop_reason = "epsilon_2_end";
    return true;
  }
  return false;
}

SicResult pure_dynamic(const Configuration& start, const SicOptions& o, const SicObserver& observer,
                       const RestartObserver& on_restart_point, const SicRestart* resume) {
  SicResult result = resume ? resume->so_far : SicResult{};
  const double seconds_before = result.dynamic_seconds;
  const auto t0 = Clock::now();
  const double pressure = start.stage.sigma_ext[0];
  // An exported equilibrium continues to the bit (docs/dynamic.md, "Determinism"): its stage is
  // the biaxial one already.
  Engine engine(resume ? resume->current : start, o.engine);
  if (!resume) protocols::begin_biaxial_stage(engine, start.material, pressure);
  Configuration state = resume ? resume->current : start;  // the final state if no wait follows
  for (int k = resume ? resume->next : 0;; ++k) {
    const double q = k * o.dq;  // from k, not accumulated: no drift of the targets
    if (beyond_q_max(q, o)) {
      result.stop_reason = "q_max";
      break;
    }
    const auto r = md_increment(engine, q, pressure, o, state, observer);
    result.md_steps += r.steps;
    result.curve.push_back(dynamic_point(state, q, k, r.steps, r.reached, o.dq));
    if (ends_run(r, o, result)) break;
    if (on_restart_point) {
      result.dynamic_seconds = seconds_before + seconds_since(t0);
      on_restart_point({state, q, k + 1, result});
    }
  }
  result.final_state = state;
  result.dynamic_seconds = seconds_before + seconds_since(t0);
  return result;
}

SicResult hybrid(const Configuration& start, const SicOptions& o, const SicObserver& observer,
                 const RestartObserver& on_restart_point, const SicRestart* resume) {
  SicResult result = resume ? resume->so_far : SicResult{};
  const double pressure = start.stage.sigma_ext[0];
  Configuration current = resume ? resume->current : start;
  statics::Q1Options so = o.statics;
  so.dq = o.dq;
  so.control = statics::Control::stress;
  so.load_stop = o.q_max;
  so.stop_when = [&](const statics::CurvePoint& p) {
    if (observer) observer(p.load, p.eps2, Method::static_stepping);
    return p.eps2 >= o.epsilon_2_end;
  };
  double q = resume ? resume->q : start.stage.sigma_ext[1] / pressure - 1.0;
  for (int interval = resume ? resume->next : 0;; ++interval) {
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
    if (ends_run(r, o, result)) break;
    if (on_restart_point) on_restart_point({current, q, interval + 1, result});
  }
  result.final_state = std::move(current);
  return result;
}

}  // namespace

const char* method_name(Method m) { return m == Method::static_stepping ? "static" : "dynamic"; }

double next_increment(double q, double dq) { return (std::floor(q / dq + 1e-9) + 1.0) * dq; }

SicResult run_sic(const Configuration& start, const SicOptions& options,
                  const SicObserver& observer, const RestartObserver& on_restart_point,
                  const SicRestart* resume) {
  if (!(options.dq > 0.0)) throw std::invalid_argument("sic: dq must be > 0");
  if (!(options.epsilon_2_end > 0.0) && !std::isfinite(options.q_max))
    throw std::invalid_argument("sic: give a finite q_max or epsilon_2_end > 0");
  if (!(start.stage.sigma_ext[0] > 0.0))
    throw std::invalid_argument("sic: the start's sigma_ext[0] must be > 0");
  return options.hybrid ? hybrid(start, options, observer, on_restart_point, resume)
                        : pure_dynamic(start, options, observer, on_restart_point, resume);
}

namespace {

// One line of numbers per record, shortest round-trip decimals.
template <typename... T>
std::string record_line(T... values) {
  std::string line;
  ((line += csv_number(static_cast<double>(values)) + ' '), ...);
  line.back() = '\n';
  return line;
}

std::vector<std::vector<double>> parse_records(const protocols::Checkpoint& c,
                                               std::string_view name, std::size_t fields) {
  std::vector<std::vector<double>> out;
  std::istringstream in(c.text(name));
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::vector<double> v;
    for (std::string w; words >> w;) {
      double x = 0.0;
      const auto r = std::from_chars(w.data(), w.data() + w.size(), x);
      if (r.ec != std::errc() || r.ptr != w.data() + w.size())
        throw std::runtime_error(c.source_name() + ": entry " + std::string(name) +
                                 ": not a number: " + w);
      v.push_back(x);
    }
    if (v.size() != fields)
      throw std::runtime_error(c.source_name() + ": entry " + std::string(name) + ": expected " +
                               std::to_string(fields) + " numbers a line");
    out.push_back(std::move(v));
  }
  return out;
}

}  // namespace

void put_restart(protocols::Checkpoint& c, const SicRestart& r, std::size_t keep) {
  const SicResult& s = r.so_far;
  c.set_configuration("sic.current", r.current);
  c.set_number("sic.q", r.q);
  c.set_count("sic.next", static_cast<std::uint64_t>(r.next));
  c.set_count("sic.md_steps", s.md_steps);
  c.set_count("sic.static_states", static_cast<std::uint64_t>(s.static_states));
  c.set_number("sic.static_seconds", s.static_seconds);
  c.set_number("sic.dynamic_seconds", s.dynamic_seconds);
  std::string curve, intervals, ends, jumps;
  for (const SicPoint& p : s.curve)
    curve += record_line(p.method == Method::static_stepping ? 1 : 0, p.q_target, p.q, p.eps1,
                         p.eps2, p.epsv, p.n_sliding, p.interval, p.md_steps, p.on_grid, p.reached,
                         p.interpolated);
  for (const StabilityInterval& v : s.intervals) {
    intervals += record_line(v.q_start, v.q_end, v.eps2_start, v.eps2_end, v.states,
                             v.polish_strain, v.polish_displacement);
    std::string end = v.end;
    std::replace(end.begin(), end.end(), '\n', ' ');
    ends += end + '\n';
  }
  // The states of the `keep` largest jumps so far: no other can be among the largest at the end.
  std::vector<std::size_t> order(s.rearrangements.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  const auto jump = [&](std::size_t k) {
    return std::abs(s.rearrangements[k].eps2_after - s.rearrangements[k].eps2_before);
  };
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return jump(a) > jump(b); });
  std::vector<char> kept(order.size(), 0);
  for (std::size_t n = 0; n < order.size() && n < keep; ++n) kept[order[n]] = 1;
  for (std::size_t k = 0; k < s.rearrangements.size(); ++k) {
    const Rearrangement& j = s.rearrangements[k];
    const bool states = kept[k] && !j.before.disks.empty();
    jumps += record_line(j.q_from, j.q_to, j.eps2_before, j.eps2_after, j.md_steps,
                         j.rattlers_freed, j.reached, states);
    if (states) {
      c.set_configuration("sic.jump." + std::to_string(k) + ".before", j.before);
      c.set_configuration("sic.jump." + std::to_string(k) + ".after", j.after);
    }
  }
  c.set("sic.curve", curve);
  c.set("sic.intervals", intervals);
  c.set("sic.interval_ends", ends);
  c.set("sic.rearrangements", jumps);
}

SicRestart get_restart(const protocols::Checkpoint& c) {
  SicRestart r;
  SicResult& s = r.so_far;
  r.current = c.configuration("sic.current");
  r.q = c.number("sic.q");
  r.next = static_cast<int>(c.count("sic.next"));
  s.md_steps = c.count("sic.md_steps");
  s.static_states = static_cast<int>(c.count("sic.static_states"));
  s.static_seconds = c.number("sic.static_seconds");
  s.dynamic_seconds = c.number("sic.dynamic_seconds");
  for (const auto& v : parse_records(c, "sic.curve", 12)) {
    SicPoint p;
    p.method = v[0] != 0.0 ? Method::static_stepping : Method::dynamics;
    p.q_target = v[1];
    p.q = v[2];
    p.eps1 = v[3];
    p.eps2 = v[4];
    p.epsv = v[5];
    p.n_sliding = static_cast<int>(v[6]);
    p.interval = static_cast<int>(v[7]);
    p.md_steps = static_cast<std::uint64_t>(v[8]);
    p.on_grid = v[9] != 0.0;
    p.reached = v[10] != 0.0;
    p.interpolated = v[11] != 0.0;
    s.curve.push_back(p);
  }
  std::istringstream ends(c.text("sic.interval_ends"));
  for (const auto& v : parse_records(c, "sic.intervals", 7)) {
    StabilityInterval iv;
    iv.q_start = v[0];
    iv.q_end = v[1];
    iv.eps2_start = v[2];
    iv.eps2_end = v[3];
    iv.states = static_cast<int>(v[4]);
    iv.polish_strain = v[5];
    iv.polish_displacement = v[6];
    if (!std::getline(ends, iv.end))
      throw std::runtime_error(c.source_name() + ": entry sic.interval_ends: too few lines");
    s.intervals.push_back(iv);
  }
  const auto records = parse_records(c, "sic.rearrangements", 8);
  for (std::size_t k = 0; k < records.size(); ++k) {
    const auto& v = records[k];
    Rearrangement j;
    j.q_from = v[0];
    j.q_to = v[1];
    j.eps2_before = v[2];
    j.eps2_after = v[3];
    j.md_steps = static_cast<std::uint64_t>(v[4]);
    j.rattlers_freed = static_cast<int>(v[5]);
    j.reached = v[6] != 0.0;
    if (v[7] != 0.0) {
      j.before = c.configuration("sic.jump." + std::to_string(k) + ".before");
      j.after = c.configuration("sic.jump." + std::to_string(k) + ".after");
    }
    s.rearrangements.push_back(std::move(j));
  }
  return r;
}

}  // namespace granstab::hybrid
