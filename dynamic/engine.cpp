#include "engine.hpp"

#include <omp.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "cell_control.hpp"
#include "common/contact_law.hpp"
#include "halo.hpp"
#include "integrator.hpp"

namespace granstab {

using dynamic::BlockSums;
using dynamic::ForceInputs;

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

}  // namespace

void Engine::check_axis(int axis) {
  require(axis == 0 || axis == 1, "engine: axis must be 0 or 1, got " + std::to_string(axis));
}

Engine::Engine(const Configuration& config, const EngineOptions& options)
    : options_(options),
      material_(config.material),
      stage_(config.stage),
      neighbours_(options.skin),
      time_(config.time),
      step_(config.step),
      rng_state_(config.rng_state) {
  validate(config.material);
  validate(config.cell);
  const Disks& in = config.disks;
  const std::size_t n = in.size();
  require(n >= 1, "configuration: no disks");
  for (auto* v : {&in.y, &in.radius, &in.mass, &in.inertia, &in.vx, &in.vy, &in.omega, &in.theta}) {
    require(v->size() == n,
            "configuration.disks: all fields must have N = " + std::to_string(n) + " entries");
  }
  require(std::isfinite(options.dt_fraction) && options.dt_fraction > 0.0,
          "engine options: dt_fraction must be > 0");
  require(std::isfinite(options.skin) && options.skin > 0.0, "engine options: skin must be > 0");

  cell_.boundary = config.cell.boundary;
  cell_.length = config.cell.length;
  cell_.length_rate = config.cell.length_rate;
  cell_.mass = config.cell.mass;

  disks_.x.assign(in.x.begin(), in.x.end());
  disks_.y.assign(in.y.begin(), in.y.end());
  disks_.vx.assign(in.vx.begin(), in.vx.end());
  disks_.vy.assign(in.vy.begin(), in.vy.end());
  disks_.omega.assign(in.omega.begin(), in.omega.end());
  disks_.theta.assign(in.theta.begin(), in.theta.end());
  disks_.radius.assign(in.radius.begin(), in.radius.end());
  disks_.mass.assign(in.mass.begin(), in.mass.end());
  disks_.inertia.assign(in.inertia.begin(), in.inertia.end());
  disks_.inv_mass.resize(n);
  disks_.inv_inertia.resize(n);
  disks_.alpha_wall.resize(n);
  double m_min = INFINITY;
  for (std::size_t i = 0; i < n; ++i) {
    const std::string at = "configuration.disks[" + std::to_string(i) + "]";
    require(std::isfinite(in.x[i]) && std::isfinite(in.y[i]), at + ": position must be finite");
    require(in.radius[i] > 0.0 && in.mass[i] > 0.0 && in.inertia[i] > 0.0,
            at + ": radius, mass and inertia must be > 0");
    disks_.inv_mass[i] = 1.0 / in.mass[i];
    disks_.inv_inertia[i] = 1.0 / in.inertia[i];
    m_min = std::min(m_min, in.mass[i]);
    if (cell_.periodic()) {
      disks_.x[i] =
          dynamic::wrap(disks_.x[i] - std::floor(disks_.x[i] / cell_.length[0]) * cell_.length[0],
                        cell_.length[0]);
      disks_.y[i] =
          dynamic::wrap(disks_.y[i] - std::floor(disks_.y[i] / cell_.length[1]) * cell_.length[1],
                        cell_.length[1]);
    }
  }
  for (auto* v : {&disks_.vpx, &disks_.vpy, &disks_.fx, &disks_.fy, &disks_.torque, &disks_.fvx,
                  &disks_.fvy}) {
    v->assign(n, 0.0);
  }
  for (auto& w : disks_.wall_delta_t) w.assign(n, 0.0);
  for (auto& w : disks_.wall_f_v) w.assign(n, 0.0);
  for (auto& w : disks_.wall_closed) w.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    disks_.alpha_wall[i] = material_.damping_coefficient(in.mass[i], INFINITY);
  }
  time_scale_ = std::sqrt(m_min / material_.k_n);
  dt_ = options.dt_fraction * time_scale_;

  apply_stage(config.stage);
  neighbours_.rebuild(disks_, cell_, pairs_, material_);
  import_contacts(config.contacts);
  evaluate_state();
}

