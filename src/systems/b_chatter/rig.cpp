#include "systems/b_chatter/rig.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "lathectl/core/first_order_lag.hpp"
#include "lathectl/sim/config_error.hpp"
#include "systems/b_chatter/machine_params.hpp"

namespace lathectl::systems::b_chatter {

namespace {

constexpr double kPi = std::numbers::pi;

std::vector<sim::Channel> rig_b_channels() {
  return {{"time_s", "s"},
          {"z1_mm", "mm"},
          {"z2_mm", "mm"},
          {"y_um", "um"},
          {"y_highpass_um", "um"},
          {"a0_um", "um"},
          {"omega_d_Hz", "Hz"},
          {"feed1_mm_per_min", "mm/min"},
          {"feed2_mm_per_min", "mm/min"},
          {"feed1_cmd_mm_per_min", "mm/min"},
          {"feed2_cmd_mm_per_min", "mm/min"},
          {"chip1_mm", "mm"},
          {"chip2_mm", "mm"},
          {"depth1_mm", "mm"},
          {"depth2_mm", "mm"},
          {"radial1_N", "N"},
          {"radial2_N", "N"},
          {"cut_power_W", "W"},
          {"cut_power_measured_W", "W"},
          {"spindle_power_W", "W"},
          {"spindle_rpm", "rpm"},
          {"engaged", ""},
          {"reason_code", ""},
          {"S_min_mm_per_min", "mm/min"},
          {"dS_mm_per_min", "mm/min"},
          {"dl_mm", "mm"},
          {"n_s", ""},
          {"inter_tool_delay_rev", "rev"}};
}

}  // namespace

double Rig::max_step_s(const RigConfig& cfg, double* f_Hz) {
  const double L_mm = cfg.part.length_m * 1e3;
  if (!(cfg.z_end_mm < L_mm && cfg.z_end_mm > cfg.z_start_mm))
    throw sim::ConfigError("cut.z_end_mm",
                           "the cut must run between the centres: 0 < z_start < z_end < length");
  if (!(cfg.modes >= 1 && cfg.modes <= dynamics::TwinTurretCut::kMaxModes))
    throw sim::ConfigError("part.modes", "modes must be in 1..6");
  (void)dynamics::beam_modes_at(cfg.part, cfg.z_start_mm * 1e-3, cfg.modes);  // validates
  // Process stiffness: the radial force per metre of depth (Kienzle: linear in the depth) at the
  // whole programmed feed per tool (an upper bound for feed division's half chips).
  auto cp = cfg.cutting;
  cp.form = cutting::ForceForm::Kienzle;
  cutting::CuttingModel model;
  model.configure(cp);
  const double v = kPi * cfg.part.diameter_m * cfg.rpm;
  const int tools = cfg.setup == TwinSetup::Single ? 1 : 2;
  const double k_p =
      tools * model.forces({1.0, cfg.feed_mm_per_rev, v, 1.0, 1.0}).Py / 1e-3;  // N/m
  const double z0 = cfg.z_start_mm, z1 = cfg.modes_follow_tool ? cfg.z_end_mm : cfg.z_start_mm;
  double f_ref = 0.0;
  for (int j = 1; j <= cfg.modes; ++j) {
    double k_min = std::numeric_limits<double>::infinity();
    dynamics::BeamModeAt bm{};
    for (int i = 0; i <= 64; ++i) {
      const double x_mm = std::clamp(z0 + (z1 - z0) * i / 64.0, 1.0, L_mm - 1.0);
      bm = dynamics::beam_mode_at(cfg.part, x_mm * 1e-3, j);
      if (bm.shape != 0.0) k_min = std::min(k_min, bm.mode.stiffness_N_per_m);
    }
    const double z = bm.mode.damping_ratio;
    if (j > 1 && 2.0 * k_min * z * (1.0 + z) > 4.0 * k_p) continue;
    f_ref = std::max(f_ref, bm.mode.natural_frequency_Hz * std::sqrt(1.0 + 2.0 * z));
  }
  for (const auto& m : cfg.tool_modes) {
    const double c2 = std::cos(m.angle_rad) * std::cos(m.angle_rad);
    const double z = m.damping_ratio;
    if (!(c2 > 1e-12) || 2.0 * m.stiffness_N_per_m / c2 * z * (1.0 + z) > 4.0 * k_p) continue;
    f_ref = std::max(f_ref, m.natural_frequency_Hz * std::sqrt(1.0 + 2.0 * z));
  }
  if (f_Hz) *f_Hz = f_ref;
  return 0.2 / (2.0 * kPi * f_ref);
}

void Rig::configure(const RigConfig& cfg, double dt, double record_interval, double max_duration) {
  if (!(dt > 0.0 && record_interval >= dt && max_duration > 0.0))
    throw sim::ConfigError(
        "run.record_interval_s",
        "dt, record interval and duration must be positive (record interval ≥ dt)");
  const double L_mm = cfg.part.length_m * 1e3;
  if (!(cfg.z_end_mm < L_mm && cfg.z_end_mm > cfg.z_start_mm))
    throw sim::ConfigError("cut.z_end_mm",
                           "the cut must run between the centres: 0 < z_start < z_end < length");
  {
    double f = 0.0;
    const double lim = max_step_s(cfg, &f);
    if (!(dt <= lim))
      throw sim::ConfigError("run.step_s", "step " + std::to_string(dt) +
                                               " s too coarse for the part's chatter near " +
                                               std::to_string(f) + " Hz: use a step ≤ " +
                                               std::to_string(lim) + " s");
  }
  if (!(cfg.approach_mm >= 0.0 && cfg.idle_block_s >= 0.0))
    throw sim::ConfigError("cut", "approach and idle block must be non-negative");
  if (!(cfg.feed_drive_bandwidth_Hz > 0.0))
    throw sim::ConfigError("cut.feed_drive_bandwidth_Hz", "feed drive bandwidth must be positive");
  cfg_ = cfg;
  dt_ = dt;
  max_t_ = max_duration;
  t_ = 0.0;
  step_ = 0;
  since_control_ = since_chain_ = since_record_ = 0;
  done_ = false;
  t_cut_start_ = engaged_at_ = -1.0;
  theta_ = 0.0;
  record_every_ =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(record_interval / dt)));
  chain_every_ =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(kSamplePeriod_s / dt)));
  control_every_ =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(kModulePeriod_s / dt)));

  const dynamics::TwinTurretCut::Params pp = cut_params(cfg);
  sim::configure_as("cut", {{"tool2_lag_mm", "cut.tool2_lag_mm"}, {"step", "run.step_s"}},
               [&] { process_.configure(pp, dt); });
  n_tools_ = process_.tools();
  for (int i = 0; i < 2; ++i) {
    turrets_[i] = Turret{};
    turrets_[i].z0_mm = cfg.z_start_mm - cfg.approach_mm;
  }
  if (cfg.setup != TwinSetup::Single) turrets_[1].z0_mm -= cfg.tool2_lag_mm;
  for (Turret& tu : turrets_) tu.z_mm = tu.z0_mm;
  drive_lag_ = core::FirstOrderLag::with_decay(  // τ = 1/(2π·bandwidth)
      std::exp(-2.0 * kPi * cfg.feed_drive_bandwidth_Hz * dt));

  cfg_.vibration.sample_period_s = dt * static_cast<double>(chain_every_);
  sim::configure_as("vibration_sensor",
                    [&] { highpass_.configure(cfg_.vibration.highpass_Hz, dt); });
  y_hp_ = 0.0;

  sim::configure_as("spindle", [&] { spindle_.configure(cfg.spindle); });
  spindle_.reset(cfg.rpm);
  // The CNC's side: the chains and the planner as one machine, the one LinuxCNC runs, with the
  // parameters every host derives (machine_params.cpp), at the periods this step allows; the
  // feeds go to the turrets' drives.
  const auto mp = machine_params(cfg, Host{.module_period_s = dt * static_cast<double>(control_every_),
                                           .sample_period_s = cfg_.vibration.sample_period_s});
  sim::configure_as("modulation",
                    {{"vibration", "vibration_sensor"},
                     {"power", "power_sensor"},
                     {"period_s", "run.step_s"},
                     {"coefficient", "modulation.coefficient"},
                     {"part_mass_kg", "modulation.part_mass_kg"},
                     {"radial_force_ratio", "modulation.radial_force_ratio"},
                     {"force_feed_exponent", "modulation.force_feed_exponent"},
                     {"modulation_frequency_Hz", "modulation.modulation_frequency_Hz"},
                     {"drive_bandwidth_Hz", "cut.feed_drive_bandwidth_Hz"},
                     {"n_s", "modulation.n_s"},
                     {"resolution_mm", "modulation.resolution_um"},
                     {"s_min_fraction", "modulation.s_min_fraction"},
                     {"s_max_fraction", "modulation.s_max_fraction"},
                     {"engage_time_s", "modulation.engage_time_ms"},
                     {"release_time_s", "modulation.release_time_ms"},
                     {"replan_period_s", "modulation.replan_period_s"}},
                    [&] { machine_.configure(mp); });
  const double cut_time = (cfg.z_end_mm - cfg.z_start_mm + cfg.approach_mm + cfg.tool2_lag_mm) /
                          (cfg.feed_mm_per_rev * cfg.rpm / 60.0);
  max_t_ = std::min(max_duration, cfg.idle_block_s + 1.5 * cut_time + 1.0);
  max_rows_ = max_t_ / (dt * static_cast<double>(record_every_)) + 2.0;
  if (streamed_) {  // bounded by the disk-space check of what the study streams
    // 2^16 values per level (A and E: 2^14): B's chatter (hundreds of Hz at 1 kHz recording)
    // shows only in the recorded samples, and its examples record up to 45 000 rows; 28 channels
    // of float pairs keep ~0.7 MB each.
    rec_ = sim::Recorder::streamed(rig_b_channels(), {}, plots_ ? std::size_t{1} << 16 : 0);
    return;
  }
  if (!(max_rows_ <= 5e6))
    throw sim::ConfigError("run.record_interval_s",
                           "more than 5e6 recorded rows: raise run.record_interval_s");
  rec_ = sim::Recorder(rig_b_channels(), static_cast<std::size_t>(max_rows_));
}

