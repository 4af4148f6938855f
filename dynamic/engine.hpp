#pragma once
// The MD engine of SPEC §1 and §3 (issue #3): disks with the common contact law in a periodic
// cell or between walls, the cell lengths / mobile walls under per-axis control. Protocols
// (issue #4) are small drivers over one Engine: they set the control between steps and call
// step() / run(); the Engine owns the one time loop.
//
// State in and out is a granstab::Configuration (positions, fluctuating velocities, spins, cell,
// contacts with delta_t and images, stage). A configuration exported after any step and read
// back into a new Engine continues to the bit (the cached forces are a function of that state).
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "common/configuration.hpp"
#include "contact_forces.hpp"
#include "neighbour_list.hpp"
#include "state.hpp"

namespace granstab {

struct EngineOptions {
  // Time step as a fraction of the shortest contact time scale sqrt(m_min / K_N); the default
  // and its justification are in docs/dynamic.md (restitution and energy tests).
  double dt_fraction = 0.05;
  // Verlet-list skin in units of a (the largest diameter).
  double skin = 0.1;
  // Whether the viscous contact forces push the periodic cell / mobile walls (see
  // docs/dynamic.md: they vanish at equilibrium; without them the cell's own oscillation is
  // only damped through the disks' non-affine motion). Measured stresses never include them.
  bool viscous_forces_drive_cell = true;
  // Samples with fewer disks run every loop on the calling thread whatever OMP_NUM_THREADS says:
  // below this size a step is too short for the synchronisation of a thread team to pay off
  // (and on a loaded machine, waiting for a descheduled thread costs whole time slices); up to
  // timed_team_max_disks the team checks that it pays. The results are the same bits either
  // way (docs/dynamic.md, "Determinism"; bench/README.md).
  std::size_t parallel_min_disks = 1024;
  // Steps a team that the OS keeps on one CPU runs on one thread before it tries again (see
  // Engine::run); 0: 2e6 / N, about 0.1 s on the test machine. Also the window over which a
  // team times itself (timed_team_max_disks). Same bits either way.
  std::uint64_t alone_steps = 0;
  // Below this many disks a team times its steps against one thread's (the sample as one part,
  // no team) and runs on one thread while that is faster (Engine::run;
  // docs/dynamic.md, "Performance"). Two cores of a virtual machine pass cache lines in 50 ns
  // at one time and in 230 ns at another, which decides whether two threads pay at N = 1400;
  // above this size they always did. 0: never timed. Same bits either way.
  std::size_t timed_team_max_disks = 4096;
  // Every so many steps a team moves its parts' boundaries (whole blocks of 64 disks) towards
  // equal work times of its threads, when the slowest took more than 3 % over the mean: a CPU
  // that runs slower (a busy neighbour of a virtual machine) or a part with more boundary work
  // then holds fewer disks. 0: the parts stay as they are. Same bits either way (docs/dynamic.md,
  // "Determinism").
  std::uint64_t balance_steps = 200;
  // The team's first split (first block of each part, then the block count; see
  // dynamic::valid_parts); empty or not valid for the team: even.
  std::vector<std::int32_t> part_blocks;
};

class Engine {
 public:
  using Tensor = std::array<std::array<double, 2>, 2>;  // sigma[a][b] = (1/A) sum f_a l_b

  explicit Engine(const Configuration& config, const EngineOptions& options = {});

  // One velocity-Verlet step: update neighbours -> contact forces -> cell/wall control ->
  // integrate (see step() in engine.cpp).
  void step();
  void run(std::uint64_t steps);

  // --- state out ---------------------------------------------------------------------------
  Configuration configuration() const;
  void export_to(Configuration& out) const;  // reuses out's storage

  // --- clock -------------------------------------------------------------------------------
  double time() const { return time_; }
  std::uint64_t step_count() const { return step_; }
  double dt() const { return dt_; }
  void set_dt(double dt);
  double time_scale() const { return time_scale_; }  // sqrt(m_min / K_N)