void Engine::import_contacts(const Contacts& c) {
  const int n = static_cast<int>(disks_.size());
  for (std::size_t k = 0; k < c.size(); ++k) {
    const std::string at = "configuration.contacts[" + std::to_string(k) + "]";
    const int i = c.i[k], j = c.j[k];
    require(i >= 0 && i < n, at + ": i out of range");
    if (is_wall(j)) {
      require(!cell_.periodic(), at + ": wall contact in a periodic cell");
      require(j >= wall_top, at + ": unknown wall " + std::to_string(j));
      disks_.wall_delta_t[-j - 1][i] = c.delta_t[k];
      continue;
    }
    require(j < n && j != i, at + ": j out of range");
    // delta_t is unchanged when i and j swap (n and t both flip), so (min, max) carries it.
    const int a = std::min(i, j), b = std::max(i, j);
    const auto first = pairs_.j.begin() + pairs_.row_start[a];
    const auto last = pairs_.j.begin() + pairs_.row_start[a + 1];
    const auto it = std::lower_bound(first, last, b);
    // A listed contact beyond the skin is open: its state is dropped (SPEC §1.1).
    if (it != last && *it == b) pairs_.delta_t[it - pairs_.j.begin()] = c.delta_t[k];
  }
}

ForceInputs Engine::force_inputs(const dynamic::CellState& cell, double dt_tangential,
                                 bool mid_step) const {
  ForceInputs in;
  in.material = &material_;
  in.periodic = cell.periodic();
  in.length = cell.length;
  in.dt = dt_tangential;
  for (int a = 0; a < 2; ++a) {
    const double scale = in.periodic ? 1.0 / cell.length[a] : 1.0;
    in.rate_tangential[a] = cell.length_rate[a] * scale;
    in.rate_viscous[a] = (mid_step ? cell.rate_predicted[a] : cell.length_rate[a]) * scale;
  }
  in.vx = disks_.vx.data();
  in.vy = disks_.vy.data();
  in.omega = disks_.omega.data();
  in.vx_viscous = mid_step ? disks_.vpx.data() : disks_.vx.data();
  in.vy_viscous = mid_step ? disks_.vpy.data() : disks_.vy.data();
  in.parallel = parallel();
  return in;
}

void Engine::evaluate_state() {
  sums_ = dynamic::compute_contact_forces(
      disks_, pairs_, [&] { return force_inputs(cell_, 0.0, false); }, blocks_);
  control_cell(cell_, sums_);
}

void Engine::control_cell(dynamic::CellState& cell, const BlockSums& sums) const {
  const dynamic::ControlForces f =
      dynamic::control_forces(cell, sums, options_.viscous_forces_drive_cell);
  cell.length_acceleration = dynamic::length_acceleration(cell, stage_, f);
}

void Engine::step() { run(1); }

namespace {
constexpr int colocated_steps = 16;
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}
}  // namespace

