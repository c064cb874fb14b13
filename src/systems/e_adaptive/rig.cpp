#include "systems/e_adaptive/rig.hpp"

#include "lathectl/control/adaptive_input.hpp"
#include "lathectl/sim/config_error.hpp"
#include "systems/e_adaptive/machine_params.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace lathectl::systems::e_adaptive {

namespace {
constexpr std::size_t kChannels = 22;
std::vector<sim::Channel> rig_channels() {
  return {{"time_s", "s"},
          {"z_mm", "mm"},
          {"pass", ""},
          {"depth_mm", "mm"},
          {"feed_per_rev_mm", "mm/rev"},
          {"feed_rate_mm_per_min", "mm/min"},
          {"force_parameter", "N or W"},
          {"force_parameter_true", "N or W"},
          {"force_Pz_N", "N"},
          {"force_Py_N", "N"},
          {"cut_power_kW", "kW"},
          {"spindle_power_kW", "kW"},
          {"spindle_rpm", "rpm"},
          {"speed_m_per_min", "m/min"},
          {"speed_opt_m_per_min", "m/min"},
          {"feed_cmd_mm_per_rev", "mm/rev"},
          {"tool_life_used", ""},
          {"strength_factor", ""},
          {"reason_code", ""},
          {"alarm", ""},
          {"feed_hold", ""},
          {"in_cut", ""}};
}
}  // namespace

Rig::WorstCase Rig::worst_case(const RigConfig& cfg, const cutting::CuttingModel& cut,
                                const cutting::Stock& stock) {
  const auto& d = cfg.disturbances;
  double hard = 1.0;
  for (const auto& h : d.hardness) hard = std::max(hard, h.value);
  const double t_max = stock.max_depth_mm() + 3.0 * d.random_sigma_mm;
  const double wear = 1.0 + d.wear_force_gain_per_mm * d.wear_VB0_mm;
  const double v = cfg.controller.speed_programmed_m_per_min;
  auto param = [&](double s) {
    const auto f = cut.forces({t_max, s, v, hard, wear});
    return cutting::force_parameter(cfg.force_parameter, f, cut.power_W(f, v));
  };
  WorstCase w{.depth_mm = t_max, .hardness = hard, .wear_factor = wear, .speed_m_per_min = v};
  double lo = cfg.controller.feed_min_mm_per_rev, hi = cfg.controller.feed_max_mm_per_rev;
  if (param(lo) > cfg.controller.load_limit) {
    w.at_min = true;
  } else if (param(hi) <= cfg.controller.load_limit) {
    lo = hi;
  } else {
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (lo + hi);
      (param(mid) > cfg.controller.load_limit ? hi : lo) = mid;
    }
  }
  w.feed_mm_per_rev = lo;
  w.parameter_at_feed = param(lo);
  return w;
}

