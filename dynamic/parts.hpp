#pragma once
// The team's parts: part k holds the blocks [part_block[k], part_block[k + 1]) (blocks of
// block_size disks), whatever the pass, so that each thread keeps its disks' data in its core's
// cache. No sum depends on the split (docs/dynamic.md, "Determinism").
#include <array>
#include <cstdint>
#include <vector>

#include "state.hpp"

namespace granstab::dynamic {

std::vector<std::int32_t> even_parts(std::size_t n, int team);  // nb k / team
// Whether part_block splits the blocks of n disks into `team` non-empty parts.
bool valid_parts(const std::vector<std::int32_t>& part_block, std::size_t n, int team);
// The split after a measurement of busy[k] seconds of work (waits excluded) on part k: unchanged
// when the slowest part took at most (1 + tolerance) times the mean; otherwise every boundary
// moves half way towards the split at which the measured speeds (blocks per second) would
// finish together, each part keeping at least one block.
std::vector<std::int32_t> balanced_parts(const std::vector<std::int32_t>& part_block,
                                         const std::vector<double>& busy, double tolerance);
// The split's crossing pairs (j in a later part than i) and their mirrors in j's part, with a
// copy of the pairs' state (PairArrays::mirrors), and the halo (PairArrays::halo, its ghosts
// filled): after every list rebuild, for a new team size and when the split moves. part_block
// may be pairs.part_block itself (a replan of the split).
void plan_parts(DiskArrays& disks, PairArrays& pairs, const std::vector<std::int32_t>& part_block);
std::array<int, 2> part_disks(const PairArrays& pairs, std::size_t n, int part);  // [first, end)

}  // namespace granstab::dynamic
