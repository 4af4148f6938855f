#pragma once
#include "common/io/json_text.hpp"
// The JSON summary every protocol writes beside its CSV (issue #4): an ordered object of
// numbers (shortest round-trip decimals; non-finite -> null), strings, booleans, arrays and
// nested objects, written atomically.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "common/equilibrium.hpp"
#include "common/measurements.hpp"

namespace granstab::protocols {

class JsonObject {
 public:
  JsonObject& add(std::string_view key, double value);
  JsonObject& add(std::string_view key, std::int64_t value);
  JsonObject& add(std::string_view key, std::uint64_t value);
  JsonObject& add(std::string_view key, int value) { return add(key, std::int64_t{value}); }
  JsonObject& add(std::string_view key, bool value);
  JsonObject& add(std::string_view key, std::string_view value);
  JsonObject& add(std::string_view key, const char* value) {
    return add(key, std::string_view(value));
  }
  JsonObject& add(std::string_view key, const std::vector<double>& values);
  JsonObject& add(std::string_view key, const JsonObject& object);
  JsonObject& add(std::string_view key, const std::vector<JsonObject>& objects);

  std::string text(int indent = 0) const;

 private:
  std::vector<std::pair<std::string, std::string>> members_;  // key, encoded value
};

using granstab::json_number;
using granstab::json_string;

// SPEC §2 quantities of a state, and the §3.1 residuals with their tolerances.
JsonObject measurements_json(const Measurements& m);
JsonObject equilibrium_json(const EquilibriumReport& r, const EquilibriumTolerances& tolerances);

// Writes object.text() atomically.
void write_json(const std::filesystem::path& path, const JsonObject& object);

}  // namespace granstab::protocols
