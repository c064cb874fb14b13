#include "systems/e_adaptive/rig.hpp"

#include "lathectl/control/adaptive_input.hpp"
#include "lathectl/sim/config_error.hpp"

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

double Rig::worst_case_feed(const RigConfig& cfg, const cutting::CuttingModel& cut,
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
  double lo = cfg.controller.feed_min_mm_per_rev, hi = cfg.controller.feed_max_mm_per_rev;
  if (param(lo) > cfg.controller.force_limit) return lo;
  if (param(hi) <= cfg.controller.force_limit) return hi;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (param(mid) > cfg.controller.force_limit ? hi : lo) = mid;
  }
  return lo;
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
  phi_ = 0.0;
  sound_ = true;
  first_hold_s_ = -1.0;
  record_every_ =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(record_interval / dt)));
  sim::configure_as("material", [&] { cut_.configure(cfg.cutting); });
  sim::configure_as("stock", [&] { stock_.configure(cfg.stock); });
  auto dp = cfg.disturbances;
  dp.depth_steps.clear();
  dp.runout_mm = 0.0;
  sim::configure_as("stock", [&] { dist_.configure(dp); });

  auto cp = cfg.controller;
  if (cfg.worst_case_feed) {
    cp.feed_programmed_mm_per_rev = worst_case_feed(cfg, cut_, stock_);
    cp.feed_min_mm_per_rev = std::min(cp.feed_min_mm_per_rev, cp.feed_programmed_mm_per_rev);
  }
  cp.air_feed_mm_per_rev = std::max(cp.air_feed_mm_per_rev, 1e-6);
  control_every_ =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(cp.period_s / dt)));
  if (std::abs(static_cast<double>(control_every_) * dt - cp.period_s) > 0.01 * cp.period_s)
    throw sim::ConfigError("run.step_s",
                           "the control period (controller.period_ms) must be a whole "
                           "number of steps, as on a machine's servo thread");
  // The machine side a lathe runs (the LinuxCNC component runs the same object): sensor 4 is
  // the dynamometer, or the spindle drive's power meter (the cutting power at the spindle).
  control::AdaptiveMachine::Params mp;
  mp.controller = cp;
  mp.parameter = cfg.force_parameter;
  mp.power_sensor = cfg.force_parameter == cutting::ForceParameter::Power;
  mp.spindle = cfg.spindle;
  mp.power_lag_s = cfg.power_meter.time_constant_s;
  mp.rating.limit_max = 1e300;  // the program sets nothing: the scenario's settings
  mp.rating.feed_max_mm_per_rev = 1e300;
  sim::configure_as("controller", [&] { machine_.configure(mp); });
  mout_ = {};
  sensor_held_ = 0.0;
  life_plan_min_ = cut_.tool_life_min(cp.speed_programmed_m_per_min, cp.feed_planned_mm_per_rev,
                                      cfg.planned_depth_mm);

  sim::configure_as("feed_axis", [&] { axis_.configure(cfg.axis, dt); });
  const auto& first = cfg.stock.passes.front();
  axis_.reset((first.z_start_mm - cfg.approach_mm) * 1e-3, 0.0);
  sim::configure_as("spindle", [&] { spindle_.configure(cfg.spindle); });
  const double d0 = stock_.surface_diameter_mm(0, first.z_start_mm);
  const double rpm0 = std::clamp(cp.speed_programmed_m_per_min * 1000.0 / (std::numbers::pi * d0),
                                 cfg.spindle.min_rpm, cfg.spindle.max_rpm);
  spindle_.reset(rpm0);
  sim::configure_as("sensor", [&] { force_sensor_.configure(cfg.force_sensor); });
  force_sensor_.reset(0.0);
  const double rev_steps = 60.0 / cfg.spindle.min_rpm / dt;
  if (rev_steps > 2e7)
    throw sim::ConfigError("run.step_s",
                           "one revolution at the spindle's min_rpm spans more than 2e7 steps");
  const auto hist = static_cast<std::size_t>(rev_steps) + 8;
  hist_theta_.assign(hist, 0.0);
  hist_z_.assign(hist, 0.0);
  head_ = tail_ = count_ = 0;
  theta_ = 0.0;
  contact_ = false;
  sim::configure_as("sensor", [&] { power_meter_.configure(cfg.power_meter); });
  power_meter_.reset(spindle_.electrical_power_W());
  rpm_cmd_ = rpm0;
  in_block_ = true;
  force_seen_ = 0.0;
  faults_.reset(0.0);
  acc_param_ = acc_pz_ = acc_py_ = acc_depth_ = acc_power_ = 0.0;
  acc_n_ = 0;
  // Streamed: rows go to the sinks the study attaches (metrics, channels.csv), not to memory;
  // the disk-space check of channels.csv bounds the duration instead of a row limit.
  rec_ = sim::Recorder::streamed(rig_channels());
}

