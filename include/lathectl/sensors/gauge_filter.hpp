#pragma once
// The vibro-contact gauge's filter (seed 003, (14)), on the rectified generator signal g = |u|:
//   first order   T_f·S' + S = g, exact for g held over a sample
//   second order  two such lags of T_f/2 in cascade: the same ramp lag T_f, the probe's 2ω ripple
//                 down by a further ~ωT_f/2
//   synchronous   the mean of g over the last T_w = 2n supply periods (T_w the even number of
//                 periods nearest 2·T_f): ramp lag T_w/2, every harmonic of ω/2 nulled
// One implementation for the transducer model (sensors::VibroContactGauge) and the machine side
// (control::GaugeMachine): here in sensors/, below control/, so that both may include it.
// configure() allocates the synchronous window; reset() and step() do not.

#include <cstddef>
#include <vector>

#include "lathectl/core/first_order_lag.hpp"

namespace lathectl::sensors {

enum class GaugeFilterKind { FirstOrder, SecondOrder, Synchronous };

class GaugeFilter {
 public:
  struct Params {
    bool operator==(const Params&) const = default;
    GaugeFilterKind kind = GaugeFilterKind::FirstOrder;
    double time_constant_s = 0.1;  // T_f
    double supply_Hz = 50.0;       // ω/2π: sets the synchronous window
  };
  // T_w: the even number of supply periods nearest 2·T_f (≥ 2).
  static double window_s(const Params& p) noexcept;
  // The delay of a ramp through the filter: T_f, T_f, T_w/2.
  static double lag_s(const Params& p) noexcept;
  // Throws core::ParameterError ("filter_time_constant_s", "supply_Hz", "step").
  void configure(const Params& p, double dt_s);
  void reset(double level) noexcept;  // settled on a constant input `level`
  double step(double g) noexcept;     // one sample of the rectified signal; returns S
  [[nodiscard]] double value() const noexcept { return s_; }

 private:
  Params p_{};
  core::FirstOrderLag lag_;  // each stage's
  double s_ = 0.0, s1_ = 0.0;
  std::vector<double> ring_;  // synchronous: the window's samples and their running sum
  std::size_t ring_pos_ = 0;
  double ring_sum_ = 0.0;
};

}  // namespace lathectl::sensors
