#include "systems/a_pulse_feed/rig.hpp"

#include "systems/a_pulse_feed/machine_params.hpp"

#include "lathectl/sim/config_error.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace lathectl::systems::a_pulse_feed {

namespace {
constexpr std::size_t kChannels = 17;

std::vector<sim::Channel> rig_a_channels() {
  return {{"time_s", "s"},
          {"travel_mm", "mm"},
          {"feed_mm_per_min", "mm/min"},
          {"feed_per_rev_mm", "mm/rev"},
          {"force_Py_N", "N"},
          {"force_estimate_N", "N"},
          {"depth_mm", "mm"},
          {"sensor_V", "V"},
          {"slot_um", "µm"},
          {"frequency_Hz", "Hz"},
          {"flow_cm3_per_min", "cm³/min"},
          {"leak_cm3_per_min", "cm³/min"},
          {"cylinder_pressure_MPa", "MPa"},
          {"reason_code", ""},
          {"alarm", ""},
          {"obliteration_layer_um", "µm"},
          {"strength_factor", ""}};
}
constexpr double kM3sToCm3min = 1e6 * 60.0;
}  // namespace

// configure() in phases, in the order they run.

// The step against the slide's fastest dynamics: the hydraulic natural frequency and the damper.
void Rig::check_step_for_slide(const RigConfig& cfg, double dt) const {
  const double wh = slide_.hydraulic_omega();
  if (wh * dt > 0.5)
    throw sim::ConfigError("run.step_s", "step_s " + std::to_string(dt) +
                                             " too coarse for the slide's hydraulic "
                                             "natural frequency " +
                                             std::to_string(wh / 2 / std::numbers::pi) +
                                             " Hz: use step_s ≤ " + std::to_string(0.5 / wh));
  if (cfg.slide.damper_capacitance_m3_per_Pa > 0.0) {
    const double tau_d =
        cfg.slide.damper_capacitance_m3_per_Pa * cfg.slide.damper_resistance_Pa_s_per_m3;
    const double tau_c = cfg.slide.dead_volume_m3 / cfg.slide.bulk_modulus_Pa *
                         cfg.slide.damper_resistance_Pa_s_per_m3;
    if (dt > 0.5 * std::min(tau_d, tau_c))
      throw sim::ConfigError("run.step_s", "step_s too coarse for the damper: use step_s ≤ " +
                                               std::to_string(0.5 * std::min(tau_d, tau_c)));
  }
}

// The uncontrolled machine's setting: the flow the programmed feed needs, with the true
// leakage and the friction and regulator gain of the machine's model (machine_params).
void Rig::set_fixed_actuator(const RigConfig& cfg, const control::SlideMachine::Params& mp) {
  const auto& cp = mp.controller;
  const double feed = cfg.controller.feed_m_per_s;
  const double F = cfg.slide.piston_area_m2;
  const double gain = cp.regulator_gain_per_m;
  const double q_needed =
      feed * F + cfg.slide.leak_m3_per_s_Pa * (force_nominal_ + cp.friction_N) / F;
  fixed_actuator_ = cfg.regulator_kind == RegulatorKind::Throttle
                        ? q_needed / gain
                        : q_needed / (gain * cfg.pulse_width_s * cfg.frequency_Hz);
}

// The machine side, started at the nominal load, and its first actuator command.
void Rig::start_machine(const RigConfig& cfg, const control::SlideMachine::Params& mp, double dt) {
  const auto& cp = mp.controller;
  const double feed = cfg.controller.feed_m_per_s;
  sim::configure_as("controller",
                    {{"overload_factor", "controller.overload_factor"},
                     {"overload_time_s", "controller.overload_time_ms"},
                     {"breakage_drop", "controller.breakage_drop"},
                     {"breakage_window_s", "controller.breakage_window_ms"},
                     {"feed_law", "controller.feed_law"},
                     {"force_law", "controller.force_law"}},
                    [&] { machine_.configure(mp); });
  machine_.start(force_nominal_);
  const auto& ctl = machine_.controller();
  ctl_out_ = {};
  ctl_out_.slot_m =
      cfg.controller_kind == ControllerKind::Aim
          ? std::clamp(ctl.actuator_for(feed, force_nominal_), cp.slot_min_m, cp.slot_max_m)
          : fixed_actuator_;
  ctl_out_.pulses = true;  // the slide was feeding before t = 0 (the warm-up below)
  ctl_out_.frequency_Hz = cfg.controller_kind == ControllerKind::Fim
                              ? ctl.actuator_for(feed, force_nominal_)
                              : cfg.frequency_Hz;
  control_every_ =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(cp.period_s / dt)));
  if (cfg.controller_kind == ControllerKind::Aim) {
    auto ep = cfg.eccentric;
    sim::configure_as("eccentric", [&] { ecc_.configure(ep); });
    ecc_.set_slot(ctl_out_.slot_m);
  }
}

