#include "lathectl/control/modulation_machine.hpp"

#include <stdexcept>

#include "lathectl/core/parameter_error.hpp"

namespace lathectl::control {

void ModulationMachine::configure(const Params& p) {
  // The chains' own errors name no parameter: they are this machine's "vibration" and "power".
  try {
    chain_.configure(p.vibration);
  } catch (const core::ParameterError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    throw core::ParameterError("vibration", e.what());
  }
  try {
    power_.configure(p.power, p.module.period_s);
  } catch (const std::invalid_argument& e) {
    throw core::ParameterError("power", e.what());
  }
  module_.configure(p.module);  // its own parameters' names
  p_ = p;
  idle_known_ = !p.power.idle_table_rpm.empty();
  out_ = {};
  configured_ = true;
}

void ModulationMachine::update(const Input& in) noexcept {
  if (!configured_) {
    out_ = {};
    return;
  }
  power_.update(in.motor_power_W, in.rpm, in.idle_block);
  idle_known_ = idle_known_ || in.idle_block;

  ModulatedFeedController::Input mi;
  mi.a0_m = in.external_detectors ? in.a0_m : chain_.a0_m();
  mi.omega_d_rad_per_s = in.external_detectors ? in.omega_d_rad_per_s : chain_.omega_d();
  // Without an idle reference N_m − 0 would size the idle losses as cutting force: no force
  // known, no plan (the planner says modulation_no_force; the machine says why).
  mi.cut_power_W = idle_known_ ? power_.cutting_W() : 0.0;
  mi.speed_m_per_min = in.speed_m_per_min;
  mi.rpm = in.rpm;
  for (int k = 0; k < 2; ++k) {
    mi.feed_programmed_mm_per_min[k] = in.feed_programmed_mm_per_min[k];
    mi.path_mm[k] = in.path_mm[k];
  }
  mi.feed_block = in.feed_block;
  mi.source = in.source;
  mi.turret = in.turret;
  mi.programmed = in.programmed;
  ModulatedFeedController::Output& mo = out_;
  module_.update(mi, mo);
  if (mo.reason == Reason::ModulationNoForce && !idle_known_) mo.reason = Reason::ModulationNoIdle;
  out_.a0_m = mi.a0_m;
  out_.omega_d_rad_per_s = mi.omega_d_rad_per_s;
  out_.cut_power_W = power_.cutting_W();
  out_.idle_power_W = power_.idle_W();
  out_.idle_known = idle_known_;
}

}  // namespace lathectl::control
