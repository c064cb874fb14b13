#pragma once
// A plausible pulse-feed controller configuration (the a_finishing_* slide) shared by the
// zero-allocation test and the benchmarks.
#include "lathectl/control/pulse_feed_controller.hpp"

namespace lathectl::testing {

inline control::PulseFeedController::Params sample_pulse_feed_params(
    control::PulseFeedController::Modulation m, control::PulseFeedController::Mode mode) {
  control::PulseFeedController::Params p;
  p.modulation = m;
  p.mode = mode;
  p.regulator_gain_per_m = 0.2;
  p.pulse_width_s = 0.005;
  p.frequency_Hz = 20;
  p.slot_m = 40e-6;
  p.piston_area_m2 = 8e-4;
  p.leak_m3_per_s_Pa = 1e-12;
  p.feed_m_per_s = 1e-3;
  p.force_set_N = 200;
  p.sensor_V_per_N = 5e-3;
  p.slot_max_m = 1e-4;
  p.compliance_m3_per_Pa = 5e-13;
  p.sensor_monitor = {-0.5, 10.5, 0.05, 0.0};
  return p;
}

}  // namespace lathectl::testing
