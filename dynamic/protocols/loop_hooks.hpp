#pragma once
// How a protocol loop lets its command checkpoint it, guard it and continue it (issue #8,
// docs/reliability.md). A safe point is a place in a loop where the engine's state plus a Cursor
// is everything the loop needs to go on: a resumed loop given that cursor continues to the bit.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "common/equilibrium.hpp"
#include "dynamic/engine.hpp"

namespace granstab::protocols {

// Where a protocol loop stands at a safe point. Each protocol documents what its fields mean.
struct Cursor {
  int phase = 0;                 // part of the run (compaction: 0 strain rate, 1 stress, ...)
  std::int64_t index = 0;        // SIC: increment k; perturbation: draw
  std::uint64_t steps = 0;       // steps into the current wait (or strain-rate phase)
  std::uint64_t done_steps = 0;  // steps of the protocol before the current wait
  double next_record = 0.0;      // SRC: strain of the next recorded state
  std::vector<double> values;    // protocol-specific numbers (creep: strains at the switch, ...)
  std::string rng_state;         // perturbation: generator state before the current draw
  EquilibriumReport report;      // perturbation: of the loaded wait, during the released one
};

struct LoopHooks {
  // Before a state is recorded or shown to an observer: throws when the state has blown up.
  std::function<void(const Engine&)> check;
  // At every safe point, with the cursor to continue from there.
  std::function<void(const Engine&, const Cursor&)> safe_point;
};

// What a protocol function gets besides its physics settings. Default: no hooks, a fresh start.
struct LoopControl {
  LoopHooks hooks;
  // The cursor the loop reports at its safe points: the caller sets what it owns (phase,
  // done_steps, values...), the loop updates its own fields (steps, index, next_record...).
  Cursor cursor;
  bool resume = false;  // continue from `cursor` (the engine holds its state) instead of starting

  void check(const Engine& e) const {
    if (hooks.check) hooks.check(e);
  }
  void safe_point(const Engine& e, const Cursor& c) const {
    if (hooks.safe_point) hooks.safe_point(e, c);
  }
};

}  // namespace granstab::protocols
