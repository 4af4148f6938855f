#pragma once
// Isotropic compaction under the pressure P (SPEC §3.2), from a gas to equilibrium (§3.1).
#include <cstdint>

#include "equilibration.hpp"

namespace granstab::protocols {

struct CompactionOptions {
  double pressure = 1.0;
  // 0: stress control at P from the gas on (the literal recipe of SPEC §3.2). > 0: first an
  // isotropic compression at this prescribed strain rate d epsilon / dt (units sqrt(P/m), both
  // axes, strains relative to the gas) until the mean stress reaches P, then stress control at
  // P. This avoids the free fall of the cell onto the jammed packing (docs/protocols.md).
  double strain_rate = 0.0;
  // The inertia of each cell length (or mobile wall) during the compaction, as a multiple of the
  // engine's cell mass on entry (the default sum m_i / pi^2 for a gas from random_gas). The mass
  // on entry is restored before the state is exported, so a later stage keeps the default.
  // SPEC §1.3: quasistatic results must not depend on it (docs/validation.md measures it).
  double cell_mass_factor = 1.0;
  std::uint64_t max_strain_rate_steps = 100'000'000;
  EquilibrationOptions equilibration;
};

struct CompactionResult {
  bool reached = false;
  std::uint64_t strain_rate_steps = 0;  // phase 1 (0 when strain_rate = 0)
  std::uint64_t stress_steps = 0;       // phase 2, to equilibrium
  EquilibriumReport report;
};

// Drives `engine` (whatever its stage) through the compaction; `state` receives the final
// configuration, whose stage is isotropic stress control at P with the final lengths as the
// reference lengths L_a0 (the start of any later biaxial stage).
//
// Safe points (control.hooks, docs/reliability.md): cursor.phase 0 after every strain-rate step
// (steps = strain-rate steps so far), phase 1 after every check of the wait for equilibrium
// (done_steps = strain-rate steps, steps = steps of the wait). control.resume continues there.
// With cell_mass_factor != 1, cursor.values holds the two cell masses on entry.
CompactionResult compact_isotropically(Engine& engine, const CompactionOptions& options,
                                       Configuration& state,
                                       const EquilibrationObserver& observer = {},
                                       const LoopControl& control = {});

}  // namespace granstab::protocols
