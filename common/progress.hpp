#pragma once
// Progress of a long run on stderr with an ETA (issue #4). One line every `interval` seconds
// (lines, not carriage returns, so a log file stays readable); disabled by --quiet.
#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace granstab {

class Progress {
 public:
  // total: the amount of work the run expects (steps, strain, q, ...); total <= 0 means
  // unknown (no percentage, no ETA).
  Progress(std::string label, double total, bool enabled, double interval_seconds = 2.0);

  // Reports `done` units of work; prints only when the interval has elapsed. `detail` is
  // appended to the line (a residual, the current q, ...).
  void update(double done, std::string_view detail = {});
  // For runs with no known end: `done` units so far and an estimate of the seconds left (none:
  // no estimate yet), printed as "ETA ~X (estimate: BASIS)"; an empty basis (no end known to
  // estimate towards) prints "ETA ?" alone.
  void update_estimated(double done, std::optional<double> seconds_left, std::string_view basis,
                        std::string_view detail = {});
  // Prints the final line (elapsed wall time) if enabled.
  void finish(std::string_view detail = {});

  double elapsed_seconds() const;
  bool enabled() const { return enabled_; }

  // "45.2% (900 / 2000)  elapsed 12 s  ETA 15 s" (public for tests).
  static std::string format(std::string_view label, double done, double total, double elapsed,
                            std::string_view detail);
  // "12000  elapsed 3 s  ETA ~8 s (estimate: residual decay)" (public for tests).
  static std::string format_estimated(std::string_view label, double done, double elapsed,
                                      std::optional<double> seconds_left, std::string_view basis,
                                      std::string_view detail);

 private:
  using Clock = std::chrono::steady_clock;
  std::string label_;
  double total_;
  bool enabled_;
  double interval_;
  Clock::time_point start_, last_;
};

// An observer of every progress update of this thread, printed or not (--quiet): the Python
// module's progress callback. Called with the label, the work done, the expected total (<= 0:
// unknown) and the detail text; it may throw to stop the run (Ctrl-C in Python).
using ProgressObserver =
    std::function<void(std::string_view label, double done, double total, std::string_view detail)>;
// Installs `observer` for this thread until the returned guard is destroyed.
class ScopedProgressObserver {
 public:
  explicit ScopedProgressObserver(ProgressObserver observer);
  ~ScopedProgressObserver();
  ScopedProgressObserver(const ScopedProgressObserver&) = delete;
  ScopedProgressObserver& operator=(const ScopedProgressObserver&) = delete;

 private:
  ProgressObserver previous_;
};
bool has_progress_observer();

// How long until a residual that decays roughly exponentially (a run to equilibrium) falls to
// its tolerance. Fed with ratio = residual / tolerance at each check, it fits log(ratio) against
// the step over the later half of the checks so far (the early transient says little about the
// end) and extrapolates the fitted line to ratio = 1. Only an estimate: the residual of a
// granular packing is noisy and its decay rate changes (docs/protocols.md).
class DecayEstimate {
 public:
  void add(double step, double ratio);
  // Steps left until the fitted ratio reaches 1; nullopt with fewer than 4 checks or when the
  // fitted residual is not decreasing.
  std::optional<double> steps_left() const;

 private:
  std::vector<double> step_, log_ratio_;
};

// "12 s", "3 min 05 s", "2 h 03 min".
std::string format_duration(double seconds);

}  // namespace granstab