// History buffers and recorded rows of a sensible size, else the setting to change.
void Rig::check_buffers(const RigConfig& cfg, double dt, double duration) const {
  constexpr double kMaxBufferSteps = 2e7;  // history buffers beyond this mean a nonsensical step
  if (1.0 / rev_per_s_ / dt > kMaxBufferSteps || cfg.feed_window_s / dt > kMaxBufferSteps / 2)
    throw sim::ConfigError(
        1.0 / rev_per_s_ / dt > kMaxBufferSteps ? "run.step_s" : "metrics.feed_window_s",
        "one spindle revolution or the feed window spans more than 2e7 steps: "
        "increase step_s or the spindle speed, or shorten feed_window_s");
  if (!streamed_ && duration / (dt * static_cast<double>(record_every_)) > 5e7)
    throw sim::ConfigError("run.record_interval_s",
                           "more than 5e7 recorded rows: increase record_interval_s");
}

// Warm-up: the slide was already feeding before t = 0. Run regulator, damper and slide at the
// nominal load until the pulsed flow is periodic, then put the slide back at x = 0, so the
// run starts in the pulsing steady state rather than with a start-up surge.
void Rig::warm_up(const RigConfig& cfg, double dt) {
  const double warm_s = std::max(0.5, 10.0 / cfg.frequency_Hz);
  const double h0 = cfg.controller_kind == ControllerKind::Fim ? cfg.slot_m : ctl_out_.slot_m;
  const double f0 =
      cfg.controller_kind == ControllerKind::Fim ? ctl_out_.frequency_Hz : cfg.frequency_Hz;
  for (double tw = 0.0; tw < warm_s; tw += dt) {
    const double q = cfg.regulator_kind == RegulatorKind::Throttle
                         ? thr_.step(dt, fixed_actuator_)
                         : reg_.step(dt, h0, f0, cfg.pulse_width_s);
    slide_.step(dt, q, force_nominal_);
  }
  slide_.set_position(0.0);
  slide_.reset_volume_ledger();
  damper_volume0_ = slide_.damper_volume();
  void0_ = slide_.state().void_m3;
  thr_.configure({cfg.regulator.orifice, cfg.regulator.obliteration});  // no silting before t = 0
}

// The slide's path before t = 0 (steady motion), and the signals at their steady values.
void Rig::prime_history(const RigConfig& cfg, double dt) {
  const double feed = cfg.controller.feed_m_per_s;
  rev_steps_ =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(1.0 / rev_per_s_ / dt)));
  window_steps_ =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(cfg.feed_window_s / dt)));
  x_hist_.assign(std::max(rev_steps_, 2 * window_steps_) + 1, 0.0);
  hist_head_ = 0;
  for (std::size_t k = 0; k < x_hist_.size(); ++k) {  // steady motion before t = 0
    x_hist_[(x_hist_.size() - k) % x_hist_.size()] = -feed * dt * static_cast<double>(k);
  }
  force_ = force_nominal_;
  depth_ = dist_.depth_profile(0.0);
  sensor_u_ = cfg.sensor.offset_V + sensor_.volts_per_newton() * force_nominal_;
  faults_.reset(sensor_u_);
  flow_acc_ = force_acc_ = 0.0;
  acc_n_ = 0;
}