// Velocity Verlet. The first half kick and the drift belong to the integrator; the forces at
// t + dt need the velocities at t + dt only through the viscous term, which is evaluated with
// predicted velocities and then refreshed with the final ones so that the cached forces are a
// function of the synchronous state (docs/dynamic.md).
//
// The whole run is one parallel region (docs/dynamic.md, "Performance"; a timed team that
// gives its steps to one thread ends it early, below): each thread drifts,
// sweeps and kicks the disks of its own part in every pass of every step, and the team meets
// at the barriers the data flow needs: after the drift (partners' positions and mid-step
// velocities, the displacement maximum) and after the force pass (the final velocities the
// viscous refresh reads). The block sums the cell's control needs are relayed from thread to
// thread (relay_sum_blocks). The cell's state is a few numbers: every thread computes it alike
// from the same sums (same bits), so no thread waits for another to do it.
void Engine::run(std::uint64_t steps) {
  const std::size_t n = disks_.size();
  const int threads = parallel() ? omp_get_max_threads() : 1;
  while (steps > 0) {
    // A timed team that lost to one thread leaves the next steps to one thread, across runs
    // (advance); one part then, not the team's (no mirrors).
    const bool alone = threads > 1 && choice_.alone_left > 0;
    const int team = alone ? 1 : threads;
    const auto prepare = [&](int t) {
      if (alone) {
        if (pairs_.team != 1) dynamic::plan_parts(disks_, pairs_, dynamic::even_parts(n, 1));
      } else {
        if (!dynamic::valid_parts(part_blocks_, n, t)) {
          part_blocks_ = dynamic::valid_parts(options_.part_blocks, n, t)
                             ? options_.part_blocks
                             : dynamic::even_parts(n, t);
          pairs_.team = 0;
        }
        if (pairs_.team != t) dynamic::plan_parts(disks_, pairs_, part_blocks_);
      }
      dynamic::size_passes(n, pairs_, blocks_);
      viscous_blocks_.resize(blocks_.size());
      team_slots_.resize(t);
      team_slots_[0].hand_over = false;
      relay_.reset(2 * t);
      wakeup_.reset();
    };
    const std::uint64_t chunk = alone ? std::min(steps, choice_.alone_left) : steps;
    advanced_ = chunk;  // a timed team that hands over ends early (advance)
    const Clock::time_point start = Clock::now();
    dynamic::on_team(team, barrier_, prepare,
                     [&](const dynamic::TeamMember& member) { advance(member, chunk); });
    if (alone) {
      choice_.alone_left -= chunk;
      choice_.alone_steps += chunk;
      choice_.phase_steps += chunk;
      choice_.phase_seconds += seconds_since(start);
      choice_.alone_seconds = choice_.phase_seconds / static_cast<double>(choice_.phase_steps);
    }
    steps -= advanced_;
  }
}

// A team leaves its steps to one thread for a while in two cases (docs/dynamic.md,
// "Performance"; the same bits either way):
// - a team whose threads the OS keeps on one CPU (a loaded machine: Linux wakes a sleeping
//   thread on its waker's CPU when the other is busy) does the same work plus the barriers on
//   one core: after `colocated_steps` such steps in a row, thread 0 runs all the parts in their
//   order for EngineOptions::alone_steps steps while the others sleep, then wakes them; if the
//   OS now puts them on another CPU, the team goes on;
// - below EngineOptions::timed_team_max_disks thread 0 times the team's steps in windows of
//   window_steps(), run() times one thread's for a quarter of that, and the faster goes on
//   (alone_after): the team stops, every thread at the same step, and run() gives the next
//   steps to one thread on one part (no mirrors).

std::uint64_t Engine::window_steps() const {
  return options_.alone_steps > 0 ? options_.alone_steps
                                  : std::max<std::uint64_t>(64, 2'000'000 / size());
}

// Lost: one thread for 1, 2, 4 .. 64 windows (doubling while the team keeps losing), then the
// team again. Won: one thread is tried for a quarter window after 1, then 2, 4 .. 64 more team
// windows, so a winning team loses at most ~1 % of its time to the trials in a long run.
std::uint64_t Engine::alone_after(double team_seconds) {
  TeamChoice& c = choice_;
  const std::uint64_t window = window_steps();
  if (c.alone_seconds > 0.0 && team_seconds > c.alone_seconds) {
    const int windows = c.alone_windows;
    c.alone_windows = std::min(64, 2 * c.alone_windows);
    c.team_windows = 1;
    c.team_windows_won = 0;
    return windows * window;
  }
  c.alone_windows = 1;
  if (c.alone_seconds > 0.0 && ++c.team_windows_won < c.team_windows) return 0;
  if (c.alone_seconds > 0.0) c.team_windows = std::min(64, 2 * c.team_windows);
  c.team_windows_won = 0;
  return std::max<std::uint64_t>(16, window / 4);
}