  // --- control (may be changed between steps) ----------------------------------------------
  const Stage& stage() const { return stage_; }
  void set_stage(const Stage& stage);
  void set_sigma_ext(int axis, double sigma);  // prescribed stress (SIC: sigma_2 = P(1+q))
  void set_stress_control(int axis, double sigma);
  void set_strain_rate_control(int axis, double strain_rate);  // d epsilon_a / dt
  void set_fixed(int axis);
  void set_measure(StressMeasure measure);
  // New reference lengths L_a0 (start of a biaxial stage); default: the current lengths.
  void set_reference_lengths(std::array<double, 2> lengths);
  void set_reference_lengths_to_current() { set_reference_lengths(cell_.length); }
  const Material& material() const { return material_; }
  // E.g. mu_prep -> mu between stages. delta_t is kept (returned to the new Coulomb cone if it
  // lies outside); a new K_N resets dt to dt_fraction sqrt(m_min / K_N).
  void set_material(const Material& material);
  void set_cell_mass(std::array<double, 2> mass);
  // Constant external force on every disk (random perturbation test); sizes must be N. Not
  // part of the Configuration: a resumed run sets it again.
  void set_external_forces(std::span<const double> fx, std::span<const double> fy);
  void clear_external_forces();

  // --- measurements at the current (synchronous) state --------------------------------------
  std::size_t size() const { return disks_.size(); }
  Tensor stress() const;  // elastic + frictional contact forces only (SPEC §2)
  // Diagonal of the same sum over the viscous contact forces (not part of any measured stress;
  // for comparisons with codes whose virial includes damping, bench/compare_lammps).
  std::array<double, 2> viscous_stress() const;
  // The stress component a as the control sees it: Cauchy sigma_aa, or for the nominal
  // measure the force on the side normal to a divided by that side's reference length.
  double controlled_stress(int axis) const;
  // Walls: force of the disks on the mobile wall normal to a (elastic + frictional) divided by
  // the wall's current length. Periodic: equals stress()[a][a].
  double wall_stress(int axis) const;
  Cell cell() const { return cell_.cell(); }
  std::array<double, 2> length() const { return cell_.length; }
  std::array<double, 2> length_rate() const { return cell_.length_rate; }
  // Net force (contacts, viscous included, plus external) and torque on each disk.
  double force_x(std::size_t i) const { return disks_.fx[i] + disks_.fvx[i]; }
  double force_y(std::size_t i) const { return disks_.fy[i] + disks_.fvy[i]; }
  double torque(std::size_t i) const { return disks_.torque[i]; }
  std::span<const double> x() const { return std::span(disks_.x).first(size()); }
  std::span<const double> y() const { return std::span(disks_.y).first(size()); }
  std::span<const double> vx() const { return std::span(disks_.vx).first(size()); }
  std::span<const double> vy() const { return std::span(disks_.vy).first(size()); }
  std::span<const double> omega() const { return std::span(disks_.omega).first(size()); }
  std::span<const double> radius() const { return std::span(disks_.radius).first(size()); }
  double kinetic_energy() const;       // translation (fluctuating velocities) + rotation
  double elastic_energy() const;       // K_N h^2 / 2 + K_T delta_t^2 / 2 over all contacts
  double cell_kinetic_energy() const;  // sum_a M_a (dL_a/dt)^2 / 2
  std::size_t contact_count() const;   // disk-disk and disk-wall contacts with h > 0
  std::uint64_t neighbour_rebuilds() const { return neighbours_.rebuild_count(); }
  // The team's split of the last run (first block of each part, then the block count) and how
  // many times balancing moved it so far.
  const std::vector<std::int32_t>& part_blocks() const { return part_blocks_; }
  std::uint64_t part_moves() const { return part_moves_; }
  // Steps that a team left to one thread so far (on one CPU, or timed against one thread).
  std::uint64_t alone_step_count() const { return choice_.alone_steps; }

