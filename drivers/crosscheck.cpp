#include "crosscheck.hpp"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "common/io/csv_writer.hpp"
#include "common/measurements.hpp"
#include "dynamic/protocols/biaxial.hpp"
#include "stability_probe.hpp"

namespace granstab::crosscheck {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Same prescribed q: the static loads and the dynamic targets are both k dq computed from k,
// except after step cuts; 1e-9 dq separates "the same state" from "a cut state in between".
bool same_load(double a, double b, double dq) { return std::abs(a - b) <= 1e-9 * dq; }

// Linear interpolation of a static quantity at load q between curve[k-1] and curve[k].
template <class Field>
double interpolate(const std::vector<statics::CurvePoint>& curve, std::size_t k, double q,
                   Field field) {
  const statics::CurvePoint& lo = curve[k - 1];
  const statics::CurvePoint& hi = curve[k];
  const double w = (q - lo.load) / (hi.load - lo.load);
  return (1.0 - w) * field(lo) + w * field(hi);
}

// Macroscopic compliance d eps_a / dq of the static curve around point k: the larger of the
// backward and forward slopes (the conservative choice where the curve bends towards q1).
std::array<double, 2> static_compliance(const std::vector<statics::CurvePoint>& curve,
                                        std::size_t k) {
  std::array<double, 2> s{0.0, 0.0};
  const auto slope = [&](std::size_t a, std::size_t b) {
    const double dl = curve[b].load - curve[a].load;
    s[0] = std::max(s[0], std::abs((curve[b].eps1 - curve[a].eps1) / dl));
    s[1] = std::max(s[1], std::abs((curve[b].eps2 - curve[a].eps2) / dl));
  };
  if (k > 0) slope(k - 1, k);
  if (k + 1 < curve.size()) slope(k, k + 1);
  return s;
}

}  // namespace

double eps2_uncertainty(double s21, double s22, double sigma1, double sigma2,
                        const EquilibriumTolerances& tolerances) {
  // a = 1 (largest diameter) in the units of SPEC §1.
  return (std::abs(s21) * sigma1 + std::abs(s22) * sigma2) * tolerances.stress +
         (std::abs(s21) + std::abs(s22)) * tolerances.force;
}

