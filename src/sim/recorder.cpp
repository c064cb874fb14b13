#include "lathectl/sim/recorder.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lathectl::sim {

Recorder::Recorder(std::vector<Channel> channels, std::size_t capacity_rows)
    : channels_(std::move(channels)), capacity_(capacity_rows) {
  data_.resize(channels_.size());
  for (auto& d : data_) d.resize(capacity_rows);
}

Recorder Recorder::streamed(std::vector<Channel> channels, std::vector<RowSink*> sinks,
                            std::size_t values_per_level) {
  Recorder r;
  r.channels_ = std::move(channels);
  r.sinks_ = std::move(sinks);
  r.plots_.reserve(values_per_level > 0 ? r.channels_.size() : 0);
  for (std::size_t i = 0; i < r.channels_.size() && values_per_level > 0; ++i) {
    PlotPyramid::Options o;
    o.max_values_per_level = values_per_level;
    r.plots_.emplace_back(o);
  }
  r.streamed_ = true;
  return r;
}

void Recorder::push_row(std::span<const double> values) noexcept {
  for (RowSink* s : sinks_) s->row(values);
  if (streamed_) {
    const double x = values.empty() ? 0.0 : values[0];
    PlotPyramid::push_row(plots_, x, values);
    ++rows_;
    return;
  }
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
  if (streamed_) return {};
  return {data_[i].data(), rows_};
}

void Recorder::replay(RowSink& sink) const {
  if (streamed_) return;
  std::vector<double> row(data_.size());
  for (std::size_t r = 0; r < rows_; ++r) {
    for (std::size_t i = 0; i < data_.size(); ++i) row[i] = data_[i][r];
    sink.row(row);
  }
}

void Recorder::plot_points(const std::string& name, std::vector<double>& x,
                           std::vector<double>& y) const {
  const std::size_t i = index(name);
  if (streamed_) {
    if (i < plots_.size()) {
      plots_[i].points(x, y);
    } else {
      x.clear();
      y.clear();
    }
    return;
  }
  const auto cx = column(std::size_t{0}), cy = column(i);
  x.assign(cx.begin(), cx.end());
  y.assign(cy.begin(), cy.end());
}

std::shared_ptr<const PlotPyramid> Recorder::plot_pyramid(const std::string& name) const {
  const std::size_t i = index(name);
  if (!streamed_ || i >= plots_.size()) return nullptr;
  return plots_[i].finished();
}

}  // namespace lathectl::sim