 private:
  static void check_axis(int axis);  // throws std::invalid_argument unless 0 or 1
  bool parallel() const { return disks_.size() >= options_.parallel_min_disks; }
  void evaluate_state();  // forces and cell acceleration of the current state (no increment)
  bool apply_stage(const Stage& stage);
  void control_cell() { control_cell(cell_, sums_); }
  void control_cell(dynamic::CellState& cell, const dynamic::BlockSums& sums) const;
  // A thread's copy of the state the team computes alike (same bits on every thread).
  struct Local {
    dynamic::CellState cell;
    dynamic::BlockSums sums;
    dynamic::NeighbourList::RebuildTest rebuild_test;
    double max_d2 = 0.0;      // largest displacement since the list build, squared
    std::uint32_t epoch = 0;  // the team's reductions so far (relay_)
  };
  // One thread's share of run(steps), inside the team's parallel region.
  void advance(const dynamic::TeamMember& member, std::uint64_t steps);
  // Returns whether the whole team ran the step on one CPU; *hand_over: thread 0 asked the team
  // to stop and leave the next steps to one thread (TeamChoice).
  bool step_on(const dynamic::TeamMember& member, Local& local, bool balance = false,
               bool* hand_over = nullptr);
  std::uint64_t window_steps() const;
  // Thread 0 after a window of the team: how many steps one thread runs next (0: none).
  std::uint64_t alone_after(double team_seconds);
  bool balance_parts();  // thread 0, while the team waits; whether the split moved
  dynamic::ForceInputs force_inputs(const dynamic::CellState& cell, double dt_tangential,
                                    bool mid_step) const;
  void import_contacts(const Contacts& contacts);

  EngineOptions options_;
  Material material_;
  Stage stage_;
  dynamic::DiskArrays disks_;
  dynamic::PairArrays pairs_;
  dynamic::CellState cell_;
  dynamic::NeighbourList neighbours_;
  dynamic::BlockSums sums_;  // elastic sums of the last force pass + viscous of the state
  // Per-block sums of the force pass and of the viscous refresh: apart, so that a thread may
  // start the refresh while another still adds the force pass's sums.
  std::vector<dynamic::BlockSums> blocks_, viscous_blocks_;
  // The team of run(): its barrier; each thread's largest displacement of the step and CPU (one
  // cache line each, written by its thread, read by all after the barrier); where threads
  // sleep while thread 0 runs alone, and the state it hands back to them.
  dynamic::SpinBarrier barrier_;
  dynamic::Relay<dynamic::BlockSums> relay_;  // the block sums handed from thread to thread
  struct alignas(64) TeamSlot {
    double max_d2 = 0.0;
    double busy = 0.0;  // work seconds since the last balance (at a balance step)
    int cpu = -1;
    bool hand_over = false;  // thread 0's slot only: run alone from the next step
    bool planned = false;    // thread 0's slot only: the balance moved the split
  };
  // What a timed team knows of its speed against one thread (EngineOptions::
  // timed_team_max_disks), across runs: one thread's seconds per step in its last stretch; how
  // many windows the team runs before it tries one thread again, and how many one thread runs
  // after the team lost.
  struct TeamChoice {
    double alone_seconds = 0.0;  // 0: not timed yet
    int team_windows = 1, alone_windows = 1;
    int team_windows_won = 0;       // since the last try of one thread
    std::uint64_t in_window = 0;    // team steps of the current window
    double window_seconds = 0.0;    // and their seconds in earlier runs
    std::uint64_t alone_left = 0;   // steps one thread is still to run
    std::uint64_t phase_steps = 0;  // of the current time alone, and their seconds
    double phase_seconds = 0.0;
    std::uint64_t alone_steps = 0;  // in all
  } choice_;
  std::uint64_t advanced_ = 0;  // steps of the last team run (thread 0 sets them on a hand-over)
  std::vector<std::int32_t> part_blocks_;  // the team's split (PairArrays::part_block)
  std::uint64_t part_moves_ = 0;
  std::vector<TeamSlot> team_slots_;
  dynamic::Wakeup wakeup_;
  struct HandBack {
    Local local;
    std::uint64_t step = 0;
  } hand_back_;
  double dt_ = 0.0, time_scale_ = 0.0, time_ = 0.0;
  std::uint64_t step_ = 0;
  std::string rng_state_;
};

}  // namespace granstab