void Rig::configure(const RigConfig& cfg, double dt, double record_interval, double max_duration) {
  if (!(dt > 0.0) || !(record_interval >= dt) || !(max_duration > 0.0))
    throw sim::ConfigError("run.record_interval_s",
                           "need step > 0, record interval ≥ step, duration > 0");
  cfg_ = cfg;
  dt_ = dt;
  max_t_ = max_duration;
  t_ = t_cut_ = life_used_ = life_used_nominal_ = removed_mm3_ = 0.0;
  step_ = 0;
  pass_ = 0;
  sound_ = true;
  first_hold_s_ = -1.0;
  record_every_ =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(record_interval / dt)));
  sim::configure_as("material", [&] { cut_.configure(cfg.cutting); });
  sim::configure_as("stock", [&] { stock_.configure(cfg.stock); });
  // The cutting process: the LinuxCNC plant's, its stock z the rig's z (machine z = −z). The
  // scenario's [[fault]] times are the run's (applied below), not counted from first contact.
  // The cutting process: the LinuxCNC plant's bar (lathe_process), its stock z the rig's z
  // (machine z = −z). The scenario's [[fault]] times are the run's (applied below), not counted
  // from first contact.
  cutting::CuttingProcess process = lathe_process(cfg);
  process.faults.clear();
  sim::configure_as("stock", [&] { plant_.configure(process, {}); });
  pin_ = {};
  pout_ = {};

  // The machine side a lathe runs, from the scenario as every host derives it (machine_params:
  // the LinuxCNC component and the optimiser call the same): sensor 4 is the dynamometer, or the
  // spindle drive's power meter (the cutting power at the spindle). The rig adds the stock model
  // on its own blank (z = 0 at the face) and, in the fixed mode, the program's worst-case feed.
  MachineHost host;
  if (cfg.force_parameter == cutting::ForceParameter::Power)
    host.load = MachineHost::Load::SpindlePower;  // sensor 4 is the drive's power meter
  if (cfg.worst_case_feed) host.feed_programmed_mm_per_rev = worst_case_feed(cfg, cut_, stock_);
  control::AdaptiveMachine::Params mp;
  sim::configure_as("controller", [&] { mp = machine_params(cfg, host); });
  const auto& cp = mp.controller;
  control_every_ =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(cp.period_s / dt)));
  if (std::abs(static_cast<double>(control_every_) * dt - cp.period_s) > 0.01 * cp.period_s)
    throw sim::ConfigError("run.step_s",
                           "the control period (controller.period_ms) must be a whole "
                           "number of steps, as on a machine's servo thread");
  sim::configure_as("controller", [&] { machine_.configure(mp); });
  // The machine's stock model is the plant's blank cut by the same tool position every step,
  // just after the plant (cut_step, then control_step): it takes the plant's cut instead of
  // cutting the same cells again (LathePlant::follow: the same numbers, checked at each cut).
  if (share_cut_) sim::configure_as("controller", [&] { machine_.follow_stock(plant_); });
  mout_ = {};
  sensor_held_ = 0.0;
  life_plan_min_ = cut_.tool_life_min(cp.speed_programmed_m_per_min, cp.feed_planned_mm_per_rev,
                                      cfg.planned_depth_mm);

  sim::configure_as("feed_axis", [&] { axis_.configure(cfg.axis, dt); });
  const auto& first = cfg.stock.passes.front();
  plan_pass(0);
  axis_.reset(z_approach_mm_ * 1e-3, 0.0);
  x_mm_ = x_down_mm_;
  x_rate_mm_s_ = 0.0;
  phase_ = Phase::Descend;
  sim::configure_as("spindle", [&] { spindle_.configure(cfg.spindle); });
  const double d0 = stock_.surface_diameter_mm(0, first.z_start_mm);
  const double rpm0 = std::clamp(cp.speed_programmed_m_per_min * 1000.0 / (std::numbers::pi * d0),
                                 cfg.spindle.min_rpm, cfg.spindle.max_rpm);
  spindle_.reset(rpm0);
  // Sensor 4 on power is the spindle's power meter: [sensor]'s lag, noise and range (a noiseless
  // meter read exactly the same in air at a steady speed, and the monitor called it stuck).
  sim::configure_as("sensor", [&] { power_meter_.configure(spindle_power_meter(cfg)); });
  power_meter_.reset(spindle_.electrical_power_W());
  rpm_cmd_ = rpm0;
  force_seen_ = 0.0;
  faults_.reset(0.0);
  acc_param_ = acc_pz_ = acc_py_ = acc_depth_ = acc_power_ = 0.0;
  acc_n_ = 0;
  load_rev_ = {};
  load_rev_.configure(dt, std::max(cfg.spindle.min_rpm, 1.0));
  // Streamed: rows go to the sinks the study attaches (metrics, channels.csv), not to memory;
  // the disk-space check of channels.csv bounds the duration instead of a row limit.
  rec_ = sim::Recorder::streamed(rig_channels());
}

