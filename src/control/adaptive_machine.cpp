#include "lathectl/control/adaptive_machine.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "lathectl/control/adaptive_input.hpp"
#include "lathectl/control/types.hpp"

namespace lathectl::control {

namespace {
// An analog output that must be a whole number (a mode, an operation): NaN or a fraction is bad.
bool whole(double v, double lo, double hi) noexcept {
  return std::isfinite(v) && v >= lo && v <= hi && v == std::floor(v);
}
}  // namespace

AdaptiveMachine::AdaptiveMachine() = default;
AdaptiveMachine::~AdaptiveMachine() = default;

// Tool data under a running program. Task changes the tool (M6: iocontrol.0.tool-number) and its
// offsets (G43, G10 L1: motion.tooloffset.*) only with motion stopped between moves
// (emctaskmain.cc, emcTaskCheckPreconditions: WAITING_FOR_MOTION), so none of them changes in a
// feed move of a program. halui.tool.diameter is the tool table's row of the tool in the spindle,
// read from the table every machine shares (the tool data map $HOME/.tool.mmap) — which
// LinuxCNC 2.9's standalone rs274, run as the same user, recreates with its own tools under a
// running program. A change in a feed move is therefore not the program's: the part is being cut
// by other data than it was programmed for, and a load that falls or rises then says nothing
// about the tool's edge. halui publishes the diameter in its own loop, after iocontrol's tool
// number: a change within kToolSettleS of a tool change is that change arriving.
namespace {
constexpr double kToolSettleS = 1.0;
}
bool AdaptiveMachine::ToolWatch::update(int t, double d, double ox, double oz, bool feed_move,
                                        double dt) noexcept {
  since_change_s = t != tool ? 0.0 : since_change_s + dt;
  const bool settling = since_change_s < kToolSettleS;
  const bool moved = known && (t != tool || std::abs(d - diameter) > 1e-6 ||
                               std::abs(ox - offset_x) > 1e-6 || std::abs(oz - offset_z) > 1e-6);
  const bool changed = feed_move && moved &&
                       !(settling && t == tool && ox == offset_x && oz == offset_z);  // halui late
  tool = t;
  diameter = d;
  offset_x = ox;
  offset_z = oz;
  known = true;
  return changed;
}

void AdaptiveMachine::configure(const Params& p) {
  if (p.tools.size() > kMaxTools)
    throw std::invalid_argument("more than " + std::to_string(kMaxTools) + " tools");
  if (p.taught.size() > kMaxTaught)
    throw std::invalid_argument("more than " + std::to_string(kMaxTaught) + " taught references");
  if (!(p.power_lag_s >= 0.0)) throw std::invalid_argument("power_lag_s must be ≥ 0");
  if (!(p.override_step > 0.0)) throw std::invalid_argument("override_step must be > 0");
  if (!(p.learn_inertia_min_s > 0.0))
    throw std::invalid_argument("learn_inertia_min_s must be > 0");
  if (!(p.feed_forward_revs >= 0.0) || !std::isfinite(p.feed_forward_revs))
    throw std::invalid_argument("feed_forward_revs must be ≥ 0");
  if (!(p.feed_forward_rise >= 0.0) || !std::isfinite(p.feed_forward_rise))
    throw std::invalid_argument("feed_forward_rise must be ≥ 0");
  if (!(p.specific_force_time_s > 0.0))
    throw std::invalid_argument("specific_force_time_s must be > 0");
  if (p.life_law && !p.stock_model)
    throw std::invalid_argument(
        "the tool-life speed law needs the stock model (z_origin_mm): its depth and hardness "
        "come from the blank's geometry and the cut's specific force");
  p_ = p;
  auto c = p.controller;
  if (p.stock_model) c.breakage_drop_window_s = 0.0;  // the path-aware detector replaces it
  ctl_.configure(c);
  base_ = c;
  co_ = {};
  speed_law_ = c.mode == AdaptiveFeedController::Mode::ForceFeedSpeed;
  n_tools_ = 0;
  for (const auto& t : p.tools) tools_[n_tools_++] = t;
  n_taught_ = 0;
  for (const auto& t : p.taught) taught_[n_taught_++] = t;
  IdleTare::Params tp;
  tp.rpm_max = p.spindle.max_rpm;
  tp.rpm_min = p.spindle.min_rpm;
  tare_.configure(tp);
  load_rev_ = PerRevolutionMean(c.period_s, c.rpm_min);
  if (p.stock_model) {
    stock_ = std::make_unique<cutting::LathePlant>();
    stock_->configure(p.process, {.z_origin_mm = p.z_origin_mm});
    model_.configure(p.process.cutting);
    PathBreakage::Params bp;
    bp.window_s = p.controller.breakage_drop_window_s;
    bp.air = c.air_threshold;
    breakage_.configure(bp);
  } else {
    stock_.reset();
  }
  applied_ = {c.force_limit, c.feed_min_mm_per_rev, c.feed_max_mm_per_rev, 2, c.force_limit};
  every_ = count_ = 0;
  ctl_elapsed_s_ = 0.0;
  last_reset_ = false;
  req_prev_ = req_stable_ = f_word_ = 0.0;
  bad_ = false;
  accel_lagged_W_ = accel_W_ = accel_now_s_ = 0.0;
  accel_n_ = accel_head_ = 0;
  wdw_ = wdw_lagged_ = j_sxy_ = j_sxx_ = j_seen_s_ = 0.0;
  j_ready_ = false;
  inseparable_left_s_ = 0.0;
  inertia_ = p.spindle.inertia_kg_m2;
  stock_out_ = {};
  kappa_ = 1.0;
  kappa_learned_ = false;
  has_anchor_ = has_dir_ = false;
  ff_ceiling_ = ff_hold_s_ = 0.0;
  teach_ = TeachIn{};
  teach_tool_ = teach_op_ = -1;
  stats_.reset();
  op_line_ = op_tool_ = -1;
  op_number_ = op_mode_ = 0;
  op_limit_ = op_feed_s_ = 0.0;
  op_reasons_ = 0;
  op_alarm_ = op_seq_ = 0;
  contact_.reset();
  overload_latched_ = breakage_latched_ = tool_data_latched_ = tool_data_first_ = false;
  tool_watch_ = {};
  scale_mismatch_s_ = rescale_s_ = 0.0;
}

const ToolLimits* AdaptiveMachine::tool_of(int number) const noexcept {
  for (std::size_t i = 0; i < n_tools_; ++i)
    if (tools_[i].number == number) return &tools_[i];
  return nullptr;
}

AdaptiveMachine::Taught* AdaptiveMachine::taught_of(int tool, int op) noexcept {
  for (std::size_t i = 0; i < n_taught_; ++i)
    if (taught_[i].tool == tool && taught_[i].operation == op) return &taught_[i];
  return nullptr;
}

// The program's settings, the tool table's, the scenario's, in that order. A bad value leaves
// `out` as it was and returns what is wrong (and the value).
SettingError AdaptiveMachine::resolve(const Input& in, OpSettings& out,
                                      double& bad_value) const noexcept {
  const auto* tl = tool_of(in.tool_number);
  const double mode_v = in.mode_cmd;
  bad_value = mode_v;
  if (!whole(mode_v, 0.0, 4.0)) return SettingError::Mode;
  const double op_v = in.operation_cmd;
  bad_value = op_v;
  if (!whole(op_v, 0.0, 99999.0)) return SettingError::Mode;
  int mode = static_cast<int>(mode_v);
  if (mode == 0) mode = tl != nullptr && !tl->adaptive ? 1 : 2;
  OpSettings o;
  o.mode = mode;
  const double lim_v = in.limit_cmd;
  bad_value = lim_v;
  if (mode == 4) {
    if (!std::isfinite(lim_v)) return SettingError::LimitNotFinite;
    const double pct = lim_v != 0.0 ? lim_v : tl != nullptr ? tl->reference_pct : 100.0;
    if (!(pct > 0.0) || pct > p_.rating.percent_max) return SettingError::Percentage;
    const Taught* t = nullptr;
    for (std::size_t i = 0; i < n_taught_; ++i)
      if (taught_[i].tool == in.tool_number && taught_[i].operation == static_cast<int>(op_v))
        t = &taught_[i];
    if (t == nullptr) return SettingError::NotTaught;
    o.reference = t->reference;
    o.limit = pct / 100.0 * t->reference;
    bad_value = o.limit;
    if (const auto e = check_limit(o.limit, p_.rating); e != SettingError::None) return e;
    o.mode = 2;
  } else {
    if (const auto e = check_limit(lim_v, p_.rating); e != SettingError::None) return e;
    o.limit = lim_v > 0.0                        ? lim_v
              : tl != nullptr && tl->limit > 0.0 ? tl->limit
                                                 : base_.force_limit;
    o.reference = o.limit;
  }
  const double fmin_v = in.feed_min_cmd, fmax_v = in.feed_max_cmd;
  bad_value = std::isfinite(fmin_v) && fmin_v >= 0.0 ? fmax_v : fmin_v;
  if (check_feeds(fmin_v, fmax_v, p_.rating) != SettingError::None)
    return SettingError::FeedBounds;
  o.feed_min = fmin_v > 0.0                                     ? fmin_v
               : tl != nullptr && tl->feed_min_mm_per_rev > 0.0 ? tl->feed_min_mm_per_rev
                                                                : base_.feed_min_mm_per_rev;
  o.feed_max = fmax_v > 0.0                                     ? fmax_v
               : tl != nullptr && tl->feed_max_mm_per_rev > 0.0 ? tl->feed_max_mm_per_rev
                                                                : base_.feed_max_mm_per_rev;
  bad_value = o.feed_min;
  if (!(o.feed_min < o.feed_max)) return SettingError::FeedBounds;
  out = o;
  return SettingError::None;
}

// The operation that ended: its record, seq last (lathectl_oplog reads it when seq changes).
void AdaptiveMachine::publish_operation(Output& out) noexcept {
  if (op_line_ > 0 && op_feed_s_ > 0.0) {  // lines with feed moves only
    auto& r = out.op;
    r.line = op_line_;
    r.tool = op_tool_;
    r.operation = op_number_;
    r.mode = op_mode_;
    r.limit = op_limit_;
    r.load_mean = stats_.mean_load();
    r.load_peak = stats_.peak_load();
    r.feed_min = stats_.feed_min();
    r.feed_mean = stats_.feed_mean();
    r.time_in_cut_s = stats_.time_in_cut_s();
    r.time_s = stats_.time_s();
    r.reasons = op_reasons_;
    r.alarm = op_alarm_;
    r.seq = ++op_seq_;
  }
  stats_.reset();
  op_feed_s_ = 0.0;
  op_reasons_ = 0;
  op_alarm_ = 0;
}

void AdaptiveMachine::end_operation(Output& out) noexcept {
  publish_operation(out);
  op_line_ = -1;
}

void AdaptiveMachine::hold(Output& out) const noexcept {
  out.adaptive_feed = 0.0;
  out.feed_hold = true;
  out.alarm = true;
}

void AdaptiveMachine::update(const Input& in, Output& out) noexcept {
  out.control_period = false;
  if (every_ == 0) {  // the control period must be a whole number of thread periods
    const double ratio = ctl_.params().period_s / in.nominal_period_s;
    const long k = std::isfinite(ratio) ? std::lround(ratio) : 0;
    every_ = k < 1 || std::abs(ratio - static_cast<double>(k)) > 0.01 * ratio ? -1 : k;
    out.period_error = every_ < 0;
  }
  if (every_ < 0) {
    hold(out);
    out.spindle_speed_out = in.rpm_programmed;
    out.spindle_override = 1.0;
    return;
  }
  // The period as it was, not as the thread says: the detectors count this.
  const auto period = period_time(in.elapsed_s, in.nominal_period_s);
  ctl_elapsed_s_ += period.elapsed_s;
  if (in.reset && !last_reset_) {
    ctl_.reset_alarm();
    overload_latched_ = breakage_latched_ = false;
    breakage_.reset();
    tool_data_latched_ = tool_data_first_ = false;
  }
  last_reset_ = in.reset;
  const double req_now = std::abs(in.requested_vel);
  if (req_now == req_prev_) req_stable_ = req_now;
  req_prev_ = req_now;
  {  // Under G95 motion.requested-vel is the F word for a straight feed but, for an arc, the
     // arc's velocity limit (80 mm/s in the sample config: profile_arcs.ngc's G2 read as
     // 80 mm/rev, the factor fell to 0.0006 and the arc crawled). motion.feed-upm is the move's
     // own F word times motion's net feed scale: the feed scale times the adaptive feed written
     // last period, which motion used in this one. Used only where requested-vel cannot be an F
     // word (more than 4× it: an arc's limit is ~500×). Without the scale motion reports, it
     // is taken as 1: an operator's override then scales the F too, which the 4× test tolerates.
    const double net = (in.scale_in_motion > 0.0 ? in.scale_in_motion : 1.0) * out.adaptive_feed;
    f_word_ = net > 1e-9 && in.feed_upm > 0.0 ? in.feed_upm / net : 0.0;
  }

  // Settings: checked every servo period, so a value motion puts out is in effect (or held as
  // bad) in the same period.
  OpSettings want = applied_;
  double bad_value = 0.0;
  const SettingError err = resolve(in, want, bad_value);
  if (err != SettingError::None) {
    if (!bad_) {
      out.bad_line = in.program_line;
      out.bad_value = bad_value;
    }
    bad_ = true;
    out.bad_code = err;
  } else {
    bad_ = false;
    out.bad_code = SettingError::None;
    if (!(want == applied_)) {
      // resolve() checked what set_operation() requires: it cannot refuse these
      (void)ctl_.set_operation(want.limit, want.feed_min, want.feed_max, want.mode == 2);
      applied_ = want;
    }
  }
  out.bad_setting = bad_;
  out.limit = applied_.limit;
  out.feed_min = applied_.feed_min;
  out.feed_max = applied_.feed_max;
  out.adaptive_on = applied_.mode == 2;
  const bool teach_mode = applied_.mode == 3;
  const int tool = in.tool_number;
  const int opn = static_cast<int>(std::isfinite(in.operation_cmd) ? in.operation_cmd : 0.0);
  if (teach_mode && (tool != teach_tool_ || opn != teach_op_)) {  // one teach cut per key
    teach_.start();
    teach_tool_ = tool;
    teach_op_ = opn;
  }
  if (!teach_mode) teach_tool_ = teach_op_ = -1;
  out.teaching = teach_mode && teach_.running();

  // One record per program line (or tool) with feed moves.
  if (in.program_line != op_line_ || tool != op_tool_) {
    publish_operation(out);
    op_line_ = in.program_line;
    op_tool_ = tool;
  }
  op_number_ = opn;
  op_mode_ = applied_.mode;
  op_limit_ = applied_.limit;

  const bool feed_move = in.enable && is_feed_motion(in.motion_type);
  if (p_.power_sensor) acceleration_power(in.rpm, period.elapsed_s, in.nominal_period_s);
  // Every servo period: the stop comes in the period the data changes.
  if (tool_watch_.update(tool, in.tool_diameter, in.tool_offset_x, in.tool_offset_z, feed_move,
                         period.elapsed_s) &&
      !tool_data_latched_) {
    tool_data_latched_ = true;
    tool_data_first_ = !(out.alarm || breakage_latched_ || overload_latched_);
  }
  out.tool_data_changed = tool_data_latched_;
  if (tool_data_latched_) {
    hold(out);
    if (tool_data_first_) out.alarm_reason = Reason::ToolDataChanged;
  }
  if (stock_) {  // every servo period: the stop comes in the period the load collapses
    cutting::LathePlant::Input si;
    si.x_mm = in.homed ? in.x_mm : std::nan("");
    si.z_mm = in.homed ? in.z_mm : std::nan("");
    si.rpm = in.rpm;
    cutting::LathePlant::Output so;
    stock_->cut(si, period.elapsed_s, so);  // the chip's geometry alone, for the time that passed
    stock_out_ = so;
    // The engagement at this instant, not the last revolution's chip: leaving the material at
    // 300 m/min the load falls within the 10 ms window while the revolution's mean depth (19 ms
    // at 1560 rpm for half of it) still predicted material, and a run-off read as a broken tool.
    const double depth = so.engaged_depth_mm;
    // What the real blank gives at least there: the model knows the eccentricity's size and the
    // random allowance's σ, not their phase along the part or the revolution.
    const double guaranteed = depth - (so.on_blank ? p_.process.stock.eccentricity_mm : 0.0) -
                              3.0 * p_.process.disturbances.random_sigma_mm;
    out.predicted_depth_mm = depth;
    if (feed_move && inseparable_left_s_ > 0.0)
      breakage_.skip(period.elapsed_s);
    else if (feed_move && applied_.mode == 2 &&
             breakage_.update(p_.power_sensor ? out.load : in.force, applied_.limit, depth,
                              guaranteed, period.elapsed_s) &&
             !tool_data_latched_)
      breakage_latched_ = true;
    if (!feed_move) breakage_.reset();
    out.breakage = breakage_latched_;
    if (breakage_latched_) {
      hold(out);
      if (!(tool_data_latched_ && tool_data_first_)) out.alarm_reason = Reason::ToolBreakage;
    }
  }
  if (count_++ % every_ == 0) {
    const double elapsed = ctl_elapsed_s_;
    ctl_elapsed_s_ = 0.0;
    control(in, out, elapsed);
    out.control_period = true;
  } else {
    if (!(in.enable && speed_law_ && applied_.mode == 2))
      out.spindle_speed_out = in.rpm_programmed;  // program speed changes pass between updates
    if (bad_ || breakage_latched_ || tool_data_latched_) {  // held in the period it appears
      out.adaptive_feed = 0.0;
      out.feed_hold = true;
    }
  }
}

// The load sensor 4 gives the controller, and with the power sensor the cutting power at the
// spindle: η·(P_drive − P_idle(n)) − J·ω·dω/dt.
double AdaptiveMachine::measured_load(const Input& in, bool feed_move, double rpm, double dt,
                                      Output& out, bool& sensing) noexcept {
  sensing = true;
  if (!p_.power_sensor) return in.force;
  // Outside feed moves (rapids, dwells, tool changes) the drive draws its idle power only.
  tare_.update(rpm, in.spindle_power_W, dt, !feed_move);
  const bool learned = tare_.covers(rpm);
  // Until the tare has learned this speed: what the drive draws in air by its parameters (the
  // idle law and viscous friction; without the friction a prior-art run at a steady 1750 rpm
  // read 336 W of cutting in air and took it for contact).
  const double idle = learned ? tare_.idle_W(rpm) : drives::air_power_W(p_.spindle, rpm);
  out.idle_power_W = std::isfinite(idle) ? idle : 0.0;
  out.idle_law = tare_.coefficients();
  out.tare_ready = learned;
  out.acceleration_power_W = accel_lagged_W_;  // (acceleration_power(), every servo period)
  // The mechanical power at the spindle: a motoring drive draws it over η, a braking one returns
  // η of it (regeneration).
  const double drawn = in.spindle_power_W - out.idle_power_W;
  const double eta = p_.spindle.efficiency;
  // The inertia, from speed changes in air where the tare knows the idle power: the mechanical
  // power there is J·ω·dω/dt alone (least squares through the origin).
  if (p_.learn_inertia && !feed_move && learned && std::isfinite(drawn) &&
      std::abs(wdw_lagged_) > 20.0 * std::abs(rpm) * 2.0 * std::numbers::pi / 60.0) {
    const double mech = drawn >= 0.0 ? drawn * eta : drawn / eta;
    j_sxy_ += wdw_lagged_ * mech;
    j_sxx_ += wdw_lagged_ * wdw_lagged_;
    j_seen_s_ += dt;
    if (j_seen_s_ >= p_.learn_inertia_min_s && j_sxx_ > 0.0 && j_sxy_ > 0.0) {
      inertia_ = j_sxy_ / j_sxx_;
      j_ready_ = true;
    }
  }
  out.inertia_kg_m2 = inertia_;
  out.inertia_learned = j_ready_;
  double load = (drawn >= 0.0 ? drawn * eta : drawn / eta) - accel_lagged_W_;
  // In a feed move, while the inertia is still the prior of one to be learned, J·ω·dω/dt is
  // known only to its own size (a prior of 0.5 for a true 2 kg·m² leaves 3/4 of it in the
  // reading: braking, the cut reads that much low and the regulator would raise the feed).
  // Where it is above 5 % of the limit (the band the regulator holds) the reading cannot be
  // separated: it is held — the feed may fall, not rise — until a revolution after it is small
  // again, when the per-revolution mean no longer holds it. A given inertia, or a learned one,
  // is trusted.
  if (feed_move && p_.learn_inertia && !j_ready_ &&
      std::abs(accel_lagged_W_) > 0.05 * applied_.limit)
    inseparable_left_s_ = 60.0 / std::max(rpm, 1.0);
  else
    inseparable_left_s_ = std::max(0.0, inseparable_left_s_ - dt);
  sensing = !(feed_move && inseparable_left_s_ > 0.0);
  if (!feed_move) {
    // Outside feed moves nothing is cut: what is left is not a load, and not a sensor fault
    // either — a speed change in air before the inertia is learned (or with a wrong one) leaves
    // J·ω·dω/dt of either sign, tens of kW, and latched sensor_out_of_range. A reading that is
    // not a number still reaches the monitor; the drive's own reading is not range-checked
    // there: a run-up draws more than twice the rating for a moment (30 kW on the 15 kW sample
    // machine's idle sweep, which latched the alarm when it was).
    if (!std::isfinite(in.spindle_power_W)) return in.spindle_power_W;
    load = std::clamp(load, 0.0, ctl_.params().sensor_monitor.max);
  }
  return load;
}

// The power that accelerates the spindle, J·ω·dω/dt [W], from the measured speed over the last
// servo period (the nearest in time to the power reading), lagged as the power meter lags.
void AdaptiveMachine::acceleration_power(double rpm, double dt, double nominal_s) noexcept {
  // dω/dt as a difference over at least one nominal period of measured time: on time, the last
  // period's, as before. Under a loaded LinuxCNC a late period is followed by short catch-up
  // calls, each with one period's speed change over a fraction of a period: a braking spindle
  // read 29 kW for one sample (sensor_out_of_range in the shop session's idle sweep). Then the
  // difference reaches back over the late period.
  const double omega = std::abs(rpm) * 2.0 * std::numbers::pi / 60.0;
  if (!std::isfinite(omega)) {
    accel_n_ = 0;
  } else {
    accel_now_s_ += dt > 0.0 ? dt : nominal_s;
    double accel = 0.0;
    if (accel_n_ > 0) {
      // the newest sample at least a nominal period back (else the oldest kept)
      std::size_t k = 0;
      for (; k + 1 < accel_n_; ++k)
        if (accel_now_s_ - accel_t_[(accel_head_ + kAccelRing - k) % kAccelRing] >=
            nominal_s * (1.0 - 1e-9))
          break;
      const std::size_t i = (accel_head_ + kAccelRing - k) % kAccelRing;
      const double span = accel_now_s_ - accel_t_[i];
      if (span > 0.0) {
        const double wdw = omega * (omega - accel_w_[i]) / span;
        if (std::isfinite(wdw)) wdw_ = wdw;
        accel = inertia_ * wdw;
      }
    }
    accel_head_ = (accel_head_ + 1) % kAccelRing;
    accel_t_[accel_head_] = accel_now_s_;
    accel_w_[accel_head_] = omega;
    if (accel_n_ < kAccelRing) ++accel_n_;
    if (std::isfinite(accel)) accel_W_ = accel;
  }
  const core::FirstOrderLag lag(dt, p_.power_lag_s);  // the meter's
  accel_lagged_W_ = lag.step_increment(accel_lagged_W_, accel_W_);
  wdw_lagged_ = lag.step_increment(wdw_lagged_, wdw_);
}

// The handbook law's load at a chip (the load's own parameter: N, or W with the power sensor),
// at nominal hardness and a sharp tool.
double AdaptiveMachine::model_load(double t, double s, double v) const noexcept {
  const auto f = model_.forces({t, s, v, 1.0, 1.0});
  const auto which = p_.power_sensor ? cutting::ForceParameter::Power : p_.parameter;
  return cutting::force_parameter(which, f, model_.power_W(f, v));
}

// The feed-forward's ceiling [mm/rev] (0: none) for the control period about to run.
double AdaptiveMachine::feed_forward(const Input& in, double rpm, bool feed_block,
                                     Output& out) noexcept {
  out.depth_ahead_mm = 0.0;
  out.feed_ceiling_mm_per_rev = 0.0;
  if (!stock_ || !in.homed || !std::isfinite(in.x_mm) || !std::isfinite(in.z_mm)) {
    has_anchor_ = false;
    return 0.0;
  }
  // The direction of the path: the last 2 µm travelled (a period's difference is noise when
  // the tool creeps, and a tool standing still has no direction of its own).
  if (!has_anchor_) {
    anchor_x_ = in.x_mm;
    anchor_z_ = in.z_mm;
    has_anchor_ = true;
  } else if (std::hypot(in.x_mm - anchor_x_, in.z_mm - anchor_z_) >= 0.002) {
    dir_x_ = in.x_mm - anchor_x_;
    dir_z_ = in.z_mm - anchor_z_;
    anchor_x_ = in.x_mm;
    anchor_z_ = in.z_mm;
    has_dir_ = true;
  }
  if (!p_.feed_forward || !feed_block || applied_.mode != 2 || !has_dir_ || !(rpm > 0.0)) {
    ff_hold_s_ = 0.0;
    return 0.0;
  }
  const auto& cp = ctl_.params();
  // How far: the nose (in depth_ahead_mm) and feed_forward_revs revolutions at the highest feed
  // the controller may give, plus two control periods — the feed must be down a revolution
  // before the nose meets the rise (the chip there is the last revolution's feed). At the
  // highest feed, not the present one: a distance that shrank with the lowered feed let the
  // rise out of sight, and the feed went up again before it.
  const double s_hi = std::max(cp.feed_max_mm_per_rev, cp.feed_programmed_mm_per_rev);
  const double dist = s_hi * (p_.feed_forward_revs + 2.0 * cp.period_s * rpm / 60.0);
  const double ahead = stock_->depth_ahead_mm(in.x_mm, in.z_mm, dir_x_, dir_z_, dist);
  out.depth_ahead_mm = ahead;
  // (the larger of the last few cells' engagement and the last revolution's chip: the first
  // moves by a cell's worth as cells enter the nose, ±7 % at 8 mm/s on a 10 µm grid, and a dip
  // read as a rise ahead)
  const double now =
      out.contact ? std::max(stock_out_.engaged_depth_mm, stock_out_.chip_depth_mm) : 0.0;
  if (!(ahead > now * (1.0 + p_.feed_forward_rise) + 0.02)) {
    // The rise reached: the ceiling stays for one more revolution. The engagement reaches the
    // new depth within 0.03 mm of travel, the per-revolution load the regulator sees only after
    // a revolution; released at once, the regulator ramped the feed up into the corner on the
    // load of the old depth (e_worn_tool: 10.3 % over the limit, 9.3 % with the wait).
    if (ff_hold_s_ <= 0.0) return 0.0;
    ff_hold_s_ -= cp.period_s;
    out.feed_ceiling_mm_per_rev = ff_ceiling_;
    return ff_ceiling_;
  }
  const double v = in.cutting_speed_m_per_min > 0.0
                       ? in.cutting_speed_m_per_min
                       : std::numbers::pi * 2.0 * (std::abs(in.x_mm) + ahead) * rpm / 1000.0;
  const double limit = applied_.limit;
  auto load = [&](double f) { return kappa_ * model_load(ahead, f, v); };
  double lo = cp.feed_min_mm_per_rev, hi = s_hi;
  if (!(load(hi) > limit)) {  // the whole range holds the limit there
    ff_hold_s_ = 0.0;
    return 0.0;
  }
  if (load(lo) < limit) {
    for (int i = 0; i < 40; ++i) {
      const double mid = 0.5 * (lo + hi);
      (load(mid) > limit ? hi : lo) = mid;
    }
  }
  out.feed_ceiling_mm_per_rev = lo;
  ff_ceiling_ = lo;
  ff_hold_s_ = 60.0 / rpm;
  return lo;
}

// κ, the specific force the cut shows: the per-revolution load over the law's at the last
// revolution's geometric chip, in a steady cut (the chip of the revolution and of the last few
// cells of travel agree: no step, entry or exit inside the window).
void AdaptiveMachine::learn_specific_force(const Input& in, double rpm, double dt,
                                           const Output& out) noexcept {
  if (!stock_ || !p_.feed_forward || !out.contact || !load_rev_.full() || !(rpm > 0.0)) return;
  const double t = stock_out_.chip_depth_mm;
  const double s = stock_out_.feed_per_rev_mm;
  if (!(t > 0.05) || !(s > 0.01) || std::abs(stock_out_.engaged_depth_mm - t) > 0.05 * t) return;
  if (!(out.load_rev > ctl_.params().air_threshold * applied_.limit)) return;
  const double v = in.cutting_speed_m_per_min > 0.0
                       ? in.cutting_speed_m_per_min
                       : std::numbers::pi * 2.0 * (std::abs(in.x_mm) + t) * rpm / 1000.0;
  const double m = model_load(t, s, v);
  if (!(m > 0.0) || !std::isfinite(m)) return;
  const double k = std::clamp(out.load_rev / m, 0.2, 5.0);
  kappa_ = core::FirstOrderLag(dt, p_.specific_force_time_s).step_increment(kappa_, k);
  kappa_learned_ = true;
}

void AdaptiveMachine::control(const Input& in, Output& out, double dt_measured) noexcept {
  const double dt = ctl_.params().period_s;
  const bool enabled = in.enable;
  const double rpm = std::abs(in.rpm);
  const bool feed_block = enabled && is_feed_motion(in.motion_type);
  bool sensing = true;
  const double load = measured_load(in, feed_block, rpm, dt, out, sensing);
  AdaptiveSignals sig;
  sig.force = load;
  sig.spindle_power_W = in.spindle_power_W;
  sig.idle_power_W = drives::idle_power_W(p_.spindle, rpm);
  auto parameter = p_.parameter;
  if (p_.power_sensor) {
    sig.idle_power_W = out.idle_power_W;
    parameter = cutting::ForceParameter::Power;
  }
  sig.rpm = rpm;
  sig.feed_rate_mm_per_min = std::abs(in.current_vel_mm_s) * 60.0;
  // Sensor 20: a measured cutting speed when one is wired, else π·D·n at the tool's diameter.
  sig.speed_m_per_min = in.cutting_speed_m_per_min > 0.0
                            ? in.cutting_speed_m_per_min
                            : std::numbers::pi * 2.0 * std::abs(in.x_mm) * rpm / 1000.0;
  sig.feed_block = feed_block;
  auto ci = adaptive_input(parameter, sig);
  ci.dt_s = dt_measured;
  ci.feed_ceiling_mm_per_rev = feed_forward(in, rpm, feed_block, out);
  ci.reading_unusable = !sensing;
  if (p_.life_law && stock_) {
    // The depth the blank gives, and the hardness the cut shows: K_mp = h^kmp, so ĥ = κ^(1/kmp)
    // (κ also holds the tool's wear, which a slower speed suits too).
    if (out.contact && stock_out_.chip_depth_mm > 0.05) ci.depth_known_mm = stock_out_.chip_depth_mm;
    const double kmp = p_.process.cutting.material.kmp_exponent;
    const double h = kappa_learned_ && kmp > 0.0 ? std::clamp(std::pow(kappa_, 1.0 / kmp), 0.5, 2.0)
                                                 : 1.0;
    out.hardness_estimate = h;
    ci.speed_factor = model_.kmv(h) / model_.kmv(1.0);
  }
  ctl_.update(ci, co_);
  out.cut_power_W = ci.cut_power_W;
  out.load = load;
  const auto& o = co_;

  // Contact, in every mode (the controller's own runs only while it regulates).
  const auto& cp = ctl_.params();
  // (A reading that cannot be separated does not end a contact. Out of the cut it may start
  // one: taken for contact, the feed drops to the entry feed, which is the safe side.)
  if (sensing || !contact_.in_cut())
    (void)contact_.update(load, cp.air_threshold * applied_.limit, cp.air_time_s, dt,
                          feed_block && std::isfinite(load));
  out.contact = contact_.in_cut();
  // The load's mean over the last revolution: the controller's definition.
  if (out.contact && rpm > 0.0 && std::isfinite(load)) {
    out.load_rev = load_rev_.push(load, rpm);
  } else {
    load_rev_.restart();
    if (!out.contact) out.load_rev = 0.0;
  }
  out.load_percent = applied_.limit > 0.0 ? 100.0 * out.load_rev / applied_.limit : 0.0;
  if (sensing) learn_specific_force(in, rpm, dt, out);
  out.specific_force_ratio = kappa_;
  // Overload levels (Heidenhain AFC's), percentages of the reference (taught, else the limit).
  const auto* tl = tool_of(in.tool_number);
  const double ref = applied_.reference;
  out.overload_warn =
      tl != nullptr && tl->warn_pct > 0.0 && out.load_rev > tl->warn_pct / 100.0 * ref;
  if (tl != nullptr && tl->hold_pct > 0.0 && out.load_rev > tl->hold_pct / 100.0 * ref)
    overload_latched_ = true;
  out.overload_hold = overload_latched_;

  // Teach-in: the program's feed; the reference when the cut has ended.
  if (applied_.mode == 3 && teach_.sample(load, rpm, dt, out.contact)) {
    Taught* t = taught_of(teach_tool_, teach_op_);
    if (t == nullptr && n_taught_ < kMaxTaught) t = &taught_[n_taught_++];
    if (t != nullptr) *t = {teach_tool_, teach_op_, teach_.reference()};
    out.teach.tool = teach_tool_;
    out.teach.operation = teach_op_;
    out.teach.reference = teach_.reference();
    ++out.teach.seq;
  }

  double factor = 1.0;
  const bool regulating = applied_.mode == 2;
  const double max_ovr = in.max_override;
  if (feed_block && regulating) {
    // The program's feed per revolution: motion reports the F word itself under G95, a velocity
    // [mm/s] under G94 (motion.requested-vel: without the feed scale).
    const double req = req_stable_;
    const double prog_per_rev = in.per_rev ? (f_word_ > 0.0 && req > 4.0 * f_word_ ? f_word_ : req)
                                : rpm > 0.0 ? req * 60.0 / rpm
                                            : 0.0;
    // Above the program's feed up to the machine's maximum override (split_feed_override).
    factor = o.feed_hold      ? 0.0
             : prog_per_rev > 0.0 ? std::clamp(o.feed_per_rev_mm / prog_per_rev, 0.0,
                                               std::max(max_ovr, 1.0))
                                  : 1.0;
  }
  const bool held = enabled && (o.feed_hold || bad_ || overload_latched_ || breakage_latched_ ||
                                tool_data_latched_);
  // The operator's knob times the factor; the ceiling to the feed scale, every decrease on
  // adaptive-feed. Not enabled: the knob alone, on feed moves as before.
  const auto fo = split_feed_override(factor, in.knob, max_ovr, p_.override_step,
                                      out.feed_override, in.scale_in_motion, enabled && feed_block);
  out.feed_override = fo.scale;
  scale_mismatch_s_ = std::abs(in.scale_in_motion - fo.scale) > 0.5 * p_.override_step
                          ? scale_mismatch_s_ + dt
                          : 0.0;
  if (scale_mismatch_s_ > p_.rescale_after_s) {
    rescale_s_ = p_.rescale_for_s;
    scale_mismatch_s_ = 0.0;
  }
  // (one count lower while re-sending: below the divisor, so the feed only ever dips by it)
  out.feed_override_counts =
      static_cast<std::int32_t>(std::lround(fo.scale / p_.override_step)) - (rescale_s_ > 0.0 ? 1 : 0);
  rescale_s_ = std::max(rescale_s_ - dt, 0.0);
  out.feed_factor = held ? 0.0 : fo.net;
  out.adaptive_feed = held ? 0.0 : fo.adaptive;
  out.feed_hold = held;
  out.alarm = o.alarm || overload_latched_ || breakage_latched_ || tool_data_latched_;
  out.reason = o.reason;
  out.alarm_reason = tool_data_latched_ && tool_data_first_ ? Reason::ToolDataChanged
                     : breakage_latched_ && !o.alarm        ? Reason::ToolBreakage
                     : overload_latched_ && !o.alarm        ? Reason::Overload
                                                            : o.alarm_reason;
  out.feed_per_rev_mm = o.feed_per_rev_mm;
  out.speed_cmd_m_per_min = o.speed_m_per_min;
  out.speed_opt_m_per_min = o.speed_opt_m_per_min;
  out.depth_estimate_mm = o.depth_estimate_mm;
  out.in_cut = o.in_cut;
  stats_.sample(load, out.load_rev, load_rev_.full(), out.feed_factor, dt, out.contact);
  if (feed_block) op_feed_s_ += dt;
  if (feed_block && out.contact) {
    op_reasons_ |= reason_bit(o.reason);
    if (out.alarm && op_alarm_ == 0) op_alarm_ = static_cast<std::int32_t>(out.alarm_reason);
  }
  // Seed 004's speed law drives the spindle while the program runs it; otherwise the program's
  // speed passes through.
  double rpm_out = in.rpm_programmed;
  if (enabled && speed_law_ && regulating && in.rpm_programmed != 0.0)
    rpm_out = std::copysign(o.rpm, in.rpm_programmed);
  out.spindle_speed_out = rpm_out;
  out.spindle_override = in.rpm_programmed != 0.0 ? rpm_out / in.rpm_programmed : 1.0;
}

}  // namespace lathectl::control
