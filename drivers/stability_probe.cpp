#include "stability_probe.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "common/equilibrium.hpp"
#include "common/measurements.hpp"
#include "dynamic/protocols/creep.hpp"
#include "dynamic/protocols/perturbation.hpp"

namespace granstab::crosscheck {
namespace {

// Wraps a coordinate into [0, L) and returns the number of cell lengths taken off.
int wrap(double& x, double length) {
  int n = static_cast<int>(std::floor(x / length));
  x -= n * length;
  if (x >= length) {  // x a hair below 0 rounds to L
    x = 0.0;
    ++n;
  }
  return n;
}

}  // namespace

Configuration configuration_of_static_state(const statics::Network& net,
                                            const Configuration& start) {
  if (net.n_disks() != start.disks.size())
    throw std::invalid_argument("static state: not the start's disks");
  Configuration c;
  c.cell.boundary = net.boundary;
  c.cell.length = net.length;
  c.cell.mass = start.cell.mass;
  c.material = net.material;
  c.stage = start.stage;
  c.stage.control = {LengthControl::stress, LengthControl::stress};
  c.stage.strain_rate = {0.0, 0.0};
  c.stage.sigma_ext = net.loading.sigma;
  c.stage.measure = net.loading.measure;
  c.time = start.time;
  c.step = start.step;
  const std::size_t n = net.n_disks();
  std::vector<int> image1(n, 0), image2(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    double x = net.x[i], y = net.y[i];
    if (net.boundary == Boundary::periodic) {
      image1[i] = wrap(x, net.length[0]);
      image2[i] = wrap(y, net.length[1]);
    }
    c.disks.add(x, y, net.radius[i]);
    c.disks.mass[i] = start.disks.mass[i];
    c.disks.inertia[i] = start.disks.inertia[i];
    c.disks.theta[i] = net.theta[i];
  }
  c.contacts = net.contacts;
  // l = r_j + k L - r_i is kept: with r_i -> r_i - n_i L, k -> k + n_j - n_i.
  for (std::size_t k = 0; k < c.contacts.size(); ++k) {
    const int i = c.contacts.i[k], j = c.contacts.j[k];
    if (is_wall(j)) continue;
    c.contacts.k1[k] += image1[j] - image1[i];
    c.contacts.k2[k] += image2[j] - image2[i];
  }
  return c;
}

std::vector<char> overlapping_rattlers(const statics::Network& net, const Configuration& state) {
  const std::size_t n = state.disks.size();
  std::vector<char> out(n, 0);
  const Disks& d = state.disks;
  const auto& L = state.cell.length;
  const auto separation = [&](double delta, int a) {
    return state.cell.periodic() ? delta + minimum_image_shift(delta, L[a]) * L[a] : delta;
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (net.dofs.active(i)) continue;
    if (!state.cell.periodic() && (d.x[i] < d.radius[i] || d.x[i] + d.radius[i] > L[0] ||
                                   d.y[i] < d.radius[i] || d.y[i] + d.radius[i] > L[1]))
      out[i] = 1;
    for (std::size_t j = 0; j < n && !out[i]; ++j) {
      if (j == i) continue;
      const double dx = separation(d.x[j] - d.x[i], 0), dy = separation(d.y[j] - d.y[i], 1);
      if (std::hypot(dx, dy) < d.radius[i] + d.radius[j]) out[i] = 1;
    }
  }
  return out;
}

int push_out_rattlers(Configuration& state, const std::vector<char>& rattlers) {
  Disks& d = state.disks;
  const auto& L = state.cell.length;
  const bool periodic = state.cell.periodic();
  const auto separation = [&](double delta, int a) {
    return periodic ? delta + minimum_image_shift(delta, L[a]) * L[a] : delta;
  };
  constexpr double margin = 1e-9;  // units of a: a gap, not a contact at round-off
  // The push that frees disk i from its overlaps (zero when it has none).
  const auto push = [&](std::size_t i) {
    std::array<double, 2> p{0.0, 0.0};
    for (std::size_t j = 0; j < d.size(); ++j) {
      if (j == i) continue;
      const double dx = separation(d.x[j] - d.x[i], 0), dy = separation(d.y[j] - d.y[i], 1);
      const double dist = std::hypot(dx, dy), overlap = d.radius[i] + d.radius[j] - dist;
      if (overlap > 0.0 && dist > 0.0) {
        p[0] -= (overlap + margin) * dx / dist;
        p[1] -= (overlap + margin) * dy / dist;
      }
    }
    if (!periodic) {
      const double x[2] = {d.x[i], d.y[i]};
      for (int a = 0; a < 2; ++a) {
        if (x[a] < d.radius[i]) p[a] += d.radius[i] - x[a] + margin;
        if (x[a] + d.radius[i] > L[a]) p[a] -= x[a] + d.radius[i] - L[a] + margin;
      }
    }
    return p;
  };
  int left = 0;
  for (std::size_t i = 0; i < d.size() && i < rattlers.size(); ++i) {
    if (!rattlers[i]) continue;
    std::array<double, 2> p = push(i);
    for (int iteration = 0; iteration < 100 && (p[0] != 0.0 || p[1] != 0.0); ++iteration) {
      d.x[i] += p[0];
      d.y[i] += p[1];
      p = push(i);
    }
    if (p[0] != 0.0 || p[1] != 0.0) ++left;
    if (!periodic) continue;
    // Back into [0, L): l = r_j + k L - r_i is kept with k -> k + n_j - n_i.
    const int n1 = wrap(d.x[i], L[0]), n2 = wrap(d.y[i], L[1]);
    Contacts& c = state.contacts;
    for (std::size_t k = 0; k < c.size(); ++k) {
      if (is_wall(c.j[k])) continue;
      if (c.i[k] == static_cast<int>(i)) c.k1[k] -= n1, c.k2[k] -= n2;
      if (c.j[k] == static_cast<int>(i)) c.k1[k] += n1, c.k2[k] += n2;
    }
  }
  return left;
}

Configuration without_disks(const Configuration& config, const std::vector<char>& remove) {
  Configuration c = config;
  const std::size_t n = config.disks.size();
  std::vector<int> index(n, -1);
  c.disks = Disks{};
  for (std::size_t i = 0; i < n; ++i) {
    if (i < remove.size() && remove[i]) continue;
    index[i] =
        static_cast<int>(c.disks.add(config.disks.x[i], config.disks.y[i], config.disks.radius[i]));
    using Field = std::vector<double> Disks::*;
    for (const Field field :
         {&Disks::mass, &Disks::inertia, &Disks::vx, &Disks::vy, &Disks::omega, &Disks::theta})
      (c.disks.*field)[index[i]] = (config.disks.*field)[i];
  }
  c.contacts.clear();
  const Contacts& k = config.contacts;
  for (std::size_t m = 0; m < k.size(); ++m) {
    const int i = index[k.i[m]];
    const int j = is_wall(k.j[m]) ? k.j[m] : index[k.j[m]];
    if (i < 0 || (!is_wall(k.j[m]) && j < 0)) continue;
    c.contacts.add(i, j, k.k1[m], k.k2[m], k.delta_t[m], k.status[m]);
  }
  return c;
}

double static_load_tolerance(const CrosscheckOptions& options) {
  return 1e-6 * options.dq / options.static_substeps;
}

statics::StabilityResult static_run_to(const Configuration& start, const CrosscheckOptions& options,
                                       double q) {
  CrosscheckOptions o = options;
  o.q_max = q - static_load_tolerance(options);
  o.rigid_limit = false;
  o.statics.steps = statics::StepControl::fixed;  // as every run that hands states on
  // run_static_half starts from biaxial_start(sample): the start is that state already (its
  // reference lengths are its lengths), and biaxial_start of it is itself.
  return run_static_half(start, o).statics;
}

std::function<void(double, const statics::Network&)> keep_static_states(
    std::vector<double> at, double tolerance, std::vector<StaticState>& states) {
  std::sort(at.begin(), at.end());
  // States come in increasing load: keep one when it reaches the lowest load not reached before.
  return [at = std::move(at), tolerance, &states, next = std::size_t{0}](
             double load, const statics::Network& net) mutable {
    if (next == at.size() || load < at[next] - tolerance) return;
    states.push_back({load, net});
    while (next < at.size() && load >= at[next] - tolerance) ++next;
  };
}

const StaticState* static_state_at(const std::vector<StaticState>& states, double q,
                                   double tolerance) {
  for (const StaticState& s : states)
    if (s.load >= q - tolerance) return &s;
  return nullptr;
}

ProbeResult probe_static_state(const Configuration& static_state, const std::vector<char>& remove,
                               double q, double bound_eps2, const ProbeOptions& options) {
  ProbeResult r;
  r.q = q;
  r.bound_eps2 = bound_eps2;
  r.rattler_overlaps = static_cast<int>(std::count(remove.begin(), remove.end(), 1));
  const bool drop = options.remove_overlapping_rattlers && r.rattler_overlaps > 0;
  const Configuration state = drop ? without_disks(static_state, remove) : static_state;
  if (drop) r.removed_rattlers = r.rattler_overlaps;
  const std::array<double, 3> at_start = strains(state);

  Engine engine(state, options.engine);
  Configuration current;
  engine.export_to(current);  // the engine's contacts: also overlaps the file did not list
  const EquilibriumReport initial = check_equilibrium(current, options.equilibration.tolerances);
  r.initial_max_net_force = initial.max_net_force;
  r.initial_stress_error = std::max(initial.stress_error[0], initial.stress_error[1]);

  protocols::CreepOptions hold;
  hold.equilibration = options.equilibration;
  const double pressure = state.stage.sigma_ext[0];
  const protocols::CreepResult h = protocols::hold_deviator(engine, q, pressure, hold, current);
  r.hold_reached = h.equilibrium.reached;
  r.hold_steps = h.equilibrium.steps;
  r.hold_d_eps2 = h.epsilon_2_end - at_start[1];
  r.hold_d_epsv = h.epsilon_v_end - at_start[2];

  if (r.hold_reached && options.f0 > 0.0 && options.draws > 0) {
    protocols::PerturbationOptions p;
    p.f0 = options.f0;
    p.repetitions = options.draws;
    p.release = true;
    p.equilibration = options.equilibration;
    std::mt19937_64 rng(options.seed);
    protocols::run_perturbations(
        engine, p, rng, current,
        [&r](const Engine&, const Configuration&, const protocols::PerturbationRecord& d) {
          r.perturbation_steps += d.loaded.steps + d.released.steps;
          r.max_loaded_d_eps2 = std::max(r.max_loaded_d_eps2, std::abs(d.delta_epsilon_2));
          r.max_released_d_eps2 =
              std::max(r.max_released_d_eps2, std::abs(d.delta_epsilon_2_released));
          const bool reached = d.loaded.reached && d.released.reached;
          r.draws_reached += reached ? 1 : 0;
          return reached;
        });
  }
  engine.export_to(current);
  const std::array<double, 3> at_end = strains(current);
  r.final_d_eps2 = at_end[1] - at_start[1];
  r.final_d_epsv = at_end[2] - at_start[2];
  const bool waits_reached =
      r.hold_reached && (options.f0 <= 0.0 || r.draws_reached == std::max(0, options.draws));
  r.stable = waits_reached && std::abs(r.hold_d_eps2) <= bound_eps2 &&
             std::abs(r.final_d_eps2) <= bound_eps2;
  return r;
}

std::vector<ProbeResult> probe_static_states(const CrosscheckResult& result,
                                             const CrosscheckOptions& options) {
  std::vector<ProbeResult> probes;
  const int k_states = options.probe.states;
  if (k_states <= 0 || result.statics.curve.empty()) return probes;
  ProbeOptions po;
  po.f0 = options.probe.f0;
  po.draws = options.probe.draws;
  po.seed = options.probe.seed;
  po.remove_overlapping_rattlers = options.probe.remove_overlapping_rattlers;
  po.equilibration = options.equilibration;
  po.engine = options.engine;
  if (result.static_states.empty())
    throw std::invalid_argument(
        "probe_static_states: the static run kept no states (run it with "
        "probe.states > 0)");
  const double q0 = result.statics.curve.front().load;
  const double step = options.dq / options.static_substeps;
  for (int k = 1; k <= k_states; ++k) {
    // k = K: the state at q1.
    const statics::Network* net = &result.statics.network_at_q1;
    double load = result.statics.curve.back().load;
    if (k < k_states) {
      const double q = q0 + std::floor((result.statics.q1 - q0) * k / k_states / step) * step;
      if (!(q > q0)) continue;
      const StaticState* s =
          static_state_at(result.static_states, q, static_load_tolerance(options));
      if (!s) throw std::logic_error("probe_static_states: no static state at q below q1");
      net = &s->network;
      load = s->load;
    }
    const Configuration state = configuration_of_static_state(*net, result.start);
    const double bound = static_bound_eps2(result.statics.curve, load, result.pressure,
                                           options.equilibration.tolerances);
    probes.push_back(probe_static_state(state, overlapping_rattlers(*net, state), load, bound, po));
  }
  return probes;
}

double stable_up_to(const std::vector<ProbeResult>& probes) {
  double q = std::numeric_limits<double>::quiet_NaN();
  for (const ProbeResult& p : probes) {
    if (!p.stable) break;
    q = p.q;
  }
  return q;
}

}  // namespace granstab::crosscheck
