#include "systems/e_adaptive/machine_params.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace lathectl::systems::e_adaptive {

namespace {

bool on_power(const RigConfig& e, const MachineHost& h) noexcept {
  return h.load == MachineHost::Load::SpindlePower ||
         e.force_parameter == cutting::ForceParameter::Power;
}

// The controller's settings in the load's unit. A scenario on a dynamometer run on the drive's
// power (sensor=power) has its limit and plausible range in N: they do not apply to a reading in
// W. The power's own then hold: the reading goes as far negative as a braking drive regenerates
// (its rating) and up to twice the rating (a run-up); the limit is the power the spindle has for
// cutting, the speed law's clamp.
control::AdaptiveFeedController::Params controller(const RigConfig& e, const MachineHost& h) {
  auto c = e.controller;
  if (h.load == MachineHost::Load::SpindlePower &&
      e.force_parameter != cutting::ForceParameter::Power) {
    c.sensor_monitor.min = -1.2 * e.spindle.max_power_W;
    c.sensor_monitor.max = 2.0 * e.spindle.max_power_W;
    c.load_limit = std::min(c.cut_power_max_W, e.spindle.max_power_W);
  }
  if (std::isfinite(h.feed_programmed_mm_per_rev)) {
    c.feed_programmed_mm_per_rev = h.feed_programmed_mm_per_rev;
    c.feed_min_mm_per_rev = std::min(c.feed_min_mm_per_rev, c.feed_programmed_mm_per_rev);
  }
  // An air feed of 0 (the scenario's range allows it) is the smallest the controller takes.
  c.air_feed_mm_per_rev = std::max(c.air_feed_mm_per_rev, 1e-6);
  return c;
}

void tool_data(const RigConfig& e, const MachineHost& h, control::AdaptiveMachine::Params& mp) {
  using control::AdaptiveMachine;
  // The rating a program's value may not exceed: the tool table's, else what the sensor can
  // measure (the dynamometer's range; on power, the spindle's power).
  mp.rating.limit_max = on_power(e, h) ? e.spindle.max_power_W : e.force_sensor.range;
  mp.rating.feed_max_mm_per_rev = mp.controller.feed_max_mm_per_rev;
  if (h.tools != nullptr) {
    if (h.tools->limit_max > 0.0) mp.rating.limit_max = h.tools->limit_max;
    if (h.tools->feed_max_mm_per_rev > 0.0)
      mp.rating.feed_max_mm_per_rev = h.tools->feed_max_mm_per_rev;
    if (h.tools->tools.size() > AdaptiveMachine::kMaxTools)
      throw std::invalid_argument(h.tools_file + ": more than " +
                                  std::to_string(AdaptiveMachine::kMaxTools) + " tools");
    mp.tools = h.tools->tools;
  }
  const std::string unit = load_unit(e, h);
  for (const auto& t : h.taught) {
    if (t.unit != unit)
      throw std::invalid_argument(h.taught_file + ": tool " + std::to_string(t.tool) +
                                  " was taught in " + t.unit +
                                  ", this sensor measures " + unit);
    if (mp.taught.size() >= AdaptiveMachine::kMaxTaught)
      throw std::invalid_argument(h.taught_file + ": more than " +
                                  std::to_string(AdaptiveMachine::kMaxTaught) + " references");
    mp.taught.push_back({t.tool, t.operation, t.reference});
  }
}

}  // namespace

cutting::CuttingProcess lathe_process(const RigConfig& e) {
  cutting::CuttingProcess process = e;
  auto& b = process.stock.blank_diameter_mm;
  if (b.empty()) return process;
  double z_lo = b.front().at_mm, z_hi = b.back().at_mm;
  for (const auto& q : e.stock.passes) {
    z_lo = std::min(z_lo, q.z_start_mm);
    z_hi = std::max(z_hi, q.z_end_mm);
  }
  if (z_lo < b.front().at_mm) b.insert(b.begin(), {z_lo, b.front().value});
  if (z_hi > b.back().at_mm) b.push_back({z_hi, b.back().value});
  return process;
}

sensors::LaggedNoisySensor::Params spindle_power_meter(const RigConfig& e) noexcept {
  return e.force_parameter == cutting::ForceParameter::Power ? e.force_sensor : e.power_meter;
}

const char* load_unit(const RigConfig& e, const MachineHost& host) noexcept {
  return on_power(e, host) ? "W" : "N";
}

control::AdaptiveMachine::Params machine_params(const RigConfig& e, const MachineHost& h) {
  control::AdaptiveMachine::Params mp;
  mp.controller = controller(e, h);
  mp.parameter = e.force_parameter;
  mp.power_sensor = h.load == MachineHost::Load::SpindlePower;
  mp.spindle = e.spindle;
  // The drive's power reading lags as its meter.
  mp.power_lag_s = spindle_power_meter(e).time_constant_s;
  mp.learn_inertia = e.learn_inertia;
  mp.feed_forward = e.feed_forward;
  mp.stock_model = std::isfinite(h.z_origin_mm);
  if (mp.stock_model) {
    mp.process = lathe_process(e);
    mp.process.faults.clear();  // the model holds the bar; faults are the sensor's, not the bar's
    mp.z_origin_mm = h.z_origin_mm;
    mp.life_law = e.life_law;
  } else if (e.life_law) {
    throw std::invalid_argument(
        "the scenario's speed_law = \"tool_life\" needs the stock model (the stock's face: "
        "z_origin_mm)");
  }
  tool_data(e, h, mp);
  return mp;
}

}  // namespace lathectl::systems::e_adaptive
