#pragma once
// What no healthy packing has: the limits shared by the MD engine's blow-up guard
// (dynamic/sanity.hpp, during a run) and the static solver's start-state validation
// (common/start_state.hpp, before a run). One definition, so the two never disagree on what a
// broken state is.
namespace granstab {

struct SanityLimits {
  // Largest overlap h of a contact as a fraction of the smaller radius of the two disks (the
  // radius of the disk for a wall contact). Healthy runs at P = 1: h / r ~ 1 / kappa per unit of
  // contact force, ~1e-3 at kappa = 1e3, ~0.1 in the compaction overshoot of a kappa = 1e3 sample.
  double max_overlap_fraction = 0.5;
  // Largest kinetic energy of one disk (fluctuating translation + rotation) in units of
  // K_N r_i^2 / 2, the elastic energy of an overlap of its whole radius: a disk with that much
  // energy can push through its neighbours. Healthy runs stay below ~1e-3 (docs/reliability.md).
  double max_kinetic_energy = 1.0;
};

}  // namespace granstab
