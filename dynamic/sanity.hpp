#pragma once
// Physical sanity guards (issue #8 item 4): one place that decides whether a running state has
// blown up (a non-finite number, an overlap no healthy packing has, a kinetic energy that only a
// numerical instability produces), so that a protocol stops with a message naming what, where and
// when instead of writing garbage. Called by the protocol loops every few hundred steps
// (dynamic/protocols/run_guard.hpp), never from the engine's inner loop.
#include <cstdint>
#include <optional>
#include <string>

#include "common/configuration.hpp"
#include "common/sanity_limits.hpp"
#include "engine.hpp"

namespace granstab::dynamic {

// The limits are shared with the static start-state validation (common/sanity_limits.hpp).
using SanityLimits = granstab::SanityLimits;

// The first blow-up found in the engine's current state, as a message naming the quantity, the
// disk (or contact, or cell axis), the step and the value; nullopt when the state is sane.
// `exported` must be the engine's state exported at this step (it supplies contacts, masses and
// inertias). Checks, in this order: cell lengths and rates finite; each disk's position, velocity,
// spin, net force and torque finite; overlaps; kinetic energies.
std::optional<std::string> find_blow_up(const Engine& engine, const Configuration& exported,
                                        const SanityLimits& limits);

// The two quantities the limits bound, over a whole state (for measuring the margin of healthy
// runs): the largest overlap / smaller radius and the largest kinetic energy / (K_N r^2 / 2).
struct SanityMargins {
  double overlap_fraction = 0.0;
  double kinetic_energy = 0.0;
};
SanityMargins sanity_margins(const Configuration& state);

}  // namespace granstab::dynamic
