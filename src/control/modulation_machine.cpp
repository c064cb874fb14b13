#include "lathectl/control/modulation_machine.hpp"

#include <algorithm>
#include <cmath>
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
  if (!(p.ceiling >= 1.0 && p.ceiling <= 100.0))
    throw core::ParameterError("ceiling", "ceiling must be in 1 … 100");
  if (p.output != FeedOutput::Factor && p.ceiling != 1.0)
    throw core::ParameterError("ceiling", "a ceiling only with the factor output");
  module_.configure(p.module);  // its own parameters' names
  p_ = p;
  idle_known_ = !p.power.idle_table_rpm.empty();
  out_ = {};
  out_.factor = p.output == FeedOutput::Offset ? 1.0 : 1.0 / p.ceiling;
  turret_ = Turret::Right;
  ratio_ = 0.0;
  path_mm_ = 0.0;
  planned_mm_[0] = planned_mm_[1] = 0.0;
  planned_seen_ = false;
  configured_ = true;
}

void ModulationMachine::servo(const Servo& in) noexcept {
  if (!configured_) return;
  if (!in.on) ratio_ = 0.0;
  const bool offset = p_.output == FeedOutput::Offset;
  // The flag moves the offset to the other turret's axis only once the offset is 0, asked and
  // applied (out of feed blocks, when LinuxCNC's offset planner has brought the axis back): an
  // axis whose offset LinuxCNC stops planning holds it.
  const double applied = in.applied_offset_mm[turret_ == Turret::Left ? 1 : 0];
  if (!offset || (out_.offset_mm == 0.0 && std::abs(applied) < 0.5 * kOffsetResolution_mm))
    turret_ = in.turret;
  const int t = turret_ == Turret::Left ? 1 : 0;
  if (offset) {
    // The axis moves at its planned velocity × S/S_p: the offset takes the difference. Not
    // modulating (the module off or released) in a feed block, it returns to 0 at kOffsetReturn
    // of the planned speed (a step back in the cut would be a chip the program never asked for;
    // held, it would leave the turrets' relative axial position — the chip split of feed
    // division — off the program's); out of feed blocks at once, LinuxCNC's offset planner
    // moving the axis back at its OFFSET_AV_RATIO share of the axis's limits. The planned
    // velocity: the planned position differentiated; the first period: 0.
    const double v = planned_seen_ ? (in.planned_mm[t] - planned_mm_[t]) / in.dt_s : 0.0;
    planned_mm_[0] = in.planned_mm[0];
    planned_mm_[1] = in.planned_mm[1];
    planned_seen_ = true;
    out_.axis_vel_mm_per_s = v;
    const bool modulating = in.feed_block && ratio_ > 0.0;
    double& off = out_.offset_mm;
    if (modulating) {
      off += (ratio_ - 1.0) * v * in.dt_s;
    } else if (in.feed_block) {
      const double back = kOffsetReturn * std::abs(v) * in.dt_s;
      off = std::clamp(0.0, off - back, off + back);
    } else {
      off = 0.0;
    }
    path_mm_ += in.feed_block ? std::abs(v) * (modulating ? ratio_ : 1.0) * in.dt_s : 0.0;
  } else if (in.on && p_.output == FeedOutput::Factor) {
    path_mm_ += in.feed_block ? std::abs(in.path_velocity_mm_per_s) * in.dt_s : 0.0;
  }
  if (!in.on) {
    out_.factor = offset ? 1.0 : 1.0 / p_.ceiling;
    out_.engaged = false;
    out_.feed_ratio = 1.0;
  }
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
  // The F conversion: the block's feed in mm/min; the mean feed to keep is that over the
  // ceiling (Factor: the program's F is the ceiling, LinuxCNC clipping the factor at 1).
  const double f_prog =
      in.feed_per_rev ? in.feed_requested * in.feed_rpm : in.feed_requested * 60.0;
  const double mean = f_prog / p_.ceiling;
  for (int k = 0; k < 2; ++k) {
    mi.feed_programmed_mm_per_min[k] = k < in.turrets ? mean : 0.0;
    mi.path_mm[k] = in.path_mm[k];
  }
  mi.feed_block = in.feed_block && mean > 0.0;
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
  // The feed out: S(t)/S_p of the flagged turret, and the factor S(t)/F (≤ 1).
  const double feed = mo.feed_mm_per_min[in.turret == Turret::Left ? 1 : 0];
  out_.mean_feed_mm_per_min = mean;
  ratio_ = mo.engaged && mean > 0.0 ? std::max(0.0, feed / mean) : 0.0;
  out_.feed_ratio = ratio_ > 0.0 ? ratio_ : 1.0;
  out_.factor = p_.output == FeedOutput::Offset ? 1.0
                : f_prog > 0.0                  ? std::clamp(feed / f_prog, 0.0, 1.0)
                                                : 1.0 / p_.ceiling;
}

}  // namespace lathectl::control
