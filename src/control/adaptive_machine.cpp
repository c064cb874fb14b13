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

namespace {
// configure()'s refusals, before anything is changed.
void check_params(const AdaptiveMachine::Params& p) {
  if (p.tools.size() > AdaptiveMachine::kMaxTools)
    throw std::invalid_argument("more than " + std::to_string(AdaptiveMachine::kMaxTools) +
                                " tools");
  if (p.taught.size() > AdaptiveMachine::kMaxTaught)
    throw std::invalid_argument("more than " + std::to_string(AdaptiveMachine::kMaxTaught) +
                                " taught references");
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
}
}  // namespace

void AdaptiveMachine::configure(const Params& p) {
  check_params(p);
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
    // y of the load's law in the feed (M ∝ s^y: the handbook's y, or Kienzle's 1 − m), from
    // the law itself at a 10 % step
    feed_exponent_ = std::log(model_load(1.0, 0.33, 100.0) / model_load(1.0, 0.3, 100.0)) /
                     std::log(1.1);
    if (!std::isfinite(feed_exponent_)) feed_exponent_ = 0.0;
    PathBreakage::Params bp;
    bp.window_s = p.controller.breakage_drop_window_s;
    bp.air = c.air_threshold;
    breakage_.configure(bp);
  } else {
    stock_.reset();
  }
  applied_ = {c.load_limit, c.feed_min_mm_per_rev, c.feed_max_mm_per_rev, 2, c.load_limit};
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
  stock_chip_due_ = false;
  kappa_ = 1.0;
  kappa_learned_ = false;
  ln_kappa_lag_ = kappa_rate_ = 0.0;
  kappa_trend_ = false;
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
                                                 : base_.load_limit;
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

// update() in phases, in the order they run; each is the text it was, moved.

// The control period must be a whole number of thread periods: false (everything held) if not.
inline bool AdaptiveMachine::period_fits(const Input& in, Output& out) noexcept {
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
    return false;
  }
  return true;
}

