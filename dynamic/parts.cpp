#include "parts.hpp"

#include <algorithm>
#include <cmath>

#include "halo.hpp"

namespace granstab::dynamic {

std::vector<std::int32_t> even_parts(std::size_t n, int team) {
  const long long nb = block_count(n);
  std::vector<std::int32_t> part_block(team + 1);
  for (int k = 0; k <= team; ++k) part_block[k] = static_cast<std::int32_t>(nb * k / team);
  return part_block;
}

bool valid_parts(const std::vector<std::int32_t>& part_block, std::size_t n, int team) {
  if (static_cast<int>(part_block.size()) != team + 1 || part_block.front() != 0 ||
      part_block.back() != block_count(n)) {
    return false;
  }
  for (int k = 0; k < team; ++k)
    if (part_block[k + 1] <= part_block[k]) return false;
  return true;
}

std::vector<std::int32_t> balanced_parts(const std::vector<std::int32_t>& part_block,
                                         const std::vector<double>& busy, double tolerance) {
  const int team = static_cast<int>(part_block.size()) - 1;
  if (team < 2 || static_cast<int>(busy.size()) != team) return part_block;
  double mean = 0.0, worst = 0.0, speed_sum = 0.0;
  std::vector<double> speed(team);
  for (int k = 0; k < team; ++k) {
    if (!(busy[k] > 0.0)) return part_block;
    mean += busy[k] / team;
    worst = std::max(worst, busy[k]);
    speed[k] = (part_block[k + 1] - part_block[k]) / busy[k];
    speed_sum += speed[k];
  }
  if (worst <= (1.0 + tolerance) * mean) return part_block;
  // Each part moves half way towards the size its thread's speed would finish with the others.
  const double blocks = part_block.back();
  std::vector<std::int32_t> out = part_block;
  double target_start = 0.0;
  for (int k = 1; k < team; ++k) {
    target_start += blocks * speed[k - 1] / speed_sum;
    const double moved = part_block[k] + 0.5 * (target_start - part_block[k]);
    out[k] = static_cast<std::int32_t>(std::lround(moved));
  }
  for (int k = 1; k < team; ++k)  // at least one block per part
    out[k] = std::clamp(out[k], out[k - 1] + 1, part_block.back() - (team - k));
  return out;
}

// Which pairs cross a split into parts (part_block): those whose j lies in a later part than
// their i. Each gets a mirror in j's part (PairArrays::mirrors, ascending pair within a part),
// with a copy of its state: the same bits, both being the synchronous state's. Then the halo.
void plan_parts(DiskArrays& disks, PairArrays& pairs, const std::vector<std::int32_t>& part_block) {
  const std::size_t n = disks.size();
  const int nb = block_count(n);
  const int team = static_cast<int>(part_block.size()) - 1;
  std::vector<std::int32_t> part_of_block(nb);
  for (int part = 0; part < team; ++part) {
    for (int b = part_block[part]; b < part_block[part + 1]; ++b) part_of_block[b] = part;
  }
  const auto part_of = [&](int disk) { return part_of_block[disk / block_size]; };
  const std::size_t m = pairs.size();
  pairs.part_block = part_block;
  keep_room(pairs.crossing, m);
  pairs.crossing.assign(m, 0);
  pairs.block_crossing.assign(nb, 0);
  MirrorPairs& mirrors = pairs.mirrors;
  auto& start = mirrors.part_start;
  start.assign(team + 1, 0);
  for (std::size_t p = 0; p < m; ++p) {
    if (part_of(pairs.i[p]) == part_of(pairs.j[p])) continue;
    pairs.crossing[p] = 1;
    pairs.block_crossing[pairs.i[p] / block_size] = 1;
    ++start[part_of(pairs.j[p]) + 1];
  }
  for (int part = 0; part < team; ++part) start[part + 1] += start[part];
  const std::size_t count = static_cast<std::size_t>(start[team]);
  std::vector<std::int32_t> source(count);  // the listed pair of each mirror
  std::vector<std::int32_t> next(start.begin(), start.end() - 1);
  for (std::size_t p = 0; p < m; ++p) {
    if (pairs.crossing[p]) source[next[part_of(pairs.j[p])]++] = static_cast<std::int32_t>(p);
  }
  const auto copy = [&](auto& to, const auto& from) {
    resize_in_room(count, to);
    for (std::size_t k = 0; k < count; ++k) to[k] = from[source[k]];
  };
  copy(mirrors.i, pairs.i);
  copy(mirrors.j, pairs.j);
  copy(mirrors.alpha, pairs.alpha);
  copy(mirrors.delta_t, pairs.delta_t);
  copy(mirrors.viscous_x, pairs.viscous_x);
  copy(mirrors.viscous_y, pairs.viscous_y);
  copy(mirrors.nx, pairs.nx);
  copy(mirrors.ny, pairs.ny);
  copy(mirrors.lx, pairs.lx);
  copy(mirrors.ly, pairs.ly);
  copy(mirrors.f_n, pairs.f_n);
  resize_in_room(count, mirrors.active);
  mirrors.part_closed.assign(team, 0);
  mirrors.part_opened.assign(team, 0);
  pairs.team = team;
  plan_halo(disks, pairs, part_of_block);
}

std::array<int, 2> part_disks(const PairArrays& pairs, std::size_t n, int part) {
  const int end = static_cast<int>(n);
  return {std::min(end, pairs.part_block[part] * block_size),
          std::min(end, pairs.part_block[part + 1] * block_size)};
}

}  // namespace granstab::dynamic
