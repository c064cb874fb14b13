#pragma once
// System D's process as a scenario sets it: the gauging cycle's steps, an interrupted surface,
// the spindle's angle between encoder updates, the process (allowance, removal rate, target,
// noise, relay, backstop). In the settings layer (the settings hold it; machine_params and the
// HAL component use it), below the rig that runs it (rig.hpp).

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "lathectl/control/gauge_machine.hpp"

namespace lathectl::systems::d_gauging {

// The gauging cycle's steps before size (the seed's successive thresholds, each a command):
// rough → fine → spark-out → size. Each earlier threshold is (23) on the same line for the size
// where the next step starts, at the removal rate of the step it ends; the size step's rate is
// the process' a. Empty: the size step alone (the whole allowance at a).
struct GaugingCycle {
  std::vector<control::GaugeMachine::Step> before;  // thresholds rising, commands Fine, SparkOut
  // The removal rate of each command's step / a (Rough, Fine, SparkOut, Size).
  std::array<double, 4> rate_factor{1.0, 1.0, 1.0, 1.0};
  [[nodiscard]] double rate_factor_of(control::GaugeMachine::Command c) const {
    return rate_factor[static_cast<std::size_t>(c)];
  }
};

// An interrupted surface under the probe (seed 003's figure 1: interrupted surfaces machined
// with the gauge): `count` keyways (a slot `width_rad` wide, `depth_m` deep) or flats (a chord
// `depth_m` deep at its middle on a part of radius `radius_m`: the surface (R − h)/cos φ within
// |φ| < acos(1 − h/R)), equally spaced, turning at `spindle_rpm`; each part starts at its own
// random angle. `gate`: the machine knows where they are (the drawing, the spindle's angle) and
// bridges them, with `guard_s` after each while the probe settles (GaugeMachine's gate); false:
// it reads them as size.
struct Interruption {
  enum class Kind { None, Keyway, Flats };
  Kind kind = Kind::None;
  int count = 1;
  double width_rad = 0.0;  // keyway
  double depth_m = 0.0;
  double radius_m = 0.025;  // flats
  double spindle_rpm = 600.0;
  bool gate = true;
  double guard_s = 0.02;
  [[nodiscard]] bool any() const { return kind != Kind::None && count > 0; }
  // Half the angular span of one interruption.
  [[nodiscard]] double half_span_rad() const;
  // Where θ lies from the nearest interruption's middle (−π/count … π/count).
  [[nodiscard]] double from_middle_rad(double theta) const;
  // The surface's depth below the round one under the probe at spindle angle θ (0 on it).
  [[nodiscard]] double depth_at(double theta) const;
  [[nodiscard]] bool under(double theta) const {
    return any() && std::abs(from_middle_rad(theta)) < half_span_rad();
  }
  [[nodiscard]] double revolution_s() const { return 60.0 / spindle_rpm; }
  // The mean delay the bridges add to the signal (GaugeMachine::bridge_lag_s), 0 ungated.
  [[nodiscard]] double bridge_lag_s(double supply_Hz) const;
  // The round surface between two interruptions once the probe has settled (the pitch less one
  // interruption and its guard) [s]: the bridge needs two supply periods of it.
  [[nodiscard]] double round_stretch_s() const;
};

// The spindle's angle between the updates of its encoder: LinuxCNC's spindle.N.revs comes from
// the servo thread (every 1 ms: 3.6° at 600 rpm), the gauge and its plant run in the base thread
// (100 µs). Extrapolated at the speed of its last two changes, never past one more change's worth.
class SpindleAngle {
 public:
  // The angle [revolutions] now, from the encoder's `revs` read `dt_s` after the last call.
  double update(double revs, double dt_s) noexcept;
  [[nodiscard]] double speed_rev_per_s() const noexcept { return speed_; }

 private:
  double last_ = std::numeric_limits<double>::quiet_NaN();
  double since_ = 0.0, speed_ = 0.0, interval_ = 0.0;
};

struct GaugingProcess {
  double allowance_m = 200e-6;       // m_x
  double removal_m_per_s = 20e-6;    // a
  double target_m = 50e-6;           // x_k
  double noise_variance_m2 = 4e-12;  // D
  double noise_beta_per_s = 5.0;     // β
  double relay_response_s = 0.02;    // t_r
  // The programmed limit position: the cut ends when x reaches it whether or not the relay has
  // tripped (as any real gauging cycle's end stop), with an alarm. −∞: none.
  double backstop_m = -std::numeric_limits<double>::infinity();
  GaugingCycle cycle;          // the steps before size (none: the size step alone)
  Interruption interruption;  // none: a round surface
  // The time x reaches the backstop (∞ without one or without removal) at the size step's rate.
  [[nodiscard]] double backstop_time_s() const {
    return removal_m_per_s > 0.0 && std::isfinite(backstop_m)
               ? (allowance_m - backstop_m) / removal_m_per_s
               : std::numeric_limits<double>::infinity();
  }
};

}  // namespace lathectl::systems::d_gauging