void Rig::configure(const RigConfig& cfg, double dt, double record_interval, double duration) {
  if (!(dt > 0.0) || !(record_interval >= dt) || !(duration > 0.0))
    throw std::invalid_argument("run: need step > 0, record interval ≥ step, duration > 0");
  // The machine side's parameters, as every host derives them (machine_params.cpp; it rejects a
  // controller the regulator cannot take, and an external controller on anything but a pulsed
  // regulator).
  auto mp = machine_params(cfg, Host{.machine_io = external_});
  if (!(cfg.spindle_rpm > 0.0) || !(cfg.diameter_m > 0.0))
    throw std::invalid_argument("spindle speed and part diameter must be > 0");
  if (!(cfg.pulse_width_s > 0.0) || !(cfg.frequency_Hz > 0.0) || !(cfg.slot_m > 0.0))
    throw std::invalid_argument("pulse width, frequency and slot must be > 0");
  cfg_ = cfg;
  dt_ = dt;
  duration_ = duration;
  t_ = 0.0;
  step_ = since_control_ = since_record_ = 0;
  phi_ = 0.0;
  t_disturbance_ = -1.0;
  x_disturbance_mm_ = 0.0;
  life_used_ = life_used_td_ = 0.0;
  sound_ = true;
  record_every_ =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(record_interval / dt)));

  sim::configure_as("material", [&] { cut_.configure(cfg.cutting); });
  sim::configure_as("part", [&] { dist_.configure(cfg.part); });
  first_change_mm_ = dist_.first_change_mm();
  rev_per_s_ = cfg.spindle_rpm / 60.0;
  speed_m_per_min_ = std::numbers::pi * cfg.diameter_m * cfg.spindle_rpm;

  const double feed = cfg.controller.feed_m_per_s;
  // Nominal force: the programmed feed on the deterministic part of the blank at its start.
  force_nominal_ = a_pulse_feed::nominal_force_N(cfg);

  sim::configure_as("slide", [&] { slide_.configure(cfg.slide); });
  slide_.set_steady(feed, force_nominal_);
  check_step_for_slide(cfg, dt);
  sim::configure_as("regulator", [&] {
    reg_.configure(cfg.regulator);
    thr_.configure({cfg.regulator.orifice, cfg.regulator.obliteration});
  });
  sim::configure_as("sensor", [&] { sensor_.configure(cfg.sensor); });
  sensor_.set_steady(force_nominal_);

  set_fixed_actuator(cfg, mp);
  start_machine(cfg, mp, dt);
  check_buffers(cfg, dt, duration);
  warm_up(cfg, dt);
  prime_history(cfg, dt);

  if (streamed_) {
    rec_ = sim::Recorder::streamed(rig_a_channels(), {},
                                   plots_ ? sim::Recorder::kPlotValuesPerLevel : 0);
    return;
  }
  const auto rows =
      static_cast<std::size_t>(duration / (dt * static_cast<double>(record_every_))) + 2;
  rec_ = sim::Recorder(rig_a_channels(), rows);
}

double Rig::last_record_time() const noexcept {
  // run() takes llround(duration/dt) steps of t += dt from 0 and records every record_every_-th.
  const auto steps = static_cast<std::size_t>(std::llround(duration_ / dt_));
  const std::size_t last = steps / record_every_ * record_every_;
  if (last == 0) return -1.0;
  double t = 0.0;
  for (std::size_t i = 0; i < last; ++i) t += dt_;
  return t;
}

// steps < the ring's size (rev_steps_ and the feed's window are): the index wraps by a compare,
// not by a 64-bit `%` (two divisions a step were a tenth of the step's time).
inline double Rig::position_ago(std::size_t steps) const noexcept {
  return x_hist_[hist_head_ >= steps ? hist_head_ - steps : hist_head_ + x_hist_.size() - steps];
}

inline double Rig::chip_feed_mm_per_rev() const noexcept {
  return std::max((slide_.state().x_m - position_ago(rev_steps_)) * 1000.0, 0.0);
}

// step() in phases, in the order they run.

