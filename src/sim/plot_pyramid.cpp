// Min/max pyramid of a plotted series (plot_pyramid.hpp).
#include "lathectl/sim/plot_pyramid.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace lathectl::sim {

PlotPyramid::PlotPyramid(Options options) : opt_(options) {
  opt_.branching = std::max<std::size_t>(opt_.branching, 2);
  opt_.max_values_per_level = std::max<std::size_t>(opt_.max_values_per_level, 16);
  levels_.push_back(Level{});
  open_.push_back(Bucket{});  // unused slot for level 0
  dropped_.push_back(false);
}

void PlotPyramid::store(std::size_t level, float v, double x_offset) {
  if (dropped_[level]) return;
  Level& l = levels_[level];
  if (l.y.size() >= opt_.max_values_per_level) {  // over budget: this level goes
    dropped_[level] = true;
    l.y = {};
    l.x = {};
    return;
  }
  l.y.push_back(v);
  l.x.push_back(static_cast<float>(x_offset));
}

void PlotPyramid::push(double x, double y) {
  if (finished_) throw std::logic_error("PlotPyramid::push after finish");
  if (!std::isfinite(x)) return;
  if (samples_ == 0) {
    x0_ = x;
  } else {
    if (x < last_x_) monotonic_ = false;
    if (samples_ == 1) dx_ = x - x0_;
    const double expected = x0_ + static_cast<double>(samples_) * dx_;
    if (uniform_ && (!(dx_ > 0.0) || std::abs(x - expected) > 1e-3 * dx_)) uniform_ = false;
  }
  last_x_ = x;
  const double off = x - x0_;
  const bool finite = std::isfinite(y);
  const float v = finite ? static_cast<float>(std::clamp(y, -3.0e38, 3.0e38))
                         : std::numeric_limits<float>::quiet_NaN();  // a gap
  store(0, v, off);
  Bucket one;
  one.count = 1;
  one.any = finite;
  one.lo = one.hi = v;
  one.x_lo = one.x_hi = off;
  one.i_lo = one.i_hi = samples_;
  ++samples_;
  feed(1, one);
}

// Merges a closed bucket of the level below into `level`'s open bucket; closes it when full.
void PlotPyramid::feed(std::size_t level, const Bucket& b) {
  if (level >= levels_.size()) {
    levels_.push_back(Level{levels_.back().bucket * opt_.branching, {}, {}});
    open_.push_back(Bucket{});
    dropped_.push_back(false);
  }
  Bucket& o = open_[level];
  if (b.any) {
    if (!o.any || b.lo < o.lo) {
      o.lo = b.lo;
      o.x_lo = b.x_lo;
      o.i_lo = b.i_lo;
    }
    if (!o.any || b.hi > o.hi) {
      o.hi = b.hi;
      o.x_hi = b.x_hi;
      o.i_hi = b.i_hi;
    }
    o.any = true;
  }
  if (o.count == 0 && !b.any) o.x_lo = o.x_hi = b.x_lo;
  o.count += 1;
  if (o.count == opt_.branching) close(level);
}

void PlotPyramid::close(std::size_t level, bool propagate) {
  Bucket b = open_[level];
  open_[level] = Bucket{};
  if (b.count == 0) return;
  if (!b.any) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    store(level, nan, b.x_lo);
    store(level, nan, b.x_lo);
  } else if (b.i_lo <= b.i_hi) {
    store(level, b.lo, b.x_lo);
    store(level, b.hi, b.x_hi);
  } else {
    store(level, b.hi, b.x_hi);
    store(level, b.lo, b.x_lo);
  }
  b.count = 1;
  if (propagate) feed(level + 1, b);
}

void PlotPyramid::finish() {
  if (finished_) return;
  finished_ = true;
  // Close the partial buckets bottom-up: each closing may open the next level's last bucket.
  // The top level has never closed a bucket: its partial one is its only one, and nothing goes
  // above it.
  for (std::size_t level = 1; level < levels_.size(); ++level)
    close(level, level + 1 < levels_.size());
  // Keep the finest surviving levels up to the first one that is small enough on its own.
  std::vector<Level> kept;
  for (std::size_t level = 0; level < levels_.size(); ++level) {
    if (dropped_[level]) continue;
    Level& l = levels_[level];
    if (uniform_) l.x = {};
    const bool small = l.y.size() <= opt_.coarsest_values;
    kept.push_back(std::move(l));
    if (small) break;
  }
  levels_ = std::move(kept);
}

const std::vector<PlotPyramid::Level>& PlotPyramid::levels() const {
  if (!finished_) throw std::logic_error("PlotPyramid::levels before finish");
  return levels_;
}

std::shared_ptr<const PlotPyramid> PlotPyramid::finished() const {
  auto p = std::make_shared<PlotPyramid>(*this);
  p->finish();
  return p;
}

void PlotPyramid::points(std::vector<double>& x, std::vector<double>& y,
                         std::size_t max_points) const {
  if (!finished_) {
    finished()->points(x, y, max_points);
    return;
  }
  x.clear();
  y.clear();
  if (levels_.empty()) return;
  const Level* l = &levels_.back();
  for (const Level& c : levels_)
    if (c.y.size() <= max_points) {
      l = &c;
      break;
    }
  x.reserve(l->y.size());
  y.reserve(l->y.size());
  for (std::size_t i = 0; i < l->y.size(); ++i) {
    double off = 0.0;
    if (!uniform_) {
      off = l->x[i];
    } else if (l->bucket == 1) {
      off = static_cast<double>(i) * dx_;
    } else {  // pair j at (j·b + b/4) and (j·b + 3b/4) samples
      const double b = static_cast<double>(l->bucket);
      off = (static_cast<double>(i / 2) * b + (i % 2 == 0 ? 0.25 : 0.75) * b) * dx_;
    }
    x.push_back(x0_ + off);
    y.push_back(l->y[i]);
  }
}

}  // namespace lathectl::sim