double static_bound_eps2(const std::vector<statics::CurvePoint>& curve, double q, double sigma1,
                         const EquilibriumTolerances& tolerances) {
  if (curve.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::size_t k = 0;
  for (std::size_t c = 1; c < curve.size(); ++c)
    if (std::abs(curve[c].load - q) < std::abs(curve[k].load - q)) k = c;
  const std::array<double, 2> s = static_compliance(curve, k);
  return eps2_uncertainty(s[0] / sigma1, s[1] / sigma1, sigma1, sigma1 * (1.0 + q), tolerances);
}

Comparison compare_curves(const std::vector<statics::CurvePoint>& static_curve, double q1,
                          const std::vector<DynamicPoint>& dynamic_curve, double sigma1,
                          const EquilibriumTolerances& tolerances) {
  Comparison out;
  if (static_curve.empty() || dynamic_curve.empty()) return out;
  const double dq =
      dynamic_curve.size() > 1 ? dynamic_curve[1].q_target - dynamic_curve[0].q_target : 1.0;
  double step_sum = 0.0;
  int step_count = 0;
  for (const statics::CurvePoint& p : static_curve)
    if (p.n_sliding > 0 && p.load <= q1) {
      out.q_first_static_sliding = p.load;
      break;
    }
  for (std::size_t d = 0; d < dynamic_curve.size(); ++d) {
    const DynamicPoint& p = dynamic_curve[d];
    const bool below = p.q_target <= q1 + 1e-9 * dq;
    if (!below) {
      if (d > 0 && dynamic_curve[d - 1].reached) {
        out.dynamic_jump_after_q1 = p.eps2 - dynamic_curve[d - 1].eps2;
        out.q_of_jump = p.q_target;
        out.jump_reached_equilibrium = p.reached;
      }
      break;
    }
    if (!p.reached) break;
    if (d > 0) {
      const double step = p.eps2 - dynamic_curve[d - 1].eps2;
      step_sum += step;
      ++step_count;
      if (!(step <= out.max_dynamic_step_below_q1)) {  // also replaces the initial NaN
        out.max_dynamic_step_below_q1 = step;
        out.q_of_max_dynamic_step = p.q_target;
      }
    }
    if (p.q_target <= 0.5 * dq) continue;  // the common start: both strains are 0 by definition
    // Static state at the same load, or the pair of states around it.
    std::size_t k = 0;
    while (k < static_curve.size() && static_curve[k].load < p.q_target - 1e-9 * dq) ++k;
    if (k == static_curve.size()) break;  // beyond the static curve (stopped before q1)
    MatchedPoint m;
    m.q = p.q_target;
    m.eps2_dynamic = p.eps2;
    m.epsv_dynamic = p.epsv;
    m.eps1_dynamic = p.eps1;
    if (same_load(static_curve[k].load, p.q_target, dq)) {
      m.eps2_static = static_curve[k].eps2;
      m.epsv_static = static_curve[k].epsv;
      m.eps1_static = static_curve[k].eps1;
      // A row the adaptive step control interpolated inside a step without status change.
      m.interpolated = static_curve[k].interpolated;
      out.n_interpolated += m.interpolated;
    } else {
      if (k == 0) continue;
      m.interpolated = true;
      m.eps2_static = interpolate(static_curve, k, m.q, [](const auto& c) { return c.eps2; });
      m.epsv_static = interpolate(static_curve, k, m.q, [](const auto& c) { return c.epsv; });
      m.eps1_static = interpolate(static_curve, k, m.q, [](const auto& c) { return c.eps1; });
      ++out.n_interpolated;
    }
    const std::array<double, 2> s = static_compliance(static_curve, k);
    // d eps / d sigma_2 = (d eps / dq) / sigma_1 at fixed sigma_1.
    m.bound_eps2 =
        eps2_uncertainty(s[0] / sigma1, s[1] / sigma1, sigma1, sigma1 * (1.0 + m.q), tolerances);
    const double d2 = std::abs(m.eps2_dynamic - m.eps2_static);
    out.max_abs_diff_eps2 = std::max(out.max_abs_diff_eps2, d2);
    if (m.eps2_static != 0.0)
      out.max_rel_diff_eps2 = std::max(out.max_rel_diff_eps2, d2 / std::abs(m.eps2_static));
    out.max_abs_diff_epsv =
        std::max(out.max_abs_diff_epsv, std::abs(m.epsv_dynamic - m.epsv_static));
    out.max_abs_diff_eps1 =
        std::max(out.max_abs_diff_eps1, std::abs(m.eps1_dynamic - m.eps1_static));
    if (m.bound_eps2 > 0.0) {
      if (d2 / m.bound_eps2 > out.max_diff_over_bound_eps2) {
        out.max_diff_over_bound_eps2 = d2 / m.bound_eps2;
        out.diff_eps2_at_max = m.eps2_dynamic - m.eps2_static;
      }
      if (!(m.q >= out.q_first_static_sliding - 1e-9 * dq)) {
        out.max_diff_over_bound_eps2_before_sliding =
            std::max(out.max_diff_over_bound_eps2_before_sliding, d2 / m.bound_eps2);
        ++out.n_compared_before_sliding;
      }
    }
    out.points.push_back(m);
  }
  out.n_steps_compared = static_cast<int>(out.points.size());
  if (step_count > 0) out.mean_dynamic_step_below_q1 = step_sum / step_count;
  return out;
}

Configuration biaxial_start(const Configuration& sample, double mu) {
  if (!std::isfinite(mu) || mu < 0.0)
    throw std::invalid_argument("compare: mu must be a finite number >= 0");
  const Stage& st = sample.stage;
  if (st.control[0] != LengthControl::stress || st.control[1] != LengthControl::stress)
    throw std::invalid_argument("compare: the sample's stage.control must be 'stress stress'");
  if (!(st.sigma_ext[0] > 0.0) || std::abs(st.sigma_ext[1] / st.sigma_ext[0] - 1.0) > 1e-12)
    throw std::invalid_argument(
        "compare: the sample's stage.sigma_ext must be isotropic and > 0 (an isotropic "
        "equilibrium state is the start of a biaxial test)");
  Configuration start = sample;
  start.material.mu = mu;
  start.stage.reference_length = start.cell.length;
  return start;
}

void require_biaxial_start(const Configuration& sample) {
  biaxial_start(sample, sample.material.mu);
}

void run_dynamic(const Configuration& from, const CrosscheckOptions& options, double q_end,
                 DynamicRun& run, const protocols::LoopControl& control) {
  Engine engine(from, options.engine);
  const double pressure = from.stage.sigma_ext[0];
  // A resumed engine is in the biaxial stage already, with sigma_2 of its increment.
  if (!control.resume) protocols::begin_biaxial_stage(engine, from.material, pressure);
  protocols::StressStepOptions sic;
  const int substeps = std::max(1, options.dynamic_substeps);
  sic.delta_q = options.dq / substeps;
  sic.q_max = q_end;
  sic.epsilon_2_max = options.epsilon_2_max;
  sic.equilibration = options.equilibration;
  Configuration state;
  const auto record = [&run, substeps, sic](const Engine&, const Configuration& s,
                                            const protocols::StressStepRecord& r) {
    run.steps_since_record += r.steps;
    const long k = std::lround(r.q_target / sic.delta_q);
    if (r.equilibrium.reached && k % substeps != 0) return;  // between two recorded states
    const Measurements m = measure(s);
    DynamicPoint p;
    p.q_target = r.q_target;
    p.q = m.q;
    p.eps1 = m.epsilon_1;
    p.eps2 = m.epsilon_2;
    p.epsv = m.epsilon_v;
    p.n_sliding = m.n_sliding;
    p.steps = run.steps_since_record;
    run.steps_since_record = 0;
    p.reached = r.equilibrium.reached;
    p.max_net_force = r.equilibrium.report.max_net_force;
    p.max_net_torque = r.equilibrium.report.max_net_torque;
    p.stress_error_1 = r.equilibrium.report.stress_error[0];
    p.stress_error_2 = r.equilibrium.report.stress_error[1];
    run.curve.push_back(p);
  };
  const protocols::StressStepResult r =
      protocols::run_stress_steps(engine, sic, pressure, state, record, {}, control);
  run.stop_reason = r.stop_reason;
  run.steps = r.steps;
}

std::string dynamic_run_state(const DynamicRun& run) {
  std::string s = std::to_string(run.steps_since_record) + "\n";
  for (const DynamicPoint& p : run.curve) {
    for (const double v : {p.q_target, p.q, p.eps1, p.eps2, p.epsv, p.max_net_force,
                           p.max_net_torque, p.stress_error_1, p.stress_error_2}) {
      s += csv_number(v) + ' ';
    }
    s += std::to_string(p.n_sliding) + ' ' + std::to_string(p.steps) + ' ' +
         (p.reached ? "1" : "0") + '\n';
  }
  return s;
}

DynamicRun parse_dynamic_run_state(const std::string& text) {
  DynamicRun run;
  const char* at = text.data();
  const char* const end = text.data() + text.size();
  const auto fail = [] { throw std::runtime_error("compare: damaged dynamic curve state"); };
  const auto field = [&](auto& value, char separator) {
    const auto r = std::from_chars(at, end, value);
    if (r.ec != std::errc() || r.ptr == end || *r.ptr != separator) fail();
    at = r.ptr + 1;
  };
  field(run.steps_since_record, '\n');
  while (at != end) {
    DynamicPoint p;
    for (double* v : {&p.q_target, &p.q, &p.eps1, &p.eps2, &p.epsv, &p.max_net_force,
                      &p.max_net_torque, &p.stress_error_1, &p.stress_error_2}) {
      field(*v, ' ');
    }
    int reached = 0;
    field(p.n_sliding, ' ');
    field(p.steps, ' ');
    field(reached, '\n');
    if (reached != 0 && reached != 1) fail();
    p.reached = reached == 1;
    run.curve.push_back(p);
  }
  return run;
}

CrosscheckResult run_static_half(const Configuration& sample, const CrosscheckOptions& options) {
  if (!(options.dq > 0.0) || !std::isfinite(options.dq))
    throw std::invalid_argument("compare: --dq must be a finite number > 0");
  if (!(options.q_max > 0.0)) throw std::invalid_argument("compare: --q-max must be > 0");
  if (options.steps_after_q1 < 0)
    throw std::invalid_argument("compare: steps after q1 must be >= 0");
  if (options.dynamic_substeps < 1 || options.static_substeps < 1)
    throw std::invalid_argument("compare: --dynamic-substeps and --static-substeps must be >= 1");
  CrosscheckResult out;
  out.mu = std::isnan(options.mu) ? sample.material.mu : options.mu;
  out.start = biaxial_start(sample, out.mu);
  out.pressure = out.start.stage.sigma_ext[0];

  statics::Q1Options so = options.statics;
  so.dq = options.dq / options.static_substeps;
  so.dq_min = std::min(so.dq_min, so.dq);
  so.control = statics::Control::stress;
  so.load_stop = options.q_max;
  // A caller that keeps states at given loads (granstab probe --at) needs one at every multiple
  // of dq: fixed steps. compare --probe-states takes the first accepted state at or above each
  // fraction of q1, which the adaptive control provides as well.
  if (so.on_accepted) so.steps = statics::StepControl::fixed;
  if (options.probe.states > 0) {
    // compare --probe-states: the probed loads are fractions of q1, known only at the end.
    so.on_accepted = [&states = out.static_states, then = options.statics.on_accepted](
                         double load, const statics::Network& net) {
      states.push_back({load, net});
      if (then) then(load, net);
    };
  }
  auto t0 = std::chrono::steady_clock::now();
  out.statics = statics::find_q1(out.start, so);
  out.static_seconds = seconds_since(t0);

  if (options.rigid_limit) {
    t0 = std::chrono::steady_clock::now();
    out.rigid = statics::rigid_limit(out.start);
    out.rigid_seconds = seconds_since(t0);
  }
  return out;
}

double dynamic_q_end(const CrosscheckResult& static_half, const CrosscheckOptions& options) {
  // The dynamic run covers the static range, and a few increments beyond q1 when it was found.
  if (std::isfinite(options.q_max)) return options.q_max;
  const double k1 = std::floor(static_half.statics.q1 / options.dq + 1e-9);
  return (k1 + options.steps_after_q1) * options.dq;
}

void compare_halves(CrosscheckResult& r, const CrosscheckOptions& options) {
  r.comparison = compare_curves(r.statics.curve, r.statics.q1, r.dynamic.curve, r.pressure,
                                options.equilibration.tolerances);
}

CrosscheckResult run_crosscheck(const Configuration& sample, const CrosscheckOptions& options) {
  CrosscheckResult out = run_static_half(sample, options);
  const auto t0 = std::chrono::steady_clock::now();
  run_dynamic(out.start, options, dynamic_q_end(out, options), out.dynamic);
  out.dynamic_seconds = seconds_since(t0);
  compare_halves(out, options);
  return out;
}

// --- outputs --------------------------------------------------------------------------------

std::string static_curve_csv(const statics::StabilityResult& r) {
  std::ostringstream s;
  s << "step,load,q,epsilon_1,epsilon_2,epsilon_v,n_sliding,hill,det_sign,newton_iterations,"
       "new_contacts,interpolated\n";
  for (std::size_t k = 0; k < r.curve.size(); ++k) {
    const statics::CurvePoint& p = r.curve[k];
    s << k << ',' << json_number(p.load) << ',' << json_number(p.q) << ',' << json_number(p.eps1)
      << ',' << json_number(p.eps2) << ',' << json_number(p.epsv) << ',' << p.n_sliding << ','
      << json_number(p.hill) << ',' << p.determinant_sign << ',' << p.newton_iterations << ','
      << p.new_contacts << ',' << (p.interpolated ? 1 : 0) << '\n';
  }
  return s.str();
}

std::string dynamic_curve_csv(const DynamicRun& run) {
  std::ostringstream s;
  s << "step,q_target,q,epsilon_1,epsilon_2,epsilon_v,n_sliding,md_steps,reached,max_net_force,"
       "max_net_torque,stress_error_1,stress_error_2\n";
  for (std::size_t k = 0; k < run.curve.size(); ++k) {
    const DynamicPoint& p = run.curve[k];
    s << k << ',' << json_number(p.q_target) << ',' << json_number(p.q) << ','
      << json_number(p.eps1) << ',' << json_number(p.eps2) << ',' << json_number(p.epsv) << ','
      << p.n_sliding << ',' << p.steps << ',' << (p.reached ? 1 : 0) << ','
      << json_number(p.max_net_force) << ',' << json_number(p.max_net_torque) << ','
      << json_number(p.stress_error_1) << ',' << json_number(p.stress_error_2) << '\n';
  }
  return s.str();
}

std::string matched_csv(const Comparison& c) {
  std::ostringstream s;
  s << "q,epsilon_2_static,epsilon_2_dynamic,epsilon_v_static,epsilon_v_dynamic,epsilon_1_static,"
       "epsilon_1_dynamic,bound_epsilon_2,interpolated\n";
  for (const MatchedPoint& m : c.points)
    s << json_number(m.q) << ',' << json_number(m.eps2_static) << ',' << json_number(m.eps2_dynamic)
      << ',' << json_number(m.epsv_static) << ',' << json_number(m.epsv_dynamic) << ','
      << json_number(m.eps1_static) << ',' << json_number(m.eps1_dynamic) << ','
      << json_number(m.bound_eps2) << ',' << (m.interpolated ? 1 : 0) << '\n';
  return s.str();
}

namespace {

// The static network at q1 as a Configuration, so that common/measurements.hpp gives its forces.
Configuration configuration_of(const statics::Network& n) {
  Configuration c;
  c.cell.boundary = n.boundary;
  c.cell.length = n.length;
  c.material = n.material;
  c.contacts = n.contacts;
  for (std::size_t i = 0; i < n.n_disks(); ++i) c.disks.add(n.x[i], n.y[i], n.radius[i]);
  c.stage.reference_length = n.length;
  c.stage.sigma_ext = n.loading.sigma;
  return c;
}

}  // namespace

std::string disks_at_q1_csv(const statics::StabilityResult& r) {
  return disks_csv(configuration_of(r.network_at_q1));
}

std::string network_at_q1_csv(const statics::StabilityResult& r) {
  return network_csv(configuration_of(r.network_at_q1));
}

std::string disks_csv(const Configuration& c) {
  const auto loads = contact_loads(c);
  const auto rattler = find_rattlers(c, loads);
  std::ostringstream s;
  s << "# L1 " << json_number(c.cell.length[0]) << " L2 " << json_number(c.cell.length[1])
    << " boundary " << (c.cell.periodic() ? "periodic" : "walls") << '\n';
  s << "disk,x,y,radius,rattler\n";
  for (std::size_t i = 0; i < c.disks.size(); ++i)
    s << i << ',' << json_number(c.disks.x[i]) << ',' << json_number(c.disks.y[i]) << ','
      << json_number(c.disks.radius[i]) << ',' << int(rattler[i]) << '\n';
  return s.str();
}

std::string network_csv(const Configuration& c) {
  const auto loads = contact_loads(c);
  std::ostringstream s;
  // (x_i, y_i) and the branch vector (lx, ly) to the image of j (or to the wall foot).
  s << "contact,i,j,x_i,y_i,lx,ly,f_n,f_t,sliding\n";
  for (std::size_t k = 0; k < loads.size(); ++k) {
    if (!loads[k].carrying) continue;
    const int i = c.contacts.i[k];
    s << k << ',' << i << ',' << c.contacts.j[k] << ',' << json_number(c.disks.x[i]) << ','
      << json_number(c.disks.y[i]) << ',' << json_number(loads[k].frame.lx) << ','
      << json_number(loads[k].frame.ly) << ',' << json_number(loads[k].f_n) << ','
      << json_number(loads[k].f_t) << ',' << (loads[k].sliding ? 1 : 0) << '\n';
  }
  return s.str();
}

std::string mode_csv(const statics::StabilityResult& r) {
  std::ostringstream s;
  // active: the disk carries degrees of freedom of the mode (0 for rattlers, whose zero entries
  // are no displacement and must not be drawn relative to the mean translation).
  s << "disk,x,y,ux,uy,theta,active\n";
  const statics::Network& n = r.network_at_q1;
  for (std::size_t i = 0; 3 * i + 2 < r.mode.size() && i < n.n_disks(); ++i)
    s << i << ',' << json_number(n.x[i]) << ',' << json_number(n.y[i]) << ','
      << json_number(r.mode[3 * i]) << ',' << json_number(r.mode[3 * i + 1]) << ','
      << json_number(r.mode[3 * i + 2]) << ','
      << (i < r.mode_disk_active.size() && r.mode_disk_active[i] ? 1 : 0) << '\n';
  s << "e1," << json_number(r.mode_cell[0]) << ",,,,,\ne2," << json_number(r.mode_cell[1])
    << ",,,,,\n";
  return s.str();
}

std::string compare_json(const JsonContext& x, const CrosscheckOptions& o,
                         const CrosscheckResult& r) {
  const Comparison& c = r.comparison;
  const EquilibriumTolerances& tol = o.equilibration.tolerances;
  std::ostringstream s;
  s << "{\n"
    << "  \"sample\": " << json_string(x.sample) << ",\n"
    << "  \"n_disks\": " << r.start.disks.size() << ",\n"
    << "  \"kappa\": " << json_number(r.start.material.kappa(r.pressure)) << ",\n"
    << "  \"mu\": " << json_number(r.mu) << ",\n"
    << "  \"pressure\": " << json_number(r.pressure) << ",\n"
    << x.start_fields << "  \"dq\": " << json_number(x.dq) << ",\n"
    << "  \"dynamic_substeps\": " << o.dynamic_substeps << ",\n"
    << "  \"static_substeps\": " << o.static_substeps << ",\n"
    << "  \"q_max\": " << json_number(x.q_max) << ",\n"
    << "  \"q1\": " << json_number(r.statics.q1) << ",\n"
    << "  \"q1_bracket\": [" << json_number(r.statics.q1_bracket[0]) << ", "
    << json_number(r.statics.q1_bracket[1]) << "],\n"
    << "  \"criterion\": " << json_string(statics::criterion_name(r.statics.criterion)) << ",\n"
    << "  \"detail\": " << json_string(r.statics.detail) << ",\n"
    << "  \"n_sliding_at_q1\": " << r.statics.sliding_at_q1.size() << ",\n"
    << "  \"q_max_rigid\": " << json_number(r.rigid.q_max) << ",\n"
    << "  \"q_max_rigid_status\": " << json_string(o.rigid_limit ? r.rigid.status : "not run")
    << ",\n"
    << "  \"static_steps\": " << r.statics.steps << ",\n"
    << "  \"static_step_control\": "
    << json_string(statics::step_control_name(r.statics.step_control)) << ",\n"
    << "  \"static_attempts\": " << r.statics.attempts << ",\n"
    << "  \"static_interpolated_rows\": " << r.statics.interpolated_rows << ",\n"
    << "  \"dynamic_increments\": " << r.dynamic.curve.size() << ",\n"
    << "  \"dynamic_stop_reason\": " << json_string(r.dynamic.stop_reason) << ",\n"
    << "  \"dynamic_md_steps\": " << r.dynamic.steps << ",\n"
    << "  \"equilibrium_tolerances\": {\"force\": " << json_number(tol.force)
    << ", \"torque\": " << json_number(tol.torque) << ", \"stress\": " << json_number(tol.stress)
    << "},\n"
    << "  \"n_steps_compared\": " << c.n_steps_compared << ",\n"
    << "  \"n_interpolated\": " << c.n_interpolated << ",\n"
    << "  \"max_abs_diff_eps2_below_q1\": " << json_number(c.max_abs_diff_eps2) << ",\n"
    << "  \"max_rel_diff_eps2_below_q1\": " << json_number(c.max_rel_diff_eps2) << ",\n"
    << "  \"max_abs_diff_epsv_below_q1\": " << json_number(c.max_abs_diff_epsv) << ",\n"
    << "  \"max_abs_diff_eps1_below_q1\": " << json_number(c.max_abs_diff_eps1) << ",\n"
    << "  \"max_diff_over_bound_eps2\": " << json_number(c.max_diff_over_bound_eps2) << ",\n"
    << "  \"diff_eps2_at_max\": " << json_number(c.diff_eps2_at_max) << ",\n"
    << "  \"q_first_static_sliding\": " << json_number(c.q_first_static_sliding) << ",\n"
    << "  \"max_diff_over_bound_eps2_before_sliding\": "
    << json_number(c.max_diff_over_bound_eps2_before_sliding) << ",\n"
    << "  \"n_compared_before_sliding\": " << c.n_compared_before_sliding << ",\n"
    << "  \"dynamic_jump_after_q1\": " << json_number(c.dynamic_jump_after_q1) << ",\n"
    << "  \"q_of_jump\": " << json_number(c.q_of_jump) << ",\n"
    << "  \"jump_reached_equilibrium\": " << (c.jump_reached_equilibrium ? "true" : "false")
    << ",\n"
    << "  \"mean_dynamic_step_below_q1\": " << json_number(c.mean_dynamic_step_below_q1) << ",\n"
    << "  \"max_dynamic_step_below_q1\": " << json_number(c.max_dynamic_step_below_q1) << ",\n"
    << "  \"q_of_max_dynamic_step\": " << json_number(c.q_of_max_dynamic_step) << ",\n"
    << "  \"probe_f0\": " << json_number(o.probe.f0) << ",\n"
    << "  \"probe_draws\": " << o.probe.draws << ",\n"
    << "  \"static_states_probed\": [";
  for (std::size_t k = 0; k < r.probes.size(); ++k) {
    const ProbeResult& p = r.probes[k];
    s << (k ? ",\n    " : "\n    ") << "{\"q\": " << json_number(p.q)
      << ", \"bound_eps2\": " << json_number(p.bound_eps2)
      << ", \"removed_rattlers\": " << p.removed_rattlers
      << ", \"initial_max_net_force\": " << json_number(p.initial_max_net_force)
      << ", \"hold_steps\": " << p.hold_steps << ", \"hold_d_eps2\": " << json_number(p.hold_d_eps2)
      << ", \"max_released_d_eps2\": " << json_number(p.max_released_d_eps2)
      << ", \"final_d_eps2\": " << json_number(p.final_d_eps2)
      << ", \"final_d_epsv\": " << json_number(p.final_d_epsv)
      << ", \"stable\": " << (p.stable ? "true" : "false") << "}";
  }
  s << (r.probes.empty() ? "" : "\n  ") << "],\n"
    << "  \"static_states_stable_up_to\": " << json_number(stable_up_to(r.probes)) << ",\n"
    << "  \"probe_seconds\": " << json_number(r.probe_seconds) << ",\n"
    << "  \"static_seconds\": " << json_number(r.static_seconds) << ",\n"
    << "  \"dynamic_seconds\": " << json_number(r.dynamic_seconds) << ",\n"
    << "  \"rigid_seconds\": " << json_number(r.rigid_seconds) << "\n"
    << "}\n";
  return s.str();
}

}  // namespace granstab::crosscheck
