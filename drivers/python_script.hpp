#pragma once
// The pictures and reports that granstab draws with matplotlib: a script of scripts/ run by
// /usr/bin/python3 (DEPS.md #6: the python3 on PATH may lack matplotlib) with the Agg backend.
#include <string>
#include <vector>

namespace granstab::cli {

// Runs `python GRANSTAB_SOURCE_DIR/script args...`; throws std::runtime_error naming the
// interpreter when it cannot run or lacks matplotlib, and the script when it fails.
void run_python_script(const std::string& python, const std::string& script,
                       const std::vector<std::string>& args);

}  // namespace granstab::cli