void Engine::advance(const dynamic::TeamMember& team_member, std::uint64_t steps) {
  Local local{cell_, sums_, neighbours_.rebuild_test(), 0.0};
  dynamic::TeamClock clock;
  dynamic::TeamMember member = team_member;
  const std::uint64_t balance_steps = member.threads > 1 ? options_.balance_steps : 0;
  if (balance_steps > 0) {
    member.clock = &clock;
    clock.leave();
  }
  dynamic::TeamMember alone = team_member;
  alone.threads = 1;
  alone.part_first = 0;
  alone.part_end = member.threads;
  // Thread 0 times the team in windows of team steps, which go on across runs (the time
  // between runs not counted) and start afresh after a time alone.
  const bool timed = member.threads > 1 && size() < options_.timed_team_max_disks;
  const std::uint64_t window = timed ? window_steps() : 0;
  Clock::time_point mark = Clock::now();
  std::uint64_t alone_steps = 0;  // thread 0: the length of the next time alone
  int colocated = 0;
  std::uint32_t hand_backs = 0;
  std::uint64_t s = 0;
  while (s < steps) {
    // Every thread counts the same steps (s), so they agree on the balance steps.
    const bool balance = balance_steps > 0 && (s + 1) % balance_steps == 0;
    bool hand_over = false;
    colocated = step_on(member, local, balance, &hand_over) ? colocated + 1 : 0;
    ++s;
    if (member.thread == 0 && timed && ++choice_.in_window == window) {
      const double seconds = choice_.window_seconds + seconds_since(mark);
      // Read by every thread after the next step's first barrier (step_on).
      alone_steps = alone_after(seconds / static_cast<double>(window));
      team_slots_[0].hand_over = alone_steps > 0;
      choice_.in_window = 0;
      choice_.window_seconds = 0.0;
      mark = Clock::now();
    }
    if (hand_over) {
      // Every thread stops here; run() gives the next steps to one thread.
      if (member.thread == 0) advanced_ = s;
      break;
    }
    if (colocated < colocated_steps || s == steps) continue;
    alone_steps = window_steps();
    colocated = 0;
    ++hand_backs;
    member.sync();  // the others finish the step before thread 0 takes over
    if (member.thread == 0) {
      team_slots_[0].hand_over = false;  // the others read it after they wake
      const std::uint64_t end = std::min(steps, s + alone_steps);
      const std::uint64_t from = s;
      for (; s < end; ++s) step_on(alone, local);
      choice_.alone_steps += s - from;
      hand_back_ = {local, s};
      wakeup_.publish(hand_backs);
    } else {
      wakeup_.await(hand_backs);
      local = hand_back_.local;
      s = hand_back_.step;
    }
    clock = dynamic::TeamClock{};  // the time alone is no measure of the parts
    clock.leave();
    if (member.thread == 0) {  // the team's window starts afresh, moving the data back included
      choice_.in_window = 0;
      choice_.window_seconds = 0.0;
      mark = Clock::now();
    }
  }
  if (member.thread == 0) {
    choice_.window_seconds += seconds_since(mark);
    if (team_slots_[0].hand_over) {  // taken (or decided in the run's last step): one thread next
      choice_.alone_left = alone_steps;
      choice_.phase_steps = 0;
      choice_.phase_seconds = 0.0;
      choice_.in_window = 0;
      choice_.window_seconds = 0.0;
    }
  }
  // Threads other than 0 read cell_ and sums_ only before their first barrier (or hand-back),
  // which thread 0 has passed too.
  if (member.thread == 0) {
    cell_ = local.cell;
    sums_ = local.sums;
    neighbours_.set_max_displacement_squared(local.max_d2);
  }
}

