#pragma once
// A CSV time series (issue #4): a header of column names, then rows of numbers, each written as
// the shortest decimal that reads back to the same double. The rows are kept in memory and the
// whole file is written atomically (common/atomic_file.hpp) at every flush(), so a reader never
// sees a half-written row and a crash leaves the last flushed state.
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <initializer_list>
#include <span>
#include <string>
#include <vector>

namespace granstab {

class CsvWriter {
 public:
  // Nothing is written before the first flush(). flush_interval_seconds > 0: row() flushes when
  // that much wall time has passed since the last flush (long runs stay inspectable).
  CsvWriter(std::filesystem::path path, std::vector<std::string> columns,
            double flush_interval_seconds = 0.0);

  // Throws std::invalid_argument when the row does not have one value per column.
  void row(std::span<const double> values);
  void row(std::initializer_list<double> values) { row(std::span(values.begin(), values.size())); }
  void flush();

  const std::filesystem::path& path() const { return path_; }
  const std::vector<std::string>& columns() const { return columns_; }
  std::size_t rows() const { return rows_; }
  const std::string& text() const { return text_; }

 private:
  std::filesystem::path path_;
  std::vector<std::string> columns_;
  std::string text_;
  std::size_t rows_ = 0;
  double flush_interval_;
  std::chrono::steady_clock::time_point last_flush_;
};

// Shortest round-trip decimal of v; "nan", "inf", "-inf" for non-finite values.
std::string csv_number(double v);

}  // namespace granstab
