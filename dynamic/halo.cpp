#include "halo.hpp"

#include <algorithm>
#include <array>

namespace granstab::dynamic {

namespace {
// The arrays a pass reads of a pair's partner (the ghosts' arrays).
std::array<LineVector<double>*, 8> ghosted_arrays(DiskArrays& d) {
  return {&d.x, &d.y, &d.radius, &d.vx, &d.vy, &d.omega, &d.vpx, &d.vpy};
}
}  // namespace

void plan_halo(DiskArrays& disks, PairArrays& pairs,
               const std::vector<std::int32_t>& part_of_block) {
  const std::size_t n = disks.size(), m = pairs.size();
  const int team = pairs.team;
  const auto part_of = [&](int disk) { return part_of_block[disk / block_size]; };
  Halo& h = pairs.halo;
  MirrorPairs& mirrors = pairs.mirrors;
  // Part k's ghosts: the j of its crossing pairs and the i of its mirrors, ascending, unique.
  std::vector<std::vector<std::int32_t>> wanted(team);
  for (std::size_t p = 0; p < m; ++p) {
    if (pairs.crossing[p]) wanted[part_of(pairs.i[p])].push_back(pairs.j[p]);
  }
  for (int part = 0; part < team; ++part) {
    for (int q = mirrors.part_start[part]; q < mirrors.part_start[part + 1]; ++q)
      wanted[part].push_back(mirrors.i[q]);
  }
  h.ghost_start.assign(team + 1, 0);
  std::size_t wanted_count = 0;
  for (const auto& w : wanted) wanted_count += w.size();
  keep_room(h.ghost_disk, wanted_count);  // at least the ghosts
  h.ghost_disk.clear();
  for (int part = 0; part < team; ++part) {
    auto& w = wanted[part];
    std::sort(w.begin(), w.end());
    w.erase(std::unique(w.begin(), w.end()), w.end());
    h.ghost_disk.insert(h.ghost_disk.end(), w.begin(), w.end());
    h.ghost_start[part + 1] = static_cast<std::int32_t>(h.ghost_disk.size());
  }
  const auto slot = [&](int part, int disk) {
    const auto first = h.ghost_disk.begin() + h.ghost_start[part];
    const auto last = h.ghost_disk.begin() + h.ghost_start[part + 1];
    return static_cast<std::int32_t>(n +
                                     (std::lower_bound(first, last, disk) - h.ghost_disk.begin()));
  };
  keep_room(pairs.j_slot, m);
  pairs.j_slot.assign(pairs.j.begin(), pairs.j.end());
  for (std::size_t p = 0; p < m; ++p) {
    if (pairs.crossing[p]) pairs.j_slot[p] = slot(part_of(pairs.i[p]), pairs.j[p]);
  }
  for (int part = 0; part < team; ++part) {
    for (int q = mirrors.part_start[part]; q < mirrors.part_start[part + 1]; ++q)
      mirrors.i[q] = slot(part, mirrors.i[q]);
  }
  // The ghosts by owner, ascending within each.
  const std::size_t ghosts = h.size();
  h.sent_start.assign(team + 1, 0);
  for (std::size_t g = 0; g < ghosts; ++g) ++h.sent_start[part_of(h.ghost_disk[g]) + 1];
  for (int part = 0; part < team; ++part) h.sent_start[part + 1] += h.sent_start[part];
  resize_in_room(ghosts, h.sent);
  std::vector<std::int32_t> next(h.sent_start.begin(), h.sent_start.end() - 1);
  for (std::size_t g = 0; g < ghosts; ++g)
    h.sent[next[part_of(h.ghost_disk[g])]++] = static_cast<std::int32_t>(g);
  resize_in_room(Halo::stride * ghosts, h.buffer);
  resize_in_room(2 * ghosts, h.final_buffer);
  for (auto* v : ghosted_arrays(disks)) resize_in_room(n + ghosts, *v);
  fill_ghosts(disks, h);
}

void fill_ghosts(DiskArrays& disks, const Halo& halo) {
  const std::size_t n = disks.size();
  for (auto* v : ghosted_arrays(disks)) {
    double* a = v->data();
    for (std::size_t g = 0; g < halo.size(); ++g) a[n + g] = a[halo.ghost_disk[g]];
  }
}

void pack_mid_step(const DiskArrays& d, Halo& h, int part) {
  double* const out = h.buffer.data();
  for (int k = h.sent_start[part]; k < h.sent_start[part + 1]; ++k) {
    const int g = h.sent[k], i = h.ghost_disk[g];
    double* const o = out + Halo::stride * g;
    o[0] = d.x[i];
    o[1] = d.y[i];
    o[2] = d.vx[i];
    o[3] = d.vy[i];
    o[4] = d.omega[i];
    o[5] = d.vpx[i];
    o[6] = d.vpy[i];
  }
}

void unpack_mid_step(DiskArrays& d, const Halo& h, int part) {
  const std::size_t n = d.size();
  const double* const in = h.buffer.data();
  for (int g = h.ghost_start[part]; g < h.ghost_start[part + 1]; ++g) {
    const double* const o = in + Halo::stride * g;
    const std::size_t s = n + g;
    d.x[s] = o[0];
    d.y[s] = o[1];
    d.vx[s] = o[2];
    d.vy[s] = o[3];
    d.omega[s] = o[4];
    d.vpx[s] = o[5];
    d.vpy[s] = o[6];
  }
}

void pack_final(const DiskArrays& d, Halo& h, int part) {
  double* const out = h.final_buffer.data();
  for (int k = h.sent_start[part]; k < h.sent_start[part + 1]; ++k) {
    const int g = h.sent[k], i = h.ghost_disk[g];
    out[2 * g] = d.vx[i];
    out[2 * g + 1] = d.vy[i];
  }
}

void unpack_final(DiskArrays& d, const Halo& h, int part) {
  const std::size_t n = d.size();
  const double* const in = h.final_buffer.data();
  for (int g = h.ghost_start[part]; g < h.ghost_start[part + 1]; ++g) {
    d.vx[n + g] = in[2 * g];
    d.vy[n + g] = in[2 * g + 1];
  }
}

}  // namespace granstab::dynamic