// The spindle turns, the tool cuts the local blank at the chip the slide's path leaves, and the
// tool's life is used; the load sensor follows the force. Returns the slide's position [mm].
inline double Rig::cut_step() noexcept {
  t_ += dt_;
  ++step_;
  phi_ += 2.0 * std::numbers::pi * rev_per_s_ * dt_;
  if (phi_ > 2.0 * std::numbers::pi) phi_ -= 2.0 * std::numbers::pi;
  const double x_mm = slide_.state().x_m * 1000.0;
  if (t_disturbance_ < 0.0 && x_mm >= first_change_mm_) {
    t_disturbance_ = t_;
    x_disturbance_mm_ = x_mm;
  }

  const auto local = dist_.at(x_mm, phi_, t_);
  depth_ = local.depth_mm;
  const double chip = chip_feed_mm_per_rev();
  force_ = cut_.radial_force({local.depth_mm, chip, speed_m_per_min_, local.strength_factor,
                              local.wear_factor});
  // (infinite life out of cut: nothing used)
  const double life_s =
      60.0 * cut_.tool_life_min(speed_m_per_min_, chip, local.depth_mm, local.strength_factor);
  const double used = dt_ / life_s;
  life_used_ += used;
  if (t_disturbance_ >= 0.0) life_used_td_ += used;
  (void)sensor_.step(dt_, force_);
  return x_mm;
}

// The controller: the machine's outputs from outside (a LinuxCNC session), or the machine side
// run here every control period on what the sensor reads, faults included.
inline void Rig::control_step() noexcept {
  if (external_) {  // what the machine's analog input reads, every step
    sensor_u_ = faults_.apply(cfg_.faults, t_, sensor_.sample(), cfg_.sensor.saturation_V * 2.0 + 1.0);
    ctl_out_ = act_.out;
  } else if (cfg_.controller_kind != ControllerKind::None && ++since_control_ == control_every_) {
    since_control_ = 0;
    sensor_u_ = faults_.apply(
        cfg_.faults, t_, sensor_.sample(),
        cfg_.sensor.saturation_V * 2.0 + 1.0);  // what the controller sees, faults included
    control::SlideMachine::Input in;
    in.sensor_V = sensor_u_;
    in.mode = cfg_.controller.mode;
    in.feed_m_per_s = cfg_.controller.feed_m_per_s;
    in.force_set_N = cfg_.controller.force_set_N;
    in.position_m = slide_.state().x_m;
    machine_.update(in);
    ctl_out_ = machine_.output();
  }
}

// The flow the regulator delivers this step, from the valve's state (external), the throttle,
// or the pulse train the controller commands.
inline double Rig::regulator_flow() noexcept {
  double q = 0.0;
  if (external_) {
    // The valve's state from the machine's pulse train: the spool is driven open while the
    // electromagnet is energised (duty 1 over this step) and closes otherwise.
    double h = cfg_.slot_m;
    if (cfg_.controller_kind == ControllerKind::Aim) {
      ecc_.step(dt_, act_.slot_cmd_m);
      h = ecc_.slot_m();
    }
    const double on = act_.valve_open ? 1.0 : 0.0;  // duty f·Δt exactly 1 (open) or 0 (shut)
    q = reg_.step(dt_, h, on, 1.0);
  } else if (cfg_.regulator_kind == RegulatorKind::Throttle) {
    q = thr_.step(dt_, fixed_actuator_);
  } else {
    double h = fixed_actuator_;
    double f = cfg_.frequency_Hz;
    if (cfg_.controller_kind == ControllerKind::Aim) {
      ecc_.step(dt_, ctl_out_.slot_m);
      h = ecc_.slot_m();
      if (!ctl_out_.pulses) f = 0.0;  // feed stop or slide off: valve held shut
    } else if (cfg_.controller_kind == ControllerKind::Fim) {
      h = cfg_.slot_m;
      f = ctl_out_.frequency_Hz;
    }
    q = reg_.step(dt_, h, f, cfg_.pulse_width_s);
  }
  return q;
}

