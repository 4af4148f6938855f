#pragma once
// Periodic VTK snapshots of a running protocol ([output] vtk = "PREFIX", vtk_interval = steps):
// PREFIX_<step>.vtu at checks at least vtk_interval steps apart, and PREFIX_final.vtu.
#include <cstdint>
#include <filesystem>
#include <optional>

#include "common/configuration.hpp"
#include "common/run_config.hpp"

namespace granstab::protocols {

struct SnapshotSettings {
  std::optional<std::filesystem::path> prefix;  // none: no snapshots
  std::uint64_t interval = 0;                   // steps; 0: only the final state
};

SnapshotSettings read_snapshot_settings(RunConfig& rc);

class SnapshotWriter {
 public:
  explicit SnapshotWriter(SnapshotSettings settings) : settings_(std::move(settings)) {}
  void maybe_write(const Configuration& state, std::uint64_t step);
  void write_final(const Configuration& state);
  std::size_t written() const { return written_; }
  // For checkpoints: the step before which no periodic snapshot is due (none: the next check).
  std::optional<std::uint64_t> next_step() const { return next_; }
  void restore(std::optional<std::uint64_t> next_step, std::size_t written) {
    next_ = next_step;
    written_ = written;
  }

 private:
  SnapshotSettings settings_;
  std::optional<std::uint64_t> next_;
  std::size_t written_ = 0;
};

}  // namespace granstab::protocols
