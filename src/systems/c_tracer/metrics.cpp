#include "systems/c_tracer/metrics.hpp"

#include <algorithm>
#include <cmath>

namespace lathectl::systems::c_tracer {

TracerMetrics::TracerMetrics(const sim::Recorder& rec, const std::vector<TracerFeature>& features,
                             std::size_t kept_rows)
    : tx_(rec.index("tool_x_mm")),
      cx_(rec.index("carriage_mm")),
      dx_(rec.index("dx_um")),
      dy_(rec.index("dy_um")),
      lag_(rec.index("lag_um")),
      load_(rec.index("load_N")),
      feat_(features.size()),
      kept_budget_(kept_rows) {
  // A shoulder has no length (x_start = x_end): the tool climbs it within its zone, which starts
  // the next feature's x range; its δx is the shoulder's, not the next line's.
  for (const auto& f : features)
    if (f.x_end_m <= f.x_start_m) shoulders_.push_back(f.x_start_m * 1e3);
  for (std::size_t i = 0; i < features.size(); ++i) {
    const auto& f = features[i];
    const double a = f.x_start_m * 1e3, b = f.x_end_m * 1e3;
    ranges_.push_back({a, b, b <= a});
    // Steady lag and waviness over the cone's second half (after the transient).
    if (f.kind == "cone" && b - a > 0.0) {
      ConeWindow w;
      w.feature = i;
      w.from_mm = 0.5 * (a + b);
      w.to_mm = b;
      cones_.push_back(w);
    }
  }
}

void TracerMetrics::row(std::span<const double> v) noexcept {
  const double x = v[tx_], dx = v[dx_], dy = v[dy_];
  if (rows_++ == 0) first_load_ = v[load_];
  const bool dx_ok = std::isfinite(dx), dy_ok = std::isfinite(dy);
  if (x >= -1e300 && x <= 1e300) {
    if (dx_ok) max_dx_ = std::max(max_dx_, std::abs(dx));
    if (dy_ok) max_dy_ = std::max(max_dy_, std::abs(dy));
  }
  any_dx_ = any_dx_ || dx_ok;
  if (dx_ok || dy_ok) {
    const bool at_shoulder = std::any_of(shoulders_.begin(), shoulders_.end(), [&](double s) {
      return std::abs(x - s) <= kShoulderZone_mm;
    });
    for (std::size_t i = 0; i < ranges_.size(); ++i) {
      const Range& r = ranges_[i];
      FeatureErrors& f = feat_[i];
      // A shoulder: its zone; another feature: its range without the shoulders' zones.
      const bool in = r.shoulder ? x >= r.a - kShoulderZone_mm && x <= r.a + kShoulderZone_mm
                                 : x >= r.a && x <= r.b && !at_shoulder;
      if (in && dx_ok) f.max_dx_um = std::max(f.max_dx_um, std::abs(dx));
      if (in && dy_ok) f.max_dy_um = std::max(f.max_dy_um, std::abs(dy));
      // Where δx is defined: the range (the shoulders' zones included), or the shoulder's zone.
      const double a = r.shoulder ? r.a - kShoulderZone_mm : r.a;
      const double b = r.shoulder ? r.b + kShoulderZone_mm : r.b;
      if (dx_ok && x >= a && x <= b) f.dx_defined = true;
    }
  }
  const double cx = v[cx_];
  for (ConeWindow& w : cones_) {
    if (!w.in(cx, dy)) continue;
    w.sx += cx;
    w.sy += dy;
    w.sxx += cx * cx;
    w.sxy += cx * dy;
    w.n += 1;
    w.last_lag_um = v[lag_];
    if (w.complete && kept_ < kept_budget_) {
      w.kept.emplace_back(cx, dy);
      ++kept_;
    } else if (w.complete) {
      w.complete = false;
      kept_ -= w.kept.size();
      w.kept = {};
    }
  }
  dy_x_.push(x, dy);
  dx_x_.push(x, dx);
}

bool TracerMetrics::finish() {
  bool done = true;
  for (ConeWindow& w : cones_) {
    if (!(w.n > 2)) continue;
    const double n = w.n;
    w.k1 = (n * w.sxy - w.sx * w.sy) / (n * w.sxx - w.sx * w.sx);
    w.k0 = (w.sy - w.k1 * w.sx) / n;
    if (!w.complete) {
      done = false;
      continue;
    }
    for (const auto& [cx, dy] : w.kept) w.residual(cx, dy);
    w.kept = {};
  }
  return done;
}

void TracerMetrics::Second::row(std::span<const double> v) noexcept {
  const double cx = v[m_.cx_], dy = v[m_.dy_];
  for (ConeWindow& w : m_.cones_)
    if (!w.complete && w.n > 2 && w.in(cx, dy)) w.residual(cx, dy);
}

}  // namespace lathectl::systems::c_tracer