void Rig::plan_pass(std::size_t k) noexcept {
  const auto& q = cfg_.stock.passes[k];
  const double r_n = plant_.nose_radius_mm();
  x_pass_mm_ = 0.5 * q.diameter_mm;
  // The nose's centre when the programmed point (the tool tip of the orientation) is at z_start.
  const double zc = plant_.nose_centre_stock_z_mm(-q.z_start_mm);
  // Material above the pass's radius before z_start, where the tool would come down and travel
  // in the approach: a shoulder. Come down above it at z_start and plunge there.
  const double before = plant_.max_radius_mm(zc - cfg_.approach_mm - r_n, zc - r_n);
  if (before > x_pass_mm_ + 1e-6) {
    z_approach_mm_ = q.z_start_mm;
    const double top = plant_.max_radius_mm(zc - r_n, zc + r_n);
    x_down_mm_ = top + cfg_.approach_mm;
    // The plunge's feed: what the pass's full depth takes at the limit (the handbook's force
    // law, V_p, nominal hardness and a sharp tool), set on the plunge as its feed_max (M68 E2 on
    // LinuxCNC). The plunge's chip is only as wide as the nose's engagement, so left free the
    // regulator raises the feed there and carries it into the full depth at the corner: on
    // e_worn_tool the per-revolution force then rose 10.0 % over the limit, against 7.1 %.
    const auto& cp = machine_.controller().params();
    const double depth = top - x_pass_mm_;
    auto param = [&](double f_rev) {
      const auto f = cut_.forces({depth, f_rev, cp.speed_programmed_m_per_min, 1.0, 1.0});
      return cutting::force_parameter(cfg_.force_parameter, f,
                                      cut_.power_W(f, cp.speed_programmed_m_per_min));
    };
    double lo = cp.feed_min_mm_per_rev, hi = cp.feed_max_mm_per_rev;
    if (param(hi) <= cp.load_limit) {
      lo = hi;
    } else if (param(lo) < cp.load_limit) {
      for (int i = 0; i < 50; ++i) {
        const double mid = 0.5 * (lo + hi);
        (param(mid) > cp.load_limit ? hi : lo) = mid;
      }
    }
    plunge_feed_mm_per_rev_ = lo;
  } else {
    z_approach_mm_ = q.z_start_mm - cfg_.approach_mm;
    x_down_mm_ = x_pass_mm_;
  }
}

Rig::Move Rig::move() const noexcept {
  Move m{.kind = Move::Kind::Turn, .pass = pass_};
  switch (phase_) {
    case Phase::Plunge:
      m = {Move::Kind::Plunge, pass_, x_pass_mm_, z_approach_mm_, plunge_feed_mm_per_rev_};
      break;
    case Phase::Turn:
      m.x_mm = x_pass_mm_;
      m.z_mm = pass_ < cfg_.stock.passes.size() ? cfg_.stock.passes[pass_].z_end_mm : 0.0;
      break;
    case Phase::Retract:
      m = {Move::Kind::Retract, pass_, x_clear_mm_, 0.0, 0.0};
      break;
    case Phase::Return:  // pass k's approach point, planned when the retract ended
      m = {Move::Kind::Return, pass_ + 1, x_clear_mm_, z_approach_mm_, 0.0};
      break;
    case Phase::Descend:
      m = {Move::Kind::Descend, pass_, x_down_mm_, z_approach_mm_, 0.0};
      break;
  }
  return m;
}

// step() in phases, in the order they run.

// The program, one pass after another: the next move once this one has arrived. False when the
// last pass has ended.
inline bool Rig::advance_program(double z_mm) noexcept {
  const double settle_mm_s = 1.0;  // the z axis has arrived: within 5 µm and below 1 mm/s
  const bool z_settled = std::abs(axis_.measured_velocity_m_per_s()) * 1e3 < settle_mm_s;
  switch (phase_) {
    case Phase::Plunge:
      if (x_mm_ <= x_pass_mm_) phase_ = Phase::Turn;
      break;
    case Phase::Turn:
      if (z_mm >= cfg_.stock.passes[pass_].z_end_mm) {
        if (pass_ + 1 >= cfg_.stock.passes.size()) {
          pass_ = cfg_.stock.passes.size();  // done
          return false;
        }
        phase_ = Phase::Retract;
        x_clear_mm_ = plant_.max_radius_mm(-1e300, 1e300) + cfg_.approach_mm;
      }
      break;
    case Phase::Retract:
      if (x_mm_ >= x_clear_mm_) {
        plan_pass(pass_ + 1);
        phase_ = Phase::Return;
      }
      break;
    case Phase::Return:
      if (std::abs(z_mm - z_approach_mm_) < 0.005 && z_settled) {
        ++pass_;
        phase_ = Phase::Descend;
      }
      break;
    case Phase::Descend:
      if (x_mm_ <= x_down_mm_) phase_ = x_down_mm_ > x_pass_mm_ ? Phase::Plunge : Phase::Turn;
      break;
  }
  return true;
}

