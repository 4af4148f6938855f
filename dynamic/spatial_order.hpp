#pragma once
// Renumbering disks in space-filling order. The engine streams through its pairs in index
// order and reads each partner's data: with disks numbered at random (a sample grown from a
// random gas) the partners of a disk are scattered in memory, which costs ~40% at N = 22400
// (docs/notes/2026-12-02-md-engine-measurements.md, "Disk numbering"). Numbering is arbitrary in
// the data model, so a protocol may renumber a sample once (e.g. the random gas before
// compaction) and keep that numbering.
#include <cstdint>
#include <vector>

#include "common/configuration.hpp"

namespace granstab {

// Order of the disks along rows of square cells of side ~ the largest diameter, rows swept
// alternately left-to-right and right-to-left: order[k] = old index of the disk that becomes k.
std::vector<std::int32_t> spatial_order(const Configuration& config);

// The configuration with disks renumbered as `order` says (contacts renumbered alike; a
// contact keeps its delta_t, with i and j swapped if needed so that i < j stays true for
// disk-disk contacts, which leaves delta_t unchanged, and k1, k2 negated with the swap).
Configuration renumbered(const Configuration& config, const std::vector<std::int32_t>& order);

}  // namespace granstab
