#pragma once
// VTK snapshots of a configuration (issue #4): an XML UnstructuredGrid (.vtu, ASCII) that
// ParaView reads. One grid holds both the disks and the force network:
//   - cells 0 .. N-1 are vertices at the disk centres, with point data radius, velocity (the
//     fluctuating part as stored) and velocity_total (plus the affine part of a periodic cell),
//     spin and net_force (elastic + frictional contact forces, SPEC §2);
//   - then one line per force-carrying contact, from the centre of i to the centre of j's image
//     (periodic cells: the line may leave the cell) or to the foot on the wall, with cell data
//     f_n, f_t, sliding (0/1) and wall (0/1). Contact end points carry zero point data.
// In ParaView: Glyph (sphere / 2D glyph) scaled by radius, filtered on the cell data "kind"
// (0 disk, 1 contact), lines coloured by f_n.
#include <filesystem>
#include <string>

#include "common/configuration.hpp"

namespace granstab {

std::string format_vtu(const Configuration& config);
// Atomic (temporary file + rename).
void write_vtu(const Configuration& config, const std::filesystem::path& path);

}  // namespace granstab
