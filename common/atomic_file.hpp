#pragma once
// Every granstab output is written to a temporary file in the destination's directory and then
// renamed over the destination, so a crash or a full disk never leaves a half-written file that a
// later run could mistake for a result.
#include <filesystem>
#include <string_view>

namespace granstab {

// Writes contents to path atomically (temporary file + fsync + rename). Throws std::runtime_error
// naming the path on any failure; the temporary file is removed and path is left untouched.
void write_file_atomically(const std::filesystem::path& path, std::string_view contents);

}  // namespace granstab
