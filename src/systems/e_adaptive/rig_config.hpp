#pragma once
// System E's rig configuration: what a scenario sets of the cutting process and the machine
// around it. In the settings layer (the settings hold it; machine_params derives the machine side
// from it), below the rig that runs it (rig.hpp).

#include "lathectl/control/adaptive_feed_controller.hpp"
#include "lathectl/cutting/lathe_plant.hpp"
#include "lathectl/drives/feed_axis.hpp"
#include "lathectl/drives/spindle_drive.hpp"
#include "lathectl/sensors/force_sensor.hpp"

namespace lathectl::systems::e_adaptive {

// The cutting process (material, tool, stock, disturbances, sensor 4, faults: what the LinuxCNC
// plant models too) and the machine around it. Defaults are a system-E scenario's: where a
// library struct's own default differs, the member initialiser says so.
struct RigConfig : cutting::CuttingProcess {
  // The measured feed rate over 20 ms (the struct's 10 ms is the bare axis's).
  drives::FeedAxis::Params axis{.velocity_window_s = 0.02};
  // No idle losses unless the scenario gives them (the struct's 300 W + 0.3·n + 1e-4·n² are the
  // generic drive's; system B keeps those).
  drives::SpindleDrive::Params spindle{
      .idle_p0_W = 0.0, .idle_p1_W_per_rpm = 0.0, .idle_p2_W_per_rpm2 = 0.0};
  sensors::LaggedNoisySensor::Params power_meter{.time_constant_s = 0.02};  // electrical [W]
  // A stuck reading alarms after 100 ms (the bare monitor's 0 disables the check).
  control::AdaptiveFeedController::Params controller{.sensor_monitor = {.stuck_time_s = 0.1}};
  bool worst_case_feed = false;   // fixed mode: programmed feed so the worst case meets the limit
  double planned_depth_mm = 2.0;  // depth at which V_p, S_p give the planned tool life
  // The tool-life speed law (control::AdaptiveMachine::Params::life_law): depth from the stock
  // model, hardness from the cut's specific force.
  bool life_law = false;
  // Power sensor: the machine learns the spindle's inertia (AdaptiveMachine::Params).
  bool learn_inertia = false;
  // The feed-forward from the stock model (AdaptiveMachine::Params::feed_forward).
  bool feed_forward = true;
  double approach_mm = 2.0;       // air travel before each pass
  double rapid_m_per_s = 0.1;
};

}  // namespace lathectl::systems::e_adaptive
