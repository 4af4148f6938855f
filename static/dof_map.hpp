#pragma once
// Degrees of freedom q = (u_i, theta_i of the active disks, e1, e2) of STATIC.md §S1, with the
// global translation of a periodic cell pinned by removing one backbone disk's u (§S3.0 step 3;
// never a diagonal shift).
#include <array>
#include <vector>

namespace granstab::statics {

struct DofMap {
  // Index of each disk's dofs in q, or -1 when the disk (or that component) is not a dof.
  std::vector<int> ux, uy, theta;
  std::array<int, 2> e{-1, -1};  // cell extensions e1, e2
  int size = 0;

  // Per disk (or empty): removed as a rattler by the preparation (§S3.0), as opposed to a disk
  // held fixed. A rattler has no force balance, so its contacts carry no force.
  std::vector<char> rattler;

  bool active(std::size_t i) const { return ux[i] >= 0 || uy[i] >= 0 || theta[i] >= 0; }
  bool is_rattler(std::size_t i) const { return i < rattler.size() && rattler[i]; }
};

struct DofOptions {
  std::vector<char> active;              // per disk: carries dofs (not a rattler)
  int pinned_translation = -1;           // disk whose u is removed, or -1
  std::vector<char> rotation_fixed;      // per disk (or empty): theta is not a dof
  std::array<bool, 2> cell{true, true};  // e_a is a dof (stress-controlled direction)
};

DofMap build_dof_map(const DofOptions& options);

}  // namespace granstab::statics
