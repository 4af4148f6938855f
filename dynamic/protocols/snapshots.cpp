#include "snapshots.hpp"

#include <cstdio>
#include <limits>

#include "common/io/vtk_file.hpp"

namespace granstab::protocols {

SnapshotSettings read_snapshot_settings(RunConfig& rc) {
  SnapshotSettings s;
  s.prefix = rc.path("output.vtk");
  s.interval = static_cast<std::uint64_t>(
      rc.integer("output.vtk_interval", 0, 0, std::numeric_limits<std::int64_t>::max()));
  return s;
}

void SnapshotWriter::maybe_write(const Configuration& state, std::uint64_t step) {
  if (!settings_.prefix || settings_.interval == 0) return;
  if (next_ && step < *next_) return;
  next_ = step + settings_.interval;
  char name[32];
  std::snprintf(name, sizeof name, "_%012llu.vtu", static_cast<unsigned long long>(step));
  write_vtu(state, settings_.prefix->string() + name);
  ++written_;
}

void SnapshotWriter::write_final(const Configuration& state) {
  if (!settings_.prefix) return;
  write_vtu(state, settings_.prefix->string() + "_final.vtu");
  ++written_;
}

}  // namespace granstab::protocols
