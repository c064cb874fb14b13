#include "lathectl/sim/recorder.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lathectl::sim {

PlotDecimator::PlotDecimator(std::size_t max_buckets)
    : max_(std::max<std::size_t>(2, max_buckets + (max_buckets & 1))) {
  b_.reserve(max_);
}

void PlotDecimator::absorb(Bucket& b, const Point& p) noexcept {
  if (b.n++ == 0 || (std::isnan(b.lo.y) && !std::isnan(p.y))) {
    b.lo = b.hi = p;
    return;
  }
  if (p.y < b.lo.y) b.lo = p;
  if (p.y > b.hi.y) b.hi = p;
}

void PlotDecimator::push(double x, double y) noexcept {
  const Point p{pushed_++, x, y};
  if (b_.empty() || b_.back().n >= per_bucket_) {
    if (b_.size() == max_) {  // full: merge neighbours pairwise, each bucket takes twice the rows
      for (std::size_t k = 0; k < max_ / 2; ++k) {
        Bucket m = b_[2 * k];
        const Bucket& o = b_[2 * k + 1];
        const std::size_t n = m.n;
        absorb(m, o.lo);
        absorb(m, o.hi);
        m.n = n + o.n;
        b_[k] = m;
      }
      b_.resize(max_ / 2);
      per_bucket_ *= 2;
    }
    if (b_.empty() || b_.back().n >= per_bucket_) b_.push_back(Bucket{});
  }
  absorb(b_.back(), p);
}

void PlotDecimator::points(std::vector<double>& x, std::vector<double>& y) const {
  x.clear();
  y.clear();
  x.reserve(2 * b_.size());
  y.reserve(2 * b_.size());
  for (const auto& b : b_) {
    const Point& first = b.lo.i <= b.hi.i ? b.lo : b.hi;
    const Point& second = b.lo.i <= b.hi.i ? b.hi : b.lo;
    x.push_back(first.x);
    y.push_back(first.y);
    if (second.i != first.i) {
      x.push_back(second.x);
      y.push_back(second.y);
    }
  }
}

Recorder::Recorder(std::vector<Channel> channels, std::size_t capacity_rows)
    : channels_(std::move(channels)), capacity_(capacity_rows) {
  data_.resize(channels_.size());
  for (auto& d : data_) d.resize(capacity_rows);
}

Recorder Recorder::streamed(std::vector<Channel> channels, std::vector<RowSink*> sinks,
                            std::size_t plot_buckets) {
  Recorder r;
  r.channels_ = std::move(channels);
  r.sinks_ = std::move(sinks);
  r.plots_.reserve(r.channels_.size());
  for (std::size_t i = 0; i < r.channels_.size(); ++i) r.plots_.emplace_back(plot_buckets);
  r.streamed_ = true;
  return r;
}

void Recorder::push_row(std::span<const double> values) noexcept {
  for (RowSink* s : sinks_) s->row(values);
  if (streamed_) {
    const double x = values.empty() ? 0.0 : values[0];
    const std::size_t n = std::min(values.size(), plots_.size());
    for (std::size_t i = 0; i < n; ++i) plots_[i].push(x, values[i]);
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
    plots_[i].points(x, y);
    return;
  }
  const auto cx = column(std::size_t{0}), cy = column(i);
  x.assign(cx.begin(), cx.end());
  y.assign(cy.begin(), cy.end());
}

}  // namespace lathectl::sim