// One step on the member's parts; returns whether the whole team ran it on one CPU. With balance,
// the team's parts are balanced after the drift (balance_parts).
bool Engine::step_on(const dynamic::TeamMember& member, Local& local, bool balance,
                     bool* hand_over) {
  const std::size_t n = disks_.size();
  const int first = dynamic::part_disks(pairs_, n, member.part_first)[0];
  const int end = dynamic::part_disks(pairs_, n, member.part_end - 1)[1];
  dynamic::CellState& cell = local.cell;
  BlockSums& sums = local.sums;
  const bool team = member.threads > 1;
  if (team) team_slots_[member.thread].cpu = sched_getcpu();
  const std::array<double, 2> lambda = dynamic::kick_drift_cell(cell, stage_, dt_);
  const double d2 = dynamic::kick_drift_disks(disks_, cell, lambda, dt_, neighbours_, first, end);
  team_slots_[member.thread].max_d2 = d2;
  // The halo (Halo, state.hpp): this thread's disks that other parts read, packed for them.
  const bool halo = pairs_.team > 1;
  const auto on_parts = [&](auto exchange) {
    for (int part = member.part_first; part < member.part_end; ++part)
      exchange(disks_, pairs_.halo, part);
  };
  if (halo) on_parts(dynamic::pack_mid_step);
  bool planned = false;  // a new plan has filled the ghosts (plan_parts)
  if (balance) {
    member.clock->arrive();  // its work since the last balance, up to this barrier
    team_slots_[member.thread].busy = member.clock->busy;
    member.clock->busy = 0.0;
    member.barrier->wait();
    if (member.thread == 0) team_slots_[0].planned = balance_parts();
    member.barrier->wait();
    member.clock->leave();
    planned = team_slots_[0].planned;
  } else {
    member.sync();
  }
  // Read between this barrier and the next, before any thread writes its slot again.
  local.max_d2 = d2;
  bool colocated = team;
  if (team) {
    for (int t = 0; t < member.threads; ++t) {
      local.max_d2 = std::max(local.max_d2, team_slots_[t].max_d2);
      colocated &= team_slots_[t].cpu == team_slots_[0].cpu;
    }
    if (hand_over) *hand_over = team_slots_[0].hand_over;
  }
  if (local.rebuild_test(cell, local.max_d2)) {
    // Each thread lists the rows of its own disks, so that they are written in its cache; thread
    // 0 does the few serial steps. Out of the time the balance compares (thread 0's share would
    // move blocks off it after each rebuild, 3 % of them at N = 22400).
    const int t = member.thread;
    const auto meet = [&] {
      if (team) member.barrier->wait();
    };
    if (member.clock) member.clock->arrive();
    if (t == 0) neighbours_.begin_rebuild(disks_, cell, pairs_, member.threads);
    meet();
    neighbours_.find_rows(t, first, end);
    meet();
    if (t == 0) neighbours_.size_list(pairs_, n);
    meet();
    neighbours_.fill_rows(disks_, cell, pairs_, material_, t, first, end);
    meet();
    if (t == 0) {
      neighbours_.end_rebuild(cell, pairs_);
      // The split this run has (one part when one thread runs a timed team's steps).
      dynamic::plan_parts(disks_, pairs_, pairs_.part_block);
    }
    meet();
    if (member.clock) member.clock->leave();
    local.rebuild_test = neighbours_.rebuild_test();
    planned = true;
  }
  if (halo && !planned) on_parts(dynamic::unpack_mid_step);
  ForceInputs in = force_inputs(cell, dt_, true);
  in.kick = true;  // the disks' second half kick, as each disk's forces are complete
  dynamic::contact_forces_part(member, disks_, pairs_, in, blocks_);
  const bool viscous = material_.zeta != 0.0;
  if (halo && viscous) on_parts(dynamic::pack_final);
  member.sync();  // the final velocities, which the viscous refresh reads
  if (halo && viscous) on_parts(dynamic::unpack_final);
  sums =
      dynamic::relay_sum_blocks(member, blocks_, pairs_, n, cell.periodic(), relay_, ++local.epoch);
  control_cell(cell, sums);
  dynamic::kick_cell(cell, stage_, dt_);
  // The viscous forces of the final velocities (zeta = 0: alpha = 0, they are exact zeros,
  // and fvx, fvy hold zeros already).
  if (viscous) {
    dynamic::viscous_forces_part(member, disks_, pairs_, force_inputs(cell, 0.0, false),
                                 viscous_blocks_);
    // No barrier: the next step's drift writes this thread's disks only (the others' refresh
    // reads their ghosts), and the relay hands the sums on.
    const BlockSums v = dynamic::relay_sum_blocks(member, viscous_blocks_, pairs_, n,
                                                  cell.periodic(), relay_, ++local.epoch);
    sums.sigma_viscous = v.sigma_viscous;
    sums.wall_force_viscous = v.wall_force_viscous;
    control_cell(cell, sums);
  }
  if (member.thread == 0) {
    ++step_;
    time_ += dt_;
  }
  return colocated;
}

// Thread 0, between two barriers of the team (the others read pairs_ only after the second).
// Returns whether the split moved (a new plan).
bool Engine::balance_parts() {
  std::vector<double> busy(team_slots_.size());
  for (std::size_t t = 0; t < busy.size(); ++t) busy[t] = team_slots_[t].busy;
  std::vector<std::int32_t> parts = dynamic::balanced_parts(part_blocks_, busy, 0.03);
  if (parts == part_blocks_) return false;
  part_blocks_ = std::move(parts);
  ++part_moves_;
  dynamic::plan_parts(disks_, pairs_, part_blocks_);
  return true;
}