double Rig::chip_thickness_mm(double z_mm) noexcept {
  const std::size_t n = hist_theta_.size();
  head_ = (head_ + 1) % n;
  hist_theta_[head_] = theta_;
  hist_z_[head_] = z_mm;
  if (count_ < n) ++count_;
  const double target = theta_ - 2.0 * std::numbers::pi;
  if (count_ < 2 || hist_theta_[(head_ + n - (count_ - 1)) % n] > target) {
    tail_ = (head_ + n - (count_ - 1)) % n;  // less than one revolution recorded yet
    return 0.0;
  }
  while (hist_theta_[(tail_ + 1) % n] <= target) tail_ = (tail_ + 1) % n;
  const std::size_t next = (tail_ + 1) % n;
  const double span = hist_theta_[next] - hist_theta_[tail_];
  const double w = span > 0.0 ? (target - hist_theta_[tail_]) / span : 0.0;
  double z_back = hist_z_[tail_] + w * (hist_z_[next] - hist_z_[tail_]);
  if (contact_) z_back = std::max(z_back, z_contact_mm_);
  return std::max(z_mm - z_back, 0.0);
}

bool Rig::step() noexcept {
  if (finished() || t_ >= max_t_) return false;
  t_ += dt_;
  ++step_;
  const double rpm = spindle_.rpm();
  phi_ = std::fmod(phi_ + spindle_.omega() * dt_, 2.0 * std::numbers::pi);
  const auto& pass = cfg_.stock.passes[pass_];
  const double z_mm = axis_.position_m() * 1000.0;

  // Program: the feed block of this pass ends at its z_end; then a rapid to the next start.
  if (in_block_ && z_mm >= pass.z_end_mm) in_block_ = false;
  if (!in_block_) {
    if (pass_ + 1 >= cfg_.stock.passes.size()) {
      pass_ = cfg_.stock.passes.size();  // done
      return false;
    }
    if (z_mm <= cfg_.stock.passes[pass_ + 1].z_start_mm - cfg_.approach_mm) {
      ++pass_;
      in_block_ = true;
    }
  }

  // Cutting process.
  theta_ += spindle_.omega() * dt_;
  double depth = in_block_ ? stock_.depth_mm(pass_, z_mm, phi_) : 0.0;
  if (depth > 0.0) depth = std::max(depth + dist_.random_allowance_mm(z_mm), 0.0);
  if (depth > 0.0 && !contact_) {
    contact_ = true;  // the tool meets material: the chip builds up from here
    z_contact_mm_ = z_mm;
  } else if (!in_block_ || stock_.depth_mm(pass_, z_mm, 0.5 * std::numbers::pi) <= 0.0) {
    contact_ = false;  // out of material (between passes, or past the stock)
  }
  const double s = chip_thickness_mm(z_mm);
  const double d_surface = stock_.surface_diameter_mm(pass_, z_mm);
  const double v = std::numbers::pi * d_surface * rpm / 1000.0;  // sensor 20 [m/min]
  const double strength = dist_.strength_factor(z_mm);
  cutting::Forces f{};
  if (depth > 0.0 && s > 0.0) {
    f = cut_.forces({depth, s, v, strength, dist_.wear_factor(t_cut_)});
    t_cut_ += dt_;
    life_used_ += dt_ / (60.0 * cut_.tool_life_min(v, s, depth, strength));
    life_used_nominal_ += dt_ / (60.0 * cut_.tool_life_min(v, s, depth));  // as if h = 1
    removed_mm3_ += depth * s * (rpm / 60.0) * std::numbers::pi * (d_surface - depth) * dt_;
  }
  const double cut_power = cut_.power_W(f, v);
  // The torque that supplies the cutting power Pz·V (V at the surface, as the LinuxCNC plant
  // and the handbook count it): one radius for the power and the torque.
  const double torque = f.Pz * 0.5 * d_surface * 1e-3;
  spindle_.step(dt_, rpm_cmd_, torque);
  const double true_param = cutting::force_parameter(cfg_.force_parameter, f, cut_power);
  power_meter_.step(dt_, spindle_.electrical_power_W());
  if (cfg_.force_parameter != cutting::ForceParameter::Power) force_sensor_.step(dt_, true_param);

  // The program: G95 at the programmed feed, G96 at V_p (the CNC's constant surface speed at
  // the tool's diameter), one program line per pass. Sensor 4 is sampled at the control period
  // (its noise is drawn per sample) and held between.
  if ((step_ - 1) % control_every_ == 0) {
    const double measured = cfg_.force_parameter == cutting::ForceParameter::Power
                                ? power_meter_.sample()
                                : force_sensor_.sample();
    sensor_held_ = faults_.apply(cfg_.faults, t_, measured, cfg_.force_sensor.range * 2.0 + 1.0);
  }
  const auto& cp = machine_.controller().params();
  control::AdaptiveMachine::Input in;
  in.nominal_period_s = dt_;
  in.force = sensor_held_;
  in.spindle_power_W = sensor_held_;
  if (cfg_.force_parameter != cutting::ForceParameter::Power)
    in.spindle_power_W = power_meter_.lagged();
  in.rpm = spindle_.rpm();
  in.rpm_programmed = std::clamp(cp.speed_programmed_m_per_min * 1000.0 /
                                     (std::numbers::pi * std::max(d_surface, 1e-3)),
                                 cfg_.spindle.min_rpm, cfg_.spindle.max_rpm);
  in.current_vel_mm_s = axis_.measured_velocity_m_per_s() * 1000.0;
  in.requested_vel = cp.feed_programmed_mm_per_rev;
  in.motion_type = static_cast<std::int32_t>(in_block_ ? control::AdaptiveMachine::Motion::Feed
                                                       : control::AdaptiveMachine::Motion::Traverse);
  in.per_rev = true;
  in.x_mm = 0.5 * d_surface;
  in.z_mm = z_mm;
  in.cutting_speed_m_per_min = std::numbers::pi * d_surface * spindle_.rpm() / 1000.0;
  in.tool_number = 1;
  in.program_line = static_cast<std::int32_t>(pass_) + 1;
  in.max_override = cp.feed_max_mm_per_rev / cp.feed_programmed_mm_per_rev;
  machine_.update(in, mout_);
  force_seen_ = mout_.load;
  if (mout_.control_period) rpm_cmd_ = mout_.spindle_speed_out;
  if (mout_.feed_hold && first_hold_s_ < 0.0) first_hold_s_ = t_;
  double v_cmd = 0.0;
  if (!in_block_) {
    v_cmd = -cfg_.rapid_m_per_s;
  } else if (!mout_.feed_hold) {
    v_cmd = mout_.feed_per_rev_mm * 1e-3 * spindle_.rpm() / 60.0;
  }
  axis_.step(v_cmd);

  acc_param_ += true_param;
  acc_pz_ += f.Pz;
  acc_py_ += f.Py;
  acc_depth_ += depth;
  acc_power_ += cut_power;
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
  return true;
}

void Rig::run() noexcept {
  while (step()) {
  }
}

}  // namespace lathectl::systems::e_adaptive
