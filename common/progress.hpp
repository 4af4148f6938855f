#pragma once
// Progress of a long run on stderr with an ETA (issue #4). One line every `interval` seconds
// (lines, not carriage returns, so a log file stays readable); disabled by --quiet.
#include <chrono>
#include <string>
#include <string_view>

namespace granstab {

class Progress {
 public:
  // total: the amount of work the run expects (steps, strain, q, ...); total <= 0 means
  // unknown (no percentage, no ETA).
  Progress(std::string label, double total, bool enabled, double interval_seconds = 2.0);

  // Reports `done` units of work; prints only when the interval has elapsed. `detail` is
  // appended to the line (a residual, the current q, ...).
  void update(double done, std::string_view detail = {});
  // Prints the final line (elapsed wall time) if enabled.
  void finish(std::string_view detail = {});

  double elapsed_seconds() const;
  bool enabled() const { return enabled_; }

  // "45.2% (900 / 2000)  elapsed 12 s  ETA 15 s" (public for tests).
  static std::string format(std::string_view label, double done, double total, double elapsed,
                            std::string_view detail);

 private:
  using Clock = std::chrono::steady_clock;
  std::string label_;
  double total_;
  bool enabled_;
  double interval_;
  Clock::time_point start_, last_;
};

// "12 s", "3 min 05 s", "2 h 03 min".
std::string format_duration(double seconds);

}  // namespace granstab
