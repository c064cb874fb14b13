#include "lathectl/sensors/gauge_filter.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "lathectl/core/parameter_error.hpp"

namespace lathectl::sensors {

double GaugeFilter::window_s(const Params& p) noexcept {
  const double n = std::max(1.0, std::round(p.time_constant_s * p.supply_Hz));
  return 2.0 * n / p.supply_Hz;  // 2n supply periods, nearest 2·T_f
}

double GaugeFilter::lag_s(const Params& p) noexcept {
  return p.kind == GaugeFilterKind::Synchronous ? 0.5 * window_s(p) : p.time_constant_s;
}

void GaugeFilter::configure(const Params& p, double dt) {
  auto positive = [](double v, const char* name, const char* what) {
    if (!(v > 0.0) || !std::isfinite(v))
      throw core::ParameterError(name, std::string("gauge filter: ") + what + " must be > 0");
  };
  positive(p.time_constant_s, "filter_time_constant_s", "the filter time constant");
  positive(p.supply_Hz, "supply_Hz", "the supply frequency");
  positive(dt, "step", "the sample period");
  p_ = p;
  const double tf =
      p.kind == GaugeFilterKind::SecondOrder ? 0.5 * p.time_constant_s : p.time_constant_s;
  lag_ = core::FirstOrderLag(dt, tf);  // tf > 0
  ring_.assign(
      p.kind == GaugeFilterKind::Synchronous
          ? std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(window_s(p) / dt)))
          : 0,
      0.0);
  reset(0.0);
}

void GaugeFilter::reset(double level) noexcept {
  s_ = s1_ = level;
  std::fill(ring_.begin(), ring_.end(), level);
  ring_sum_ = level * static_cast<double>(ring_.size());
  ring_pos_ = 0;
}

double GaugeFilter::step(double g) noexcept {
  switch (p_.kind) {
    case GaugeFilterKind::SecondOrder:
      s1_ = lag_.step(s1_, g);
      s_ = lag_.step(s_, s1_);
      return s_;
    case GaugeFilterKind::Synchronous: {
      ring_sum_ += g - ring_[ring_pos_];
      ring_[ring_pos_] = g;
      if (++ring_pos_ == ring_.size()) {
        ring_pos_ = 0;
        double sum = 0.0;  // once per window: no drift of the running sum
        for (double v : ring_) sum += v;
        ring_sum_ = sum;
      }
      s_ = ring_sum_ / static_cast<double>(ring_.size());
      return s_;
    }
    case GaugeFilterKind::FirstOrder:
      break;
  }
  s_ = lag_.step(s_, g);
  return s_;
}

}  // namespace lathectl::sensors