[[gnu::flatten]] bool Rig::step() noexcept {
  if (done_ || t_ >= max_t_ || !process_.sound()) return false;
  const bool idle_block = t_ < cfg_.idle_block_s;
  const bool feed_block = !idle_block;
  if (feed_block && t_cut_start_ < 0.0) t_cut_start_ = t_;

  if (since_control_ == 0) {  // step_ % control_every_ == 0, without a 64-bit division
    // The servo period as the machine runs it (the feeds go to the drives: the flag's turret at
    // once, the turrets' paths measured below), then the module period.
    control::ModulationMachine::Servo sv;
    sv.dt_s = dt_ * static_cast<double>(control_every_);
    sv.feed_block = feed_block;
    sv.turret = cfg_.turret;
    machine_.servo(sv);
    const double rpm = spindle_.rpm();
    control::ModulationMachine::Input in;
    in.motor_power_W = spindle_.electrical_power_W();
    in.idle_block = idle_block;
    in.rpm = rpm;
    in.speed_m_per_min = kPi * cfg_.part.diameter_m * rpm;
    // The program's feed per revolution at the programmed speed (the machine converts it).
    in.feed_requested = cfg_.feed_mm_per_rev;
    in.feed_per_rev = true;
    in.feed_rpm = cfg_.rpm;
    in.turrets = n_tools_;
    in.path_mm[0] = turrets_[0].z_mm - turrets_[0].z0_mm;
    in.path_mm[1] = turrets_[1].z_mm - turrets_[1].z0_mm;
    in.feed_block = feed_block;
    in.source = cfg_.source;
    in.turret = machine_.turret();
    in.programmed = cfg_.programmed;
    machine_.update(in);
    const auto& mo = machine_.output();
    if (mo.engaged && engaged_at_ < 0.0) engaged_at_ = t_;
    for (int i = 0; i < 2; ++i)
      turrets_[i].cmd_mm_per_min = feed_block && i < n_tools_ ? mo.feed_mm_per_min[i] : 0.0;
  }

  // Feed drives, spindle, cutting position.
  const auto& drive = drive_lag_;
  for (int i = 0; i < n_tools_; ++i) {
    Turret& tu = turrets_[i];
    tu.v_mm_per_min = drive.step_increment(tu.v_mm_per_min, tu.cmd_mm_per_min);
    tu.z_mm += tu.v_mm_per_min / 60.0 * dt_;
  }
  spindle_.step(dt_, cfg_.rpm, process_.torque_N_m());
  theta_ += spindle_.omega() * dt_;
  // Cutting at each edge, then the part's response to the radial forces.
  const double z[2] = {turrets_[0].z_mm, turrets_[1].z_mm};
  process_.step(theta_, spindle_.rpm(), z);
  const double y = process_.y_m();
  y_hp_ = highpass_.step(y);
  if (since_chain_ == 0) machine_.sense(y);

  if (since_record_ == 0) {
    const double cut_power = process_.power_W(spindle_.rpm());
    const auto& mo = machine_.output();
    const auto& pl = mo.plan;
    const double row[] = {t_,
                          turrets_[0].z_mm,
                          turrets_[1].z_mm,
                          y * 1e6,
                          y_hp_ * 1e6,
                          machine_.chain().a0_m() * 1e6,
                          machine_.chain().omega_d() / (2.0 * kPi),
                          turrets_[0].v_mm_per_min,
                          turrets_[1].v_mm_per_min,
                          turrets_[0].cmd_mm_per_min,
                          turrets_[1].cmd_mm_per_min,
                          process_.cutting(0) ? process_.chip_mm(0) : 0.0,
                          n_tools_ > 1 && process_.cutting(1) ? process_.chip_mm(1) : 0.0,
                          process_.cutting(0) ? process_.depth_mm(0) : 0.0,
                          n_tools_ > 1 && process_.cutting(1) ? process_.depth_mm(1) : 0.0,
                          process_.radial_N(0),
                          n_tools_ > 1 ? process_.radial_N(1) : 0.0,
                          cut_power,
                          machine_.power().cutting_W(),
                          spindle_.electrical_power_W(),
                          spindle_.rpm(),
                          mo.engaged ? 1.0 : 0.0,
                          static_cast<double>(mo.reason),
                          pl.s_min_mm_per_min,
                          pl.ds_mm_per_min,
                          pl.dl_mm,
                          static_cast<double>(pl.n_s),
                          cfg_.setup == TwinSetup::DepthDivision
                              ? process_.inter_tool_delay_rev()
                              : 0.0};
    rec_.push_row(row);
  }
  t_ += dt_;
  ++step_;
  if (++since_control_ == control_every_) since_control_ = 0;
  if (++since_chain_ == chain_every_) since_chain_ = 0;
  if (++since_record_ == record_every_) since_record_ = 0;
  if (turrets_[0].z_mm >= cfg_.z_end_mm && (n_tools_ == 1 || turrets_[1].z_mm >= cfg_.z_end_mm))
    done_ = true;
  return !done_;
}

void Rig::run() noexcept {
  while (step()) {
  }
}

}  // namespace lathectl::systems::b_chatter
