#pragma once
// System A's rig configuration: the slide, its regulator, the cut and the controller as a scenario
// sets them. In the settings layer (the settings hold it; machine_params derives the machine side
// from it), below the rig that runs it (rig.hpp).

#include <numbers>
#include <vector>

#include "lathectl/control/pulse_feed_controller.hpp"
#include "lathectl/control/slide_machine.hpp"
#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/cutting/disturbances.hpp"
#include "lathectl/drives/eccentric_drive.hpp"
#include "lathectl/hydraulics/feed_slide.hpp"
#include "lathectl/hydraulics/pulse_regulator.hpp"
#include "lathectl/sensors/faults.hpp"
#include "lathectl/sensors/inductive_sensor.hpp"

namespace lathectl::systems::a_pulse_feed {

enum class RegulatorKind { Pulsed, Throttle };
enum class ControllerKind { None, Aim, Fim };

struct RigConfig {
  double spindle_rpm = 500.0;
  double diameter_m = 0.06;
  cutting::CuttingModel::Params cutting;
  cutting::DisturbanceParams part;
  RegulatorKind regulator_kind = RegulatorKind::Pulsed;
  hydraulics::PulseRegulator::Params regulator;  // its orifice and obliteration serve the throttle
  double pulse_width_s = 0.01;                   // Δt
  double frequency_Hz = 10.0;                    // AIM / uncontrolled pulse frequency
  double slot_m = 40e-6;                         // FIM fixed slot
  // The scenario reader's defaults, where they differ from the drive's and controller's own:
  // a 3000 rpm eccentric motor, a 5 ms force filter, a 500 Hz/s converter ramp, a plausible sensor
  // range from −0.5 V to saturation + 0.5 V and a 50 ms stuck check (one default).
  drives::EccentricDrive::Params eccentric = [] {
    drives::EccentricDrive::Params p;
    p.motor_max_speed_rad_per_s = 3000.0 * 2.0 * std::numbers::pi / 60.0;
    return p;
  }();
  hydraulics::FeedSlide::Params slide;
  sensors::InductiveSensor::Params sensor;
  ControllerKind controller_kind = ControllerKind::None;
  control::PulseFeedController::Params controller{  // programmed feed, mode, limits, gains
      .force_filter_s = 5e-3,
      .sensor_monitor = {.min = -0.5, .max = 10.5, .stuck_time_s = 50e-3},
      .frequency_ramp_Hz_per_s = 500.0};
  // The machine side around the controller: roughing's alarms, the laws along the travel (the
  // controller's parameters above are the machine's; these its own).
  control::SlideMachine::Params machine;
  double leak_estimate_factor = 1.0;                // controller's K_leak = factor × the plant's
  bool compensate_compliance = true;                // finishing: add C·dp/dt (beyond the seed)
  std::vector<sensors::SensorFault> faults;
  double feed_window_s = 0.1;  // moving average of the recorded feed rate
};

}  // namespace lathectl::systems::a_pulse_feed
