#pragma once
// The adaptive controller's Input from the signals a machine measures — one function for the
// simulated rig (system E) and the LinuxCNC component (lathectl_adaptive), so both feed the
// speed law's power limit the same cutting power:
//
//   force         sensor 4's sample (N for Pz or Py, W for the cutting power)
//   P_meter       the spindle drive's power meter (electrical) minus its idle power P_idle(n)
//   cut power     Pz:    Pz·V/60 (the dynamometer; the meter also carries the power that
//                        accelerates the spindle, which would make a power-limited speed loop
//                        hunt), P_meter when Pz is not finite
//                 Py:    P_meter (Py·V is no power: the radial force does no work)
//                 power: the sensor's own sample (it is the cutting power), P_meter when the
//                        sample is not finite
//                 never negative; 0 when nothing measures it (no power limit then)
// Real-time: no allocation, no exceptions.

#include <algorithm>
#include <cmath>
#include <limits>

#include "lathectl/control/adaptive_feed_controller.hpp"
#include "lathectl/cutting/force_parameter.hpp"

namespace lathectl::control {

struct AdaptiveSignals {
  double force = 0.0;  // sensor 4 (N, or W for the power parameter)
  // The spindle's power meter, electrical [W]; NaN when the machine has none.
  double spindle_power_W = std::numeric_limits<double>::quiet_NaN();
  double idle_power_W = 0.0;          // P_idle at the measured speed (drives::idle_power_W)
  double rpm = 0.0;                   // sensor 13
  double speed_m_per_min = 0.0;       // sensor 20
  double feed_rate_mm_per_min = 0.0;  // sensor 12
  bool feed_block = true;             // a cutting (G1) block is active
};

[[nodiscard]] inline AdaptiveFeedController::Input adaptive_input(
    cutting::ForceParameter which, const AdaptiveSignals& s) noexcept {
  using cutting::ForceParameter;
  AdaptiveFeedController::Input in;
  in.force = s.force;
  in.feed_rate_mm_per_min = s.feed_rate_mm_per_min;
  in.rpm = s.rpm;
  in.speed_m_per_min = s.speed_m_per_min;
  in.feed_block = s.feed_block;
  const double meter = s.spindle_power_W - s.idle_power_W;  // NaN without a meter
  const bool force_ok = std::isfinite(s.force);
  double power = std::isfinite(meter) ? meter : 0.0;
  if (which == ForceParameter::Pz && force_ok) power = s.force * s.speed_m_per_min / 60.0;
  if (which == ForceParameter::Power && force_ok) power = s.force;
  in.cut_power_W = std::max(power, 0.0);
  return in;
}

}  // namespace lathectl::control
