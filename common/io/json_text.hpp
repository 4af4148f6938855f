#pragma once
// The two JSON scalars every summary writer needs (info, q1, compare, the protocols' summaries).
#include <string>
#include <string_view>

namespace granstab {

// Shortest round-trip form; JSON has no inf or nan, so those become null.
std::string json_number(double v);
// Quoted, with '"' and '\' escaped and control characters as \u00XX.
std::string json_string(std::string_view s);

}  // namespace granstab