// The operator's reset (on its rising edge) and the program's F word as motion reports it.
inline void AdaptiveMachine::read_motion(const Input& in, const Output& out) noexcept {
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
  // Under G95 motion.requested-vel is the F word for a straight feed but, for an arc, the
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
inline void AdaptiveMachine::apply_settings(const Input& in, Output& out) noexcept {
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
}

// Teach mode starts one teach cut per tool and operation; one record per program line (or
// tool) with feed moves.
inline void AdaptiveMachine::track_operation(const Input& in, Output& out, int opn) noexcept {
  const bool teach_mode = applied_.mode == 3;
  const int tool = in.tool_number;
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
}

// Tool data changed in a feed move: held, every servo period (the stop comes in the period the
// data changes).
inline void AdaptiveMachine::watch_tool_data(const Input& in, Output& out, bool feed_move,
                                      double dt) noexcept {
  if (tool_watch_.update(in.tool_number, in.tool_diameter, in.tool_offset_x, in.tool_offset_z,
                         feed_move, dt) &&
      !tool_data_latched_) {
    tool_data_latched_ = true;
    tool_data_first_ = !(out.alarm || breakage_latched_ || overload_latched_);
  }
  out.tool_data_changed = tool_data_latched_;
  if (tool_data_latched_) {
    hold(out);
    if (tool_data_first_) out.alarm_reason = Reason::ToolDataChanged;
  }
}

void AdaptiveMachine::update(const Input& in, Output& out) noexcept {
  out.control_period = false;
  if (!period_fits(in, out)) return;
  // The period as it was, not as the thread says: the detectors count this.
  const auto period = period_time(in.elapsed_s, in.nominal_period_s);
  ctl_elapsed_s_ += period.elapsed_s;
  read_motion(in, out);
  apply_settings(in, out);
  const int opn = static_cast<int>(std::isfinite(in.operation_cmd) ? in.operation_cmd : 0.0);
  track_operation(in, out, opn);

  const bool feed_move = in.enable && is_feed_motion(in.motion_type);
  if (p_.power_sensor) acceleration_power(in.rpm, period.elapsed_s, in.nominal_period_s);
  watch_tool_data(in, out, feed_move, period.elapsed_s);
  if (stock_) watch_path(in, out, feed_move, period.elapsed_s);
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

// control() in phases, in the order they run; each is the text it was, moved.

// What the controller is given: sensor 4's load (force, or cutting power), sensors 12, 13 and
// 20, and what the stock model knows (the feed-forward's ceiling, the depth and the hardness).
inline AdaptiveFeedController::Input AdaptiveMachine::controller_input(const Input& in, Output& out,
                                                                const LoadReading& r,
                                                                double dt_measured) noexcept {
  const double rpm = r.rpm;
  AdaptiveSignals sig;
  sig.force = r.load;
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
  sig.feed_block = r.feed_block;
  auto ci = adaptive_input(parameter, sig);
  ci.dt_s = dt_measured;
  ci.feed_ceiling_mm_per_rev = feed_forward(in, rpm, r.feed_block, out);
  ci.feed_drift_mm_per_rev_per_s = r.sensing ? hardness_drift(out) : 0.0;
  ci.reading_unusable = !r.sensing;
  if (p_.life_law && stock_) {
    // The depth the blank gives, and the hardness the cut shows: K_mp = h^kmp, so ĥ = κ^(1/kmp)
    // (κ also holds the tool's wear, which a slower speed suits too).
    const double chip = stock_chip().chip_depth_mm;
    if (out.contact && chip > 0.05) ci.depth_known_mm = chip;
    const double kmp = p_.process.cutting.material.kmp_exponent;
    const double h = kappa_learned_ && kmp > 0.0 ? std::clamp(std::pow(kappa_, 1.0 / kmp), 0.5, 2.0)
                                                 : 1.0;
    out.hardness_estimate = h;
    ci.speed_factor = model_.kmv(h) / model_.kmv(1.0);
  }
  return ci;
}

// Contact, in every mode (the controller's own runs only while it regulates), and the load's
// mean over the last revolution.
inline void AdaptiveMachine::track_contact(const LoadReading& r, double dt, Output& out) noexcept {
  const auto& cp = ctl_.params();
  const double load = r.load;
  // (A reading that cannot be separated does not end a contact. Out of the cut it may start
  // one: taken for contact, the feed drops to the entry feed, which is the safe side.)
  if (r.sensing || !contact_.in_cut())
    (void)contact_.update(load, cp.air_threshold * applied_.limit, cp.air_time_s, dt,
                          r.feed_block && std::isfinite(load));
  out.contact = contact_.in_cut();
  // The load's mean over the last revolution: the controller's definition.
  if (out.contact && r.rpm > 0.0 && std::isfinite(load)) {
    out.load_rev = load_rev_.push(load, r.rpm);
  } else {
    load_rev_.restart();
    if (!out.contact) out.load_rev = 0.0;
  }
  out.load_percent = applied_.limit > 0.0 ? 100.0 * out.load_rev / applied_.limit : 0.0;
}

// Overload levels (Heidenhain AFC's), percentages of the reference (taught, else the limit).
inline void AdaptiveMachine::watch_overload(const Input& in, Output& out) noexcept {
  const auto* tl = tool_of(in.tool_number);
  const double ref = applied_.reference;
  out.overload_warn =
      tl != nullptr && tl->warn_pct > 0.0 && out.load_rev > tl->warn_pct / 100.0 * ref;
  if (tl != nullptr && tl->hold_pct > 0.0 && out.load_rev > tl->hold_pct / 100.0 * ref)
    overload_latched_ = true;
  out.overload_hold = overload_latched_;
}

// Teach-in: the program's feed; the reference when the cut has ended.
inline void AdaptiveMachine::teach_in(const LoadReading& r, double dt, Output& out) noexcept {
  if (applied_.mode == 3 && teach_.sample(r.load, r.rpm, dt, out.contact)) {
    Taught* t = taught_of(teach_tool_, teach_op_);
    if (t == nullptr && n_taught_ < kMaxTaught) t = &taught_[n_taught_++];
    if (t != nullptr) *t = {teach_tool_, teach_op_, teach_.reference()};
    out.teach.tool = teach_tool_;
    out.teach.operation = teach_op_;
    out.teach.reference = teach_.reference();
    ++out.teach.seq;
  }
}

// The factor on the program's feed that gives the controller's feed per revolution.
inline double AdaptiveMachine::program_feed_factor(const Input& in, double rpm) const noexcept {
  // The program's feed per revolution: motion reports the F word itself under G95, a velocity
  // [mm/s] under G94 (motion.requested-vel: without the feed scale).
  const double req = req_stable_;
  const double prog_per_rev = in.per_rev  ? (f_word_ > 0.0 && req > 4.0 * f_word_ ? f_word_ : req)
                              : rpm > 0.0 ? req * 60.0 / rpm
                                          : 0.0;
  // Above the program's feed up to the machine's maximum override (split_feed_override).
  return co_.feed_hold ? 0.0
         : prog_per_rev > 0.0
             ? std::clamp(co_.feed_per_rev_mm / prog_per_rev, 0.0, std::max(in.max_override, 1.0))
             : 1.0;
}

// The operator's knob times the factor; the ceiling to the feed scale, every decrease on
// adaptive-feed. Not enabled: the knob alone, on feed moves as before.
inline void AdaptiveMachine::write_feed(const Input& in, double factor, bool feed_block, bool held,
                                 double dt, Output& out) noexcept {
  const bool enabled = in.enable;
  const auto fo = split_feed_override(factor, in.knob, in.max_override, p_.override_step,
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
}

// The controller's decision and the machine's latches, as the outputs and the operation's
// record say them.
inline void AdaptiveMachine::write_state(const LoadReading& r, double dt, Output& out) noexcept {
  const auto& o = co_;
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
  stats_.sample(r.load, out.load_rev, load_rev_.full(), out.feed_factor, dt, out.contact);
  if (r.feed_block) op_feed_s_ += dt;
  if (r.feed_block && out.contact) {
    op_reasons_ |= reason_bit(o.reason);
    if (out.alarm && op_alarm_ == 0) op_alarm_ = static_cast<std::int32_t>(out.alarm_reason);
  }
}

// Seed 004's speed law drives the spindle in the cut while the program runs it; otherwise the
// program's speed passes through. Out of the cut (air, rapids) the law has no chip to act on:
// holding V_p at the tool's diameter there ran a forged shaft's 80 mm of neck, passed in air at
// feed per revolution, at 1263 rpm against the program's 1693 (the prior art's), and the whole
// 6 s by which seed 004 was slower than the prior art was that air (issue 47).
inline void AdaptiveMachine::write_spindle(const Input& in, bool regulating,
                                           Output& out) const noexcept {
  double rpm_out = in.rpm_programmed;
  if (in.enable && speed_law_ && regulating && co_.in_cut && in.rpm_programmed != 0.0)
    rpm_out = std::copysign(co_.rpm, in.rpm_programmed);
  out.spindle_speed_out = rpm_out;
  out.spindle_override = in.rpm_programmed != 0.0 ? rpm_out / in.rpm_programmed : 1.0;
}

void AdaptiveMachine::control(const Input& in, Output& out, double dt_measured) noexcept {
  const double dt = ctl_.params().period_s;
  LoadReading r;
  r.rpm = std::abs(in.rpm);
  r.feed_block = in.enable && is_feed_motion(in.motion_type);
  r.load = measured_load(in, r.feed_block, r.rpm, dt, out, r.sensing);
  const auto ci = controller_input(in, out, r, dt_measured);
  ctl_.update(ci, co_);
  out.cut_power_W = ci.cut_power_W;
  out.load = r.load;

  track_contact(r, dt, out);
  if (r.sensing) learn_specific_force(in, r.rpm, dt, out);
  out.specific_force_ratio = kappa_;
  watch_overload(in, out);
  teach_in(r, dt, out);

  const bool regulating = applied_.mode == 2;
  const double factor = r.feed_block && regulating ? program_feed_factor(in, r.rpm) : 1.0;
  const bool held = in.enable && (co_.feed_hold || bad_ || overload_latched_ || breakage_latched_ ||
                                  tool_data_latched_);
  write_feed(in, factor, r.feed_block, held, dt, out);
  write_state(r, dt, out);
  write_spindle(in, regulating, out);
}

}  // namespace lathectl::control
