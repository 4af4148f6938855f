#pragma once
// Run settings of the subcommands: a TOML file (toml++, kept out of this header) with command-line
// overrides "key=value" on top. Every getter states the default and the allowed values, marks the
// key as used, and throws std::invalid_argument "SOURCE: key = value: what is wrong"; finish()
// then rejects every key that no getter asked for, so a misspelt key never passes silently.
//
// In a driver: cmd->add_option("--set", overrides, "override a setting, key=value");
//   RunConfig rc = RunConfig::from_file(settings_file, overrides);
//   const double gamma = rc.number("biaxial.gamma", 1e-4, 0.0, 1.0);  ... rc.finish();
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace granstab {

class RunConfig {
 public:
  // Reads a TOML file; a parse error throws std::runtime_error "FILE:LINE:COLUMN: message".
  // Overrides are "dotted.key=value" with the value in TOML syntax (0.3, true, "text", [1, 2]);
  // a value that is not TOML is taken as a bare string (--set run.mode=SRC).
  static RunConfig from_file(const std::filesystem::path& file,
                             const std::vector<std::string>& overrides = {});
  // The same on text; source_name stands for the file in messages, base_dir resolves paths.
  static RunConfig from_string(std::string_view toml, const std::string& source_name,
                               const std::vector<std::string>& overrides = {},
                               const std::filesystem::path& base_dir = {});

  RunConfig(RunConfig&&) noexcept;
  RunConfig& operator=(RunConfig&&) noexcept;
  ~RunConfig();

  // A number (TOML float or integer) in [min, max]; finite.
  double number(std::string_view key, double fallback, double min, double max);
  // A TOML integer in [min, max].
  std::int64_t integer(std::string_view key, std::int64_t fallback, std::int64_t min,
                       std::int64_t max);
  bool boolean(std::string_view key, bool fallback);
  std::string string(std::string_view key, const std::string& fallback);
  // A string that must be one of allowed.
  std::string choice(std::string_view key, const std::string& fallback,
                     const std::vector<std::string>& allowed);
  // A path string; relative paths from the file are taken relative to the file's directory,
  // those given on the command line relative to the working directory. Absent: nullopt.
  std::optional<std::filesystem::path> path(std::string_view key);

  bool contains(std::string_view key) const;
  const std::string& source_name() const;

  // Throws std::invalid_argument naming every key present (in the file or an override) that no
  // getter has read.
  void finish() const;

 private:
  struct Impl;
  explicit RunConfig(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace granstab