// The cutting process at the tool's position, the tool's life it uses, the spindle under the
// cut's torque and the power meter on the drive.
inline void Rig::cut_step(double rpm, double z_mm) noexcept {
  // The cutting process at the tool's position (machine z = −z: the plant's stock runs to −z).
  pin_ = {x_mm_, -z_mm, rpm};
  plant_.step(pin_, dt_, pout_);
  const double depth = pout_.depth_mm;
  const double s = pout_.feed_per_rev_mm;
  const double v = pout_.speed_m_per_min;  // sensor 20 [m/min]
  const double strength = pout_.strength_factor;
  const cutting::Forces f{pout_.Pz_N, pout_.Py_N, 0.0};
  if (pout_.in_contact && s > 0.0 && v > 0.0) {
    t_cut_ += dt_;
    life_used_ += dt_ / (60.0 * cut_.tool_life_min(v, s, depth, strength));
    life_used_nominal_ += dt_ / (60.0 * cut_.tool_life_min(v, s, depth));  // as if h = 1
  }
  removed_mm3_ = pout_.removed_mm3;
  // The torque that supplies the cutting power Pz·V (V at the surface, x + t, as the plant
  // counts it): one radius for the power and the torque.
  const double torque = f.Pz * (x_mm_ + depth) * 1e-3;
  spindle_.step(dt_, rpm_cmd_, torque);
  power_meter_.step(dt_, spindle_.electrical_power_W());
}

// What the machine side reads: sensor 4 (held between control periods), the drive's power, the
// spindle, the axes and the program's line, speed and feed.
inline control::AdaptiveMachine::Input Rig::machine_input(double z_mm) const noexcept {
  const auto& cp = machine_.controller().params();
  control::AdaptiveMachine::Input in;
  in.nominal_period_s = dt_;
  in.force = sensor_held_;
  in.spindle_power_W = sensor_held_;
  if (cfg_.force_parameter != cutting::ForceParameter::Power)
    in.spindle_power_W = power_meter_.lagged();
  in.rpm = spindle_.rpm();
  // The program's speed: V_p at the surface the pass cuts, D_prev(z), as a programmer sets S for
  // the handbook's V at the work diameter (LinuxCNC's G96 holds V at the tool's radius x
  // instead, (x + t)/x higher at the surface).
  const double d_surface =
      stock_.surface_diameter_mm(std::min(pass_, cfg_.stock.passes.size() - 1), z_mm);
  in.rpm_programmed = std::clamp(cp.speed_programmed_m_per_min * 1000.0 /
                                     (std::numbers::pi * std::max(d_surface, 1e-3)),
                                 cfg_.spindle.min_rpm, cfg_.spindle.max_rpm);
  const double x_vel_mm_s = phase_ == Phase::Plunge ? x_rate_mm_s_ : 0.0;
  in.current_vel_mm_s = std::hypot(axis_.measured_velocity_m_per_s() * 1000.0, x_vel_mm_s);
  in.requested_vel = cp.feed_programmed_mm_per_rev;
  in.motion_type = static_cast<std::int32_t>(feeding() ? control::AdaptiveMachine::Motion::Feed
                                                       : control::AdaptiveMachine::Motion::Traverse);
  in.per_rev = true;
  in.x_mm = x_mm_;
  in.z_mm = -z_mm;
  in.cutting_speed_m_per_min = pout_.speed_m_per_min;  // sensor 20 [m/min]
  in.tool_number = 1;
  in.program_line = static_cast<std::int32_t>(pass_) + 1;
  in.max_override = cp.feed_max_mm_per_rev / cp.feed_programmed_mm_per_rev;
  if (phase_ == Phase::Plunge) in.feed_max_cmd = plunge_feed_mm_per_rev_;
  return in;
}

// The program: G95 at the programmed feed, G96 at V_p (the CNC's constant surface speed at the
// tool's diameter), one program line per pass. Sensor 4 is sampled at the control period (its
// noise is drawn per sample) and held between; the machine side runs every step.
inline void Rig::control_step(double z_mm) noexcept {
  if ((step_ - 1) % control_every_ == 0) {
    const double measured = cfg_.force_parameter == cutting::ForceParameter::Power
                                ? power_meter_.sample()
                                : pout_.force_measured;
    sensor_held_ = faults_.apply(cfg_.faults, t_, measured, cfg_.force_sensor.range * 2.0 + 1.0);
  }
  machine_.update(machine_input(z_mm), mout_);
  force_seen_ = mout_.load;
  if (mout_.control_period) rpm_cmd_ = mout_.spindle_speed_out;
  if (mout_.feed_hold && first_hold_s_ < 0.0) first_hold_s_ = t_;
}

