#pragma once
// CNC feed axis (system E, drive 1 with feed-rate sensor 12): a position-controlled servo seen
// from the adaptive controller as a velocity source with finite bandwidth.
//
//   v_ref = clamp(v_cmd, −v_max, v_max)
//   dv/dt = clamp((v_ref − v)/τ_v, −a_max, a_max)     velocity loop (first order) with the
//                                                      drive's acceleration limit
//   dz/dt = v
//   encoder: z quantised to `encoder_resolution_m`; the measured velocity is the difference of
//   quantised positions over `velocity_window_s` (what a CNC's feed-rate display does).
// Integration: exact for the first-order lag when the acceleration limit is inactive
// (v ← v_ref + (v − v_ref)·e^(−dt/τ_v)); otherwise the limited slope for the step.

#include <vector>

#include "lathectl/core/first_order_lag.hpp"

namespace lathectl::drives {

class FeedAxis {
 public:
  struct Params {
    double time_constant_s = 0.01;           // τ_v: velocity-loop lag (bandwidth 1/(2πτ_v))
    double max_velocity_m_per_s = 0.1;       // v_max (rapid traverse)
    double max_acceleration_m_per_s2 = 2.0;  // a_max
    double encoder_resolution_m = 1e-6;
    double velocity_window_s = 0.01;  // window of the measured velocity
  };
  // Allocates the encoder history for steps of dt; throws std::invalid_argument.
  void configure(const Params& p, double dt_s);
  void reset(double z_m, double v_m_per_s) noexcept;
  void step(double v_cmd_m_per_s) noexcept;  // one step of dt
  [[nodiscard]] double position_m() const noexcept { return z_; }
  [[nodiscard]] double velocity_m_per_s() const noexcept { return v_; }
  [[nodiscard]] double measured_velocity_m_per_s() const noexcept { return v_meas_; }

 private:
  Params p_{};
  double dt_ = 1e-4;
  core::FirstOrderLag lag_;
  double z_ = 0.0;
  double v_ = 0.0;
  double v_meas_ = 0.0;
  std::vector<double> hist_;  // quantised positions, ring buffer over the velocity window
  std::size_t head_ = 0;
};

}  // namespace lathectl::drives
