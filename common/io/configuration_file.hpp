#pragma once
// The configuration file of issue #2 (docs/file-format.md): versioned, line-oriented text that
// carries everything in a Configuration, every double written as the shortest decimal that reads
// back to the same bits, so a run saved and reloaded continues exactly.
#include <filesystem>
#include <string>
#include <string_view>

#include "common/configuration.hpp"

namespace granstab {

inline constexpr int configuration_format_version = 1;

// Reads and validates a configuration file. Throws std::runtime_error "FILE:LINE: message" on
// any malformed or inconsistent input (and when the file cannot be opened).
Configuration read_configuration(const std::filesystem::path& path);

// Writes atomically (temporary file + rename). Throws std::invalid_argument, writing nothing, if
// the file could not be read back: a non-finite number, an rng_state that is not a
// std::mt19937_64 state, or anything read_configuration rejects (the message then names the
// would-be line).
void write_configuration(const Configuration& config, const std::filesystem::path& path);

// The same, on text; source_name stands for the file name in error messages.
Configuration parse_configuration(std::string_view text, const std::string& source_name);
std::string format_configuration(const Configuration& config);

}  // namespace granstab