// The axes: z a servo axis with its lag and encoder; x an ideal cross slide that stops on its
// target.
inline void Rig::move_axes(double z_mm) noexcept {
  const double feed_mm_s = mout_.feed_hold ? 0.0 : mout_.feed_per_rev_mm * spindle_.rpm() / 60.0;
  const double rapid_mm_s = cfg_.rapid_m_per_s * 1e3;
  double vz_mm_s = 0.0;
  x_rate_mm_s_ = 0.0;
  switch (phase_) {
    case Phase::Plunge:
      x_rate_mm_s_ = std::min(feed_mm_s, (x_mm_ - x_pass_mm_) / dt_);
      x_mm_ -= x_rate_mm_s_ * dt_;
      break;
    case Phase::Turn:
      vz_mm_s = feed_mm_s;
      break;
    case Phase::Retract:
      x_mm_ = std::min(x_mm_ + rapid_mm_s * dt_, x_clear_mm_);
      break;
    case Phase::Return:  // a position loop onto the approach point (20/s: no overshoot)
      vz_mm_s = std::clamp(20.0 * (z_approach_mm_ - z_mm), -rapid_mm_s, rapid_mm_s);
      break;
    case Phase::Descend:
      x_mm_ = std::max(x_mm_ - rapid_mm_s * dt_, x_down_mm_);
      break;
  }
  axis_.step(vz_mm_s * 1e-3);
}

// The step's values into the running means, and a recorded row every record_every_ steps.
inline void Rig::record_step(double z_mm) noexcept {
  const double s = pout_.feed_per_rev_mm;
  const double v = pout_.speed_m_per_min;
  const double strength = pout_.strength_factor;
  acc_param_ += pout_.force_parameter;
  (void)load_rev_.push(t_, pout_.force_parameter, spindle_.rpm(),
                       pout_.depth_mm > 0.0 && pout_.feed_per_rev_mm > 0.0);
  acc_pz_ += pout_.Pz_N;
  acc_py_ += pout_.Py_N;
  acc_depth_ += pout_.depth_mm;
  acc_power_ += pout_.cut_power_W;
  ++acc_n_;
  if (!std::isfinite(spindle_.omega()) || !std::isfinite(axis_.position_m())) sound_ = false;
  if (step_ % record_every_ == 0) {
    const double n = static_cast<double>(acc_n_);
    const std::array<double, kChannels> row{t_,
                                            z_mm,
                                            static_cast<double>(pass_),
                                            acc_depth_ / n,
                                            s,
                                            axis_.measured_velocity_m_per_s() * 60000.0,
                                            force_seen_,
                                            acc_param_ / n,
                                            acc_pz_ / n,
                                            acc_py_ / n,
                                            acc_power_ / n * 1e-3,
                                            spindle_.electrical_power_W() * 1e-3,
                                            spindle_.rpm(),
                                            v,
                                            mout_.speed_opt_m_per_min,
                                            mout_.feed_per_rev_mm,
                                            life_used_,
                                            strength,
                                            static_cast<double>(mout_.alarm
                                                                    ? mout_.alarm_reason
                                                                    : mout_.reason),
                                            mout_.alarm ? 1.0 : 0.0,
                                            mout_.feed_hold ? 1.0 : 0.0,
                                            mout_.in_cut ? 1.0 : 0.0};
    rec_.push_row(row);
    acc_param_ = acc_pz_ = acc_py_ = acc_depth_ = acc_power_ = 0.0;
    acc_n_ = 0;
  }
}

bool Rig::step() noexcept {
  if (finished() || t_ >= max_t_) return false;
  t_ += dt_;
  ++step_;
  const double rpm = spindle_.rpm();
  const double z_mm = axis_.position_m() * 1000.0;
  if (!advance_program(z_mm)) return false;
  cut_step(rpm, z_mm);
  control_step(z_mm);
  move_axes(z_mm);
  record_step(z_mm);
  return true;
}

void Rig::run() noexcept {
  while (step()) {
  }
}

}  // namespace lathectl::systems::e_adaptive
