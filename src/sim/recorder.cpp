#include "lathectl/sim/recorder.hpp"

#include <stdexcept>

namespace lathectl::sim {

Recorder::Recorder(std::vector<Channel> channels, std::size_t capacity_rows)
    : channels_(std::move(channels)), capacity_(capacity_rows) {
  data_.resize(channels_.size());
  for (auto& d : data_) d.resize(capacity_rows);
}

void Recorder::push_row(std::span<const double> values) noexcept {
  if (rows_ >= capacity_) {
    ++dropped_;
    return;
  }
  const std::size_t n = std::min(values.size(), data_.size());
  for (std::size_t i = 0; i < n; ++i) data_[i][rows_] = values[i];
  ++rows_;
}

std::size_t Recorder::index(const std::string& name) const {
  for (std::size_t i = 0; i < channels_.size(); ++i)
    if (channels_[i].name == name) return i;
  throw std::out_of_range("no recorded channel '" + name + "'");
}

std::span<const double> Recorder::column(const std::string& name) const {
  return column(index(name));
}

std::span<const double> Recorder::column(std::size_t i) const noexcept {
  return {data_[i].data(), rows_};
}

}  // namespace lathectl::sim
