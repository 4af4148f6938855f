#include "progress.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>

namespace granstab {

std::string format_duration(double seconds) {
  char buf[64];
  if (!std::isfinite(seconds) || seconds < 0.0) return "?";
  if (seconds < 100.0) {
    std::snprintf(buf, sizeof buf, "%.0f s", seconds);
  } else if (seconds < 3600.0) {
    const int s = static_cast<int>(std::lround(seconds));
    std::snprintf(buf, sizeof buf, "%d min %02d s", s / 60, s % 60);
  } else {
    const int m = static_cast<int>(std::lround(seconds / 60.0));
    std::snprintf(buf, sizeof buf, "%d h %02d min", m / 60, m % 60);
  }
  return buf;
}

Progress::Progress(std::string label, double total, bool enabled, double interval_seconds)
    : label_(std::move(label)),
      total_(total),
      enabled_(enabled),
      interval_(interval_seconds),
      start_(Clock::now()),
      last_(start_) {}

double Progress::elapsed_seconds() const {
  return std::chrono::duration<double>(Clock::now() - start_).count();
}

std::string Progress::format(std::string_view label, double done, double total, double elapsed,
                             std::string_view detail) {
  char buf[160];
  std::string line(label);
  line += ": ";
  if (total > 0.0) {
    const double fraction = std::min(1.0, std::max(0.0, done / total));
    std::snprintf(
        buf, sizeof buf, "%5.1f%% (%.6g / %.6g)  elapsed %s  ETA %s", 100.0 * fraction, done, total,
        format_duration(elapsed).c_str(),
        // Linear extrapolation of the rate so far.
        fraction > 0.0 ? format_duration(elapsed * (1.0 - fraction) / fraction).c_str() : "?");
  } else {
    std::snprintf(buf, sizeof buf, "%.6g  elapsed %s", done, format_duration(elapsed).c_str());
  }
  line += buf;
  if (!detail.empty()) {
    line += "  ";
    line += detail;
  }
  return line;
}

std::string Progress::format_estimated(std::string_view label, double done, double elapsed,
                                       std::optional<double> seconds_left, std::string_view basis,
                                       std::string_view detail) {
  char buf[200];
  std::snprintf(buf, sizeof buf, "%.6g  elapsed %s  ETA %s%s", done,
                format_duration(elapsed).c_str(), seconds_left ? "~" : "",
                seconds_left ? format_duration(*seconds_left).c_str() : "?");
  std::string line(label);
  line += ": ";
  line += buf;
  // No basis: a run with no end to estimate towards (a static run without --q-max) says "ETA ?".
  if (!basis.empty()) {
    line += " (estimate: ";
    line += basis;
    line += ")";
  }
  if (!detail.empty()) {
    line += "  ";
    line += detail;
  }
  return line;
}

namespace {
thread_local ProgressObserver observer;
}  // namespace

ScopedProgressObserver::ScopedProgressObserver(ProgressObserver o)
    : previous_(std::move(observer)) {
  observer = std::move(o);
}
ScopedProgressObserver::~ScopedProgressObserver() { observer = std::move(previous_); }
bool has_progress_observer() { return static_cast<bool>(observer); }

void Progress::update_estimated(double done, std::optional<double> seconds_left,
                                std::string_view basis, std::string_view detail) {
  if (observer) observer(label_, done, 0.0, detail);
  if (!enabled_) return;
  const auto now = Clock::now();
  if (std::chrono::duration<double>(now - last_).count() < interval_) return;
  last_ = now;
  std::cerr << format_estimated(label_, done, elapsed_seconds(), seconds_left, basis, detail)
            << std::endl;
}

void DecayEstimate::add(double step, double ratio) {
  if (!(ratio > 0.0) || !std::isfinite(ratio)) return;
  step_.push_back(step);
  log_ratio_.push_back(std::log(ratio));
}

std::optional<double> DecayEstimate::steps_left() const {
  const std::size_t n = step_.size();
  if (n < 4) return std::nullopt;
  // Least squares over the later half of the checks.
  const std::size_t first = n / 2;
  const double m = static_cast<double>(n - first);
  double sx = 0.0, sy = 0.0;
  for (std::size_t k = first; k < n; ++k) {
    sx += step_[k];
    sy += log_ratio_[k];
  }
  const double mx = sx / m, my = sy / m;
  double sxx = 0.0, sxy = 0.0;
  for (std::size_t k = first; k < n; ++k) {
    sxx += (step_[k] - mx) * (step_[k] - mx);
    sxy += (step_[k] - mx) * (log_ratio_[k] - my);
  }
  if (!(sxx > 0.0)) return std::nullopt;
  const double slope = sxy / sxx;
  if (!(slope < 0.0)) return std::nullopt;
  const double fitted_now = my + slope * (step_.back() - mx);
  return std::max(0.0, fitted_now / -slope);
}

void Progress::update(double done, std::string_view detail) {
  if (observer) observer(label_, done, total_, detail);
  if (!enabled_) return;
  const auto now = Clock::now();
  if (std::chrono::duration<double>(now - last_).count() < interval_) return;
  last_ = now;
  std::cerr << format(label_, done, total_, elapsed_seconds(), detail) << std::endl;
}

void Progress::finish(std::string_view detail) {
  if (!enabled_) return;
  std::string line = label_ + ": done in " + format_duration(elapsed_seconds());
  if (!detail.empty()) {
    line += "  ";
    line += detail;
  }
  std::cerr << line << std::endl;
}

}  // namespace granstab
