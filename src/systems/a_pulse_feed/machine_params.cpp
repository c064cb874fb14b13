#include "systems/a_pulse_feed/machine_params.hpp"

#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/cutting/disturbances.hpp"
#include "lathectl/sensors/inductive_sensor.hpp"
#include "lathectl/sim/config_error.hpp"
#include "systems/a_pulse_feed/settings.hpp"

#include <numbers>

namespace lathectl::systems::a_pulse_feed {

control::SlideMachine::Params machine_params(const RigConfig& cfg, const Host& host) {
  if (host.machine_io && (cfg.regulator_kind != RegulatorKind::Pulsed ||
                          cfg.controller_kind == ControllerKind::None))
    throw sim::ConfigError("controller.type",
                           "a machine's controller drives a pulsed regulator: controller must be "
                           "aim or fim and regulator pulsed");
  if (cfg.regulator_kind == RegulatorKind::Throttle && cfg.controller_kind != ControllerKind::None)
    throw sim::ConfigError("controller.type",
                           "a continuous throttle has no pulse actuator: controller must be none");
  const double feed = cfg.controller.feed_m_per_s;
  if (!(feed > 0.0)) throw sim::ConfigError("controller.feed_mm_per_min", "must be > 0");
  sensors::InductiveSensor sensor;
  sim::configure_as("sensor", [&] { sensor.configure(cfg.sensor); });

  auto cp = cfg.controller;
  cp.regulator_gain_per_m = cfg.regulator.orifice.gain_per_m();
  cp.pulse_width_s = cfg.pulse_width_s;
  cp.slot_m = cfg.slot_m;
  cp.frequency_Hz = cfg.frequency_Hz;
  cp.piston_area_m2 = cfg.slide.piston_area_m2;
  cp.leak_m3_per_s_Pa = cfg.slide.leak_m3_per_s_Pa * cfg.leak_estimate_factor;
  // Friction at the programmed feed: Coulomb plus viscous (the setter's and controller's model).
  cp.friction_N = cfg.slide.coulomb_friction_N + cfg.slide.viscous_friction_N_s_per_m * feed;
  if (cfg.compensate_compliance)
    cp.compliance_m3_per_Pa = cfg.slide.damper_capacitance_m3_per_Pa +
                              cfg.slide.dead_volume_m3 / cfg.slide.bulk_modulus_Pa;
  cp.sensor_V_per_N = sensor.volts_per_newton();
  cp.sensor_offset_V = cfg.sensor.offset_V;
  cp.modulation = cfg.controller_kind == ControllerKind::Fim
                      ? control::PulseFeedController::Modulation::Frequency
                      : control::PulseFeedController::Modulation::Amplitude;
  if (cp.slot_max_m > cfg.regulator.max_slot_m) cp.slot_max_m = cfg.regulator.max_slot_m;
  auto mp = cfg.machine;
  mp.controller = cp;
  return mp;
}

control::SlideMachine::Params machine_params(const Settings& s, const Host& host) {
  return machine_params(s.rig, host);
}

double nominal_force_N(const RigConfig& cfg) {
  cutting::CuttingModel cut;
  cutting::Disturbances dist;
  sim::configure_as("material", [&] { cut.configure(cfg.cutting); });
  sim::configure_as("part", [&] { dist.configure(cfg.part); });
  const double rev_per_s = cfg.spindle_rpm / 60.0;
  const double speed_m_per_min = std::numbers::pi * cfg.diameter_m * cfg.spindle_rpm;
  const double s_rev = cfg.controller.feed_m_per_s * 1000.0 / rev_per_s;
  return cut.radial_force({dist.depth_profile(0.0), s_rev, speed_m_per_min,
                           dist.strength_factor(0.0), dist.wear_factor(0.0)});
}

}  // namespace lathectl::systems::a_pulse_feed