void Engine::set_dt(double dt) {
  require(std::isfinite(dt) && dt > 0.0, "engine: dt must be finite and > 0");
  dt_ = dt;
}

// Validates and takes the stage; strain-rate controlled and fixed axes carry their imposed
// rate in the synchronous state too. Returns whether a rate changed.
bool Engine::apply_stage(const Stage& stage) {
  for (int a = 0; a < 2; ++a) {
    require(std::isfinite(stage.sigma_ext[a]), "stage.sigma_ext must be finite");
    require(std::isfinite(stage.strain_rate[a]), "stage.strain_rate must be finite");
    require(stage.reference_length[a] > 0.0, "stage.reference_length must be > 0");
  }
  stage_ = stage;
  bool changed = false;
  for (int a = 0; a < 2; ++a) {
    if (stage_.control[a] == LengthControl::stress) continue;
    const double rate = dynamic::imposed_length_rate(stage_, a);
    changed |= rate != cell_.length_rate[a];
    cell_.length_rate[a] = rate;
  }
  return changed;
}

void Engine::set_stage(const Stage& stage) {
  if (apply_stage(stage)) {
    evaluate_state();  // the viscous forces of the state see the new rates
  } else {
    control_cell();
  }
}

void Engine::set_sigma_ext(int axis, double sigma) {
  check_axis(axis);
  Stage s = stage_;
  s.sigma_ext[axis] = sigma;
  set_stage(s);
}

void Engine::set_stress_control(int axis, double sigma) {
  check_axis(axis);
  Stage s = stage_;
  s.control[axis] = LengthControl::stress;
  s.sigma_ext[axis] = sigma;
  set_stage(s);
}

void Engine::set_strain_rate_control(int axis, double strain_rate) {
  check_axis(axis);
  Stage s = stage_;
  s.control[axis] = LengthControl::strain_rate;
  s.strain_rate[axis] = strain_rate;
  set_stage(s);
}

void Engine::set_fixed(int axis) {
  check_axis(axis);
  Stage s = stage_;
  s.control[axis] = LengthControl::fixed;
  set_stage(s);
}

void Engine::set_measure(StressMeasure measure) {
  Stage s = stage_;
  s.measure = measure;
  set_stage(s);
}

void Engine::set_reference_lengths(std::array<double, 2> lengths) {
  Stage s = stage_;
  s.reference_length = lengths;
  set_stage(s);
}

void Engine::set_material(const Material& material) {
  validate(material);
  const bool new_time_scale = material.k_n != material_.k_n;
  material_ = material;
  for (std::size_t i = 0; i < disks_.size(); ++i) {
    disks_.alpha_wall[i] = material_.damping_coefficient(disks_.mass[i], INFINITY);
  }
  for (std::size_t p = 0; p < pairs_.size(); ++p) {
    pairs_.alpha[p] =
        material_.damping_coefficient(disks_.mass[pairs_.i[p]], disks_.mass[pairs_.j[p]]);
  }
  // The mirrors of the pairs across the parts copy alpha too.
  if (pairs_.team > 0) dynamic::plan_parts(disks_, pairs_, pairs_.part_block);
  if (new_time_scale) {
    const double m_min = *std::min_element(disks_.mass.begin(), disks_.mass.end());
    time_scale_ = std::sqrt(m_min / material_.k_n);
    dt_ = options_.dt_fraction * time_scale_;
  }
  evaluate_state();
}

void Engine::set_cell_mass(std::array<double, 2> mass) {
  for (int a = 0; a < 2; ++a) {
    require(std::isfinite(mass[a]) && mass[a] > 0.0, "engine: cell mass must be > 0");
  }
  cell_.mass = mass;
  control_cell();
}

void Engine::set_external_forces(std::span<const double> fx, std::span<const double> fy) {
  require(fx.size() == disks_.size() && fy.size() == disks_.size(),
          "engine: external forces need N entries per component");
  disks_.ext_fx.assign(fx.begin(), fx.end());
  disks_.ext_fy.assign(fy.begin(), fy.end());
  evaluate_state();
}

void Engine::clear_external_forces() {
  disks_.ext_fx.clear();
  disks_.ext_fy.clear();
  evaluate_state();
}

}  // namespace granstab
