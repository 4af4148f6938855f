#pragma once
// Creep test (SPEC §3.4): during an SRC test, switch to stress control holding the current q and
// wait for equilibrium; the strain change during the hold is the creep strain.
#include "biaxial.hpp"

namespace granstab::protocols {

struct CreepOptions {
  EquilibrationOptions equilibration;
  // The hold is abandoned (no equilibrium: the sample flows at this q) when epsilon_2 grows by
  // more than this during it.
  double failure_delta_epsilon_2 = 0.1;
};

struct CreepResult {
  double q_hold = 0.0;
  double epsilon_2_switch = 0.0, epsilon_v_switch = 0.0;  // at the switch to stress control
  double epsilon_2_end = 0.0, epsilon_v_end = 0.0;        // at equilibrium (or abandonment)
  double delta_epsilon_2() const { return epsilon_2_end - epsilon_2_switch; }
  double delta_epsilon_v() const { return epsilon_v_end - epsilon_v_switch; }
  EquilibrationResult equilibrium;
};

// Holds sigma_1 = P and sigma_2 = P (1 + q_hold) under stress control from the engine's current
// state until equilibrium (SPEC §3.1). observer sees every check.
// Safe points: those of the wait, with control.cursor.values = {epsilon_2, epsilon_v at the
// switch}; control.resume continues the wait.
CreepResult hold_deviator(Engine& engine, double q_hold, double pressure,
                          const CreepOptions& options, Configuration& state,
                          const EquilibrationObserver& observer = {},
                          const LoopControl& control = {});

}  // namespace granstab::protocols