// One recorded row, averaged over the steps since the last.
inline void Rig::record_row(double x_mm) noexcept {
  const auto& s = slide_.state();
  const double n = static_cast<double>(acc_n_);
  if (cfg_.controller_kind == ControllerKind::None && !external_) sensor_u_ = sensor_.sample();

  const double slot = cfg_.regulator_kind == RegulatorKind::Throttle ? fixed_actuator_
                      : cfg_.controller_kind == ControllerKind::Aim  ? ecc_.slot_m()
                      : cfg_.controller_kind == ControllerKind::Fim  ? cfg_.slot_m
                                                                     : fixed_actuator_;
  const double freq = cfg_.regulator_kind == RegulatorKind::Throttle ? 0.0
                      : external_                                    ? act_.frequency_Hz
                      : cfg_.controller_kind == ControllerKind::Fim  ? ctl_out_.frequency_Hz
                                                                     : cfg_.frequency_Hz;
  // Feed averaged over a whole number of pulse periods close to the feed window, so that the
  // pulse ripple cancels whatever the (FIM-varied) frequency.
  std::size_t w = window_steps_;
  if (freq > 0.0) {
    const double periods = std::max(1.0, std::round(cfg_.feed_window_s * freq));
    w = std::clamp<std::size_t>(static_cast<std::size_t>(std::llround(periods / freq / dt_)), 1,
                                x_hist_.size() - 1);
  }
  const double feed_avg = (s.x_m - position_ago(w)) / (static_cast<double>(w) * dt_);
  const double estimate = (sensor_u_ - cfg_.sensor.offset_V) / sensor_.volts_per_newton();
  const std::array<double, kChannels> row{
      t_,
      s.x_m * 1000.0,
      feed_avg * 60000.0,
      chip_feed_mm_per_rev(),
      force_acc_ / n,
      cfg_.controller_kind == ControllerKind::None ? estimate : ctl_out_.force_estimate_N,
      depth_,
      sensor_u_,
      slot * 1e6,
      freq,
      flow_acc_ / n * kM3sToCm3min,
      slide_.leak_flow() * kM3sToCm3min,
      s.p_cyl_Pa * 1e-6,
      static_cast<double>(ctl_out_.reason),
      ctl_out_.alarm ? 1.0 : 0.0,
      (cfg_.regulator_kind == RegulatorKind::Throttle ? thr_.layer_m() : 0.0) * 1e6,
      dist_.strength_factor(x_mm)};
  rec_.push_row(row);
  flow_acc_ = force_acc_ = 0.0;
  acc_n_ = 0;
}

[[gnu::flatten]] void Rig::step() noexcept {
  const double x_mm = cut_step();
  control_step();
  const double q = regulator_flow();
  slide_.step(dt_, q, force_);

  if (++hist_head_ == x_hist_.size()) hist_head_ = 0;
  x_hist_[hist_head_] = slide_.state().x_m;

  flow_acc_ += q;
  force_acc_ += force_;
  ++acc_n_;
  if (!std::isfinite(slide_.state().v_m_per_s) || !std::isfinite(slide_.state().p_cyl_Pa))
    sound_ = false;
  if (++since_record_ != record_every_) return;
  since_record_ = 0;
  record_row(x_mm);
}

Rig::VolumeBalance Rig::volume_balance() const noexcept {
  VolumeBalance b;
  const auto& l = slide_.ledger();
  b.delivered_m3 = l.delivered_m3;
  b.leaked_m3 = l.leaked_m3;
  b.swept_m3 = cfg_.slide.piston_area_m2 * slide_.state().x_m;  // x = 0 at t = 0
  b.stored_m3 = l.compressed_m3 + (slide_.damper_volume() - damper_volume0_) -
                (slide_.state().void_m3 - void0_);
  if (b.delivered_m3 > 0.0) {
    const double net = b.delivered_m3 - b.leaked_m3;
    b.travel_unexplained_pct = 100.0 * std::abs(net - b.swept_m3) / b.delivered_m3;
    b.conservation_error_pct = 100.0 * std::abs(net - b.swept_m3 - b.stored_m3) / b.delivered_m3;
  }
  return b;
}

void Rig::run() noexcept {
  const auto steps = static_cast<std::size_t>(std::llround(duration_ / dt_));
  for (std::size_t i = 0; i < steps; ++i) step();
}

}  // namespace lathectl::systems::a_pulse_feed
