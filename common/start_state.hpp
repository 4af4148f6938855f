#pragma once
// Validation of a static run's start (issue #19): the static solver linearises about the state it
// is given, so a state with a broken geometry or out of equilibrium gives a curve that means
// nothing. Checked before any static work by q1, compare and probe, and reported by info.
#include <string>
#include <vector>

#include "configuration.hpp"
#include "equilibrium.hpp"
#include "sanity_limits.hpp"

namespace granstab {

struct StartStateReport {
  // Broken geometry, one message per finding naming the contact or disks: overlaps beyond
  // SanityLimits::max_overlap_fraction of the smaller radius, overlapping disk pairs missing from
  // the contact list, listed disk pairs whose gap exceeds that same fraction of the smaller radius.
  std::vector<std::string> geometry;
  EquilibriumReport equilibrium;  // SPEC §3.1 at the sample's stage

  bool geometry_ok() const { return geometry.empty(); }
};

StartStateReport check_start_state(const Configuration& config,
                                   const EquilibriumTolerances& tolerances = {},
                                   const SanityLimits& limits = {});

// One line per failed SPEC §3.1 test, naming the disk with the largest force or torque.
std::vector<std::string> equilibrium_failures(const EquilibriumReport& report,
                                              const EquilibriumTolerances& tolerances = {});

// Throws std::invalid_argument prefixed with `source` (the sample's path) on broken geometry, and
// on a start out of equilibrium unless allow_unbalanced (--polish: the static solver's polish then
// moves it to equilibrium and reports how far).
void validate_start_state(const Configuration& config, const std::string& source,
                          bool allow_unbalanced);

}  // namespace granstab
