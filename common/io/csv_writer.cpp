#include "csv_writer.hpp"

#include <charconv>
#include <cmath>
#include <stdexcept>

#include "common/atomic_file.hpp"

namespace granstab {

std::string csv_number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

CsvWriter::CsvWriter(std::filesystem::path path, std::vector<std::string> columns,
                     double flush_interval_seconds)
    : path_(std::move(path)),
      columns_(std::move(columns)),
      flush_interval_(flush_interval_seconds),
      last_flush_(std::chrono::steady_clock::now()) {
  if (columns_.empty()) throw std::invalid_argument("csv " + path_.string() + ": no columns");
  for (std::size_t c = 0; c < columns_.size(); ++c) {
    if (c) text_ += ',';
    text_ += columns_[c];
  }
  text_ += '\n';
}

void CsvWriter::row(std::span<const double> values) {
  if (values.size() != columns_.size()) {
    throw std::invalid_argument("csv " + path_.string() + ": row of " +
                                std::to_string(values.size()) + " values for " +
                                std::to_string(columns_.size()) + " columns");
  }
  for (std::size_t c = 0; c < values.size(); ++c) {
    if (c) text_ += ',';
    text_ += csv_number(values[c]);
  }
  text_ += '\n';
  ++rows_;
  if (flush_interval_ > 0.0 &&
      std::chrono::duration<double>(std::chrono::steady_clock::now() - last_flush_).count() >=
          flush_interval_) {
    flush();
  }
}

void CsvWriter::flush() {
  write_file_atomically(path_, text_);
  last_flush_ = std::chrono::steady_clock::now();
}

}  // namespace granstab
