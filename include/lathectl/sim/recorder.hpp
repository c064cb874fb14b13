#pragma once
// Recorder with preallocated channels: names and units declared up front, capacity reserved for
// the whole run, push_row() never allocates.

#include <span>
#include <string>
#include <vector>

namespace lathectl::sim {

struct Channel {
  std::string name;  // snake_case with unit suffix, e.g. "force_N"
  std::string unit;
};

class Recorder {
 public:
  Recorder() = default;
  Recorder(std::vector<Channel> channels, std::size_t capacity_rows);
  // Appends one row (values in channel order). Rows beyond capacity are dropped (and counted).
  void push_row(std::span<const double> values) noexcept;
  [[nodiscard]] std::size_t rows() const noexcept { return rows_; }
  [[nodiscard]] std::size_t dropped() const noexcept { return dropped_; }
  [[nodiscard]] const std::vector<Channel>& channels() const noexcept { return channels_; }
  [[nodiscard]] std::size_t index(const std::string& name) const;  // throws std::out_of_range
  // Column view of one channel (length rows()).
  [[nodiscard]] std::span<const double> column(const std::string& name) const;
  [[nodiscard]] std::span<const double> column(std::size_t i) const noexcept;

 private:
  std::vector<Channel> channels_;
  std::vector<std::vector<double>> data_;
  std::size_t capacity_ = 0;
  std::size_t rows_ = 0;
  std::size_t dropped_ = 0;
};

}  // namespace lathectl::sim
