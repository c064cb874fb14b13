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
  dropped_.push_back(0);
}

void PlotPyramid::add_level() {
  levels_.push_back(Level{levels_.back().bucket * opt_.branching, {}, {}});
  open_.push_back(Bucket{});
  dropped_.push_back(0);
}

// Over budget: the level goes (its coarser levels carry on).
void PlotPyramid::drop(std::size_t level) {
  dropped_[level] = 1;
  levels_[level].y = {};
  levels_[level].x = {};
}

void PlotPyramid::merge(Bucket& o, const Bucket& b) noexcept {
  if (o.count == 0) o.x_lo = o.x_hi = b.x_lo;  // stays so while no finite value comes
  const bool take_lo = b.lo < o.lo, take_hi = b.hi > o.hi;  // ties keep the earlier
  // Which extreme came first: b's samples all follow o's.
  o.lo_first = take_lo ? (take_hi && b.lo_first) : (take_hi || o.lo_first);
  if (take_lo) {
    o.lo = b.lo;
    o.x_lo = b.x_lo;
  }
  if (take_hi) {
    o.hi = b.hi;
    o.x_hi = b.x_hi;
  }
  o.count += 1;
}

// x's bookkeeping for the next sample (before samples_ counts it).
inline void PlotPyramid::track_x(double x) noexcept {
  if (samples_ == 0) {
    x0_ = x;
  } else {
    if (x < last_x_) monotonic_ = false;
    if (samples_ == 1) dx_ = x - x0_;
    const double expected = x0_ + static_cast<double>(samples_) * dx_;
    if (uniform_ && (!(dx_ > 0.0) || std::abs(x - expected) > 1e-3 * dx_)) uniform_ = false;
  }
  last_x_ = x;
}

// The sample's value at offset `off` (x placed by track_x) into level 0 and level 1's bucket.
inline void PlotPyramid::push_value(double y, float off) {
  const float v = std::isfinite(y) ? static_cast<float>(std::clamp(y, -3.0e38, 3.0e38))
                                   : std::numeric_limits<float>::quiet_NaN();  // a gap
  if (!dropped_[0]) {
    Level& l = levels_[0];
    if (l.y.size() >= opt_.max_values_per_level) {
      drop(0);
    } else {
      l.y.push_back(v);
      l.x.push_back(off);
    }
  }
  ++samples_;
  if (levels_.size() < 2) [[unlikely]]
    add_level();
  // The sample as a bucket of one, into level 1 (a gap takes no extreme).
  Bucket& o = open_[1];
  if (o.count == 0) o.x_lo = o.x_hi = off;
  const bool take_lo = v < o.lo, take_hi = v > o.hi;
  o.lo_first = take_hi || (!take_lo && o.lo_first);
  if (take_lo) {
    o.lo = v;
    o.x_lo = off;
  }
  if (take_hi) {
    o.hi = v;
    o.x_hi = off;
  }
  if (++o.count == opt_.branching) close(1);
}

void PlotPyramid::push(double x, double y) {
  if (finished_) throw std::logic_error("PlotPyramid::push after finish");
  if (!std::isfinite(x)) return;
  track_x(x);
  push_value(y, static_cast<float>(x - x0_));
}

void PlotPyramid::push_row(std::span<PlotPyramid> series, double x, std::span<const double> y) {
  const std::size_t n = std::min(series.size(), y.size());
  if (n == 0) return;
  PlotPyramid& lead = series[0];
  const std::size_t before = lead.samples_;
  lead.push(x, y[0]);
  if (lead.samples_ == before) return;  // x not finite: skipped by all
  const float off = static_cast<float>(x - lead.x0_);
  for (std::size_t i = 1; i < n; ++i) {
    PlotPyramid& p = series[i];
    if (p.samples_ != before || p.finished_) [[unlikely]] {  // not fed the same x's
      p.push(x, y[i]);
      continue;
    }
    p.x0_ = lead.x0_;  // the same x's: the same bookkeeping
    p.dx_ = lead.dx_;
    p.last_x_ = lead.last_x_;
    p.uniform_ = lead.uniform_;
    p.monotonic_ = lead.monotonic_;
    p.push_value(y[i], off);
  }
}

// Stores `level`'s open bucket (its extremes in order, two NaN for one without a finite value)
// and, when propagating, merges it into the next level, closing that one in turn when full.
void PlotPyramid::close(std::size_t level, bool propagate) {
  for (;;) {
    const Bucket b = open_[level];
    open_[level] = Bucket{};
    if (b.count == 0) return;
    if (!dropped_[level]) {
      Level& l = levels_[level];
      if (l.y.size() + 2 > opt_.max_values_per_level) {
        drop(level);
      } else {
        // Its extremes in the order they occurred; two gaps at its first sample if none.
        const bool gap = !(b.lo <= b.hi), lo_first = gap || b.lo_first;
        const float nan = std::numeric_limits<float>::quiet_NaN();
        l.y.push_back(gap ? nan : lo_first ? b.lo : b.hi);
        l.y.push_back(gap ? nan : lo_first ? b.hi : b.lo);
        l.x.push_back(lo_first ? b.x_lo : b.x_hi);
        l.x.push_back(gap ? b.x_lo : lo_first ? b.x_hi : b.x_lo);
      }
    }
    if (!propagate) return;
    ++level;
    if (level >= levels_.size()) add_level();
    merge(open_[level], b);
    if (open_[level].count != opt_.branching) return;
  }
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
    if (dropped_[level] != 0) continue;
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
