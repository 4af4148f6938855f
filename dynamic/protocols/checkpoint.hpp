#pragma once
// Checkpoints of the long protocols (issue #8, docs/reliability.md): everything a run needs to
// continue to the bit after being killed. A checkpoint is an ordered list of named entries (the
// engine's Configuration, the protocol's Cursor, the command's own counters, the settings text,
// the byte size of every output written so far), written atomically as one text file:
//
//   granstab-checkpoint 1
//   NAME BYTES\n<BYTES bytes of value>\n      (one per entry, in the order they were set)
//   end FNV1A64-OF-EVERYTHING-BEFORE\n
//
// Numbers are written as the shortest decimal that reads back to the same double, so nothing is
// rounded. The trailing checksum rejects a damaged file.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "common/configuration.hpp"
#include "common/equilibrium.hpp"
#include "loop_hooks.hpp"

namespace granstab::protocols {

inline constexpr int checkpoint_format_version = 1;

class Checkpoint {
 public:
  // Setting a name twice replaces its value (and keeps its place).
  void set(std::string_view name, std::string_view value);
  void set_number(std::string_view name, double value);
  void set_count(std::string_view name, std::uint64_t value);
  void set_flag(std::string_view name, bool value);
  void set_configuration(std::string_view name, const Configuration& config);
  void set_report(std::string_view prefix, const EquilibriumReport& report);

  // Getters throw std::runtime_error "SOURCE: entry NAME: missing / not a number ...".
  bool has(std::string_view name) const;
  const std::string& text(std::string_view name) const;
  double number(std::string_view name) const;
  std::uint64_t count(std::string_view name) const;
  bool flag(std::string_view name) const;
  Configuration configuration(std::string_view name) const;
  EquilibriumReport report(std::string_view prefix) const;

  std::string format() const;
  // Throws std::runtime_error naming source_name on any damage (wrong magic, version, length,
  // checksum, missing end).
  static Checkpoint parse(std::string_view text, const std::string& source_name);
  void write(const std::filesystem::path& path) const;  // atomically
  static Checkpoint read(const std::filesystem::path& path);

  const std::string& source_name() const { return source_; }

 private:
  std::vector<std::pair<std::string, std::string>> entries_;
  std::string source_ = "checkpoint";
};

void put_cursor(Checkpoint& checkpoint, const Cursor& cursor);
Cursor get_cursor(const Checkpoint& checkpoint);

// 64-bit FNV-1a of bytes (the checksum of checkpoints and of the input files they depend on).
std::uint64_t fnv1a64(std::string_view bytes);

}  // namespace granstab::protocols
