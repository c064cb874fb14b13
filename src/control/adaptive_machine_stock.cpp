// AdaptiveMachine's phases that run on the stock model (z_origin_mm): the chip every servo period
// and the path-aware breakage detector on it, the feed-forward from the depth ahead, and κ, the
// specific force the cut shows. The rest of the class is in adaptive_machine.cpp.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "lathectl/control/adaptive_machine.hpp"

namespace lathectl::control {

void AdaptiveMachine::follow_stock(const cutting::LathePlant& plant) {
  if (stock_) stock_->follow(&plant);
}

const cutting::LathePlant::Output& AdaptiveMachine::stock_chip() noexcept {
  if (stock_chip_due_) {
    stock_->chip(stock_out_);
    stock_chip_due_ = false;
  }
  return stock_out_;
}

// The stock model's chip every servo period, and the path-aware breakage detector on it: the
// stop comes in the period the load collapses.
void AdaptiveMachine::watch_path(const Input& in, Output& out, bool feed_move, double dt) noexcept {
  cutting::LathePlant::Input si;
  si.x_mm = in.homed ? in.x_mm : std::nan("");
  si.z_mm = in.homed ? in.z_mm : std::nan("");
  si.rpm = in.rpm;
  cutting::LathePlant::Output so;
  stock_->cut_geometry(si, dt, so);  // the chip's geometry alone, for the time that passed
  stock_out_ = so;
  stock_chip_due_ = true;
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
    breakage_.skip(dt);
  else if (feed_move && applied_.mode == 2 &&
           breakage_.update(p_.power_sensor ? out.load : in.force, applied_.limit, depth,
                            guaranteed, dt) &&
           !tool_data_latched_)
    breakage_latched_ = true;
  if (!feed_move) breakage_.reset();
  out.breakage = breakage_latched_;
  if (breakage_latched_) {
    hold(out);
    if (!(tool_data_latched_ && tool_data_first_)) out.alarm_reason = Reason::ToolBreakage;
  }
}

// The handbook law's load at a chip (the load's own parameter: N, or W with the power sensor),
// at nominal hardness and a sharp tool.
double AdaptiveMachine::model_load(double t, double s, double v) const noexcept {
  const auto f = model_.forces_pz_py({t, s, v, 1.0, 1.0});  // the load is Pz, Py or Pz·V
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
      out.contact ? std::max(stock_out_.engaged_depth_mm, stock_chip().chip_depth_mm) : 0.0;
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
// cells of travel agree: no step, entry or exit inside the window). Also its trend, d ln κ/dt:
// ln κ less its own lag over one revolution, over that revolution (a ramp r reads r after a
// revolution or two); forgotten whenever the cut is not steady.
void AdaptiveMachine::learn_specific_force(const Input& in, double rpm, double dt,
                                           const Output& out) noexcept {
  const bool trend = kappa_trend_;
  kappa_trend_ = false;
  kappa_rate_ = 0.0;
  if (!stock_ || !p_.feed_forward || !out.contact || !load_rev_.full() || !(rpm > 0.0)) return;
  const auto& so = stock_chip();
  const double t = so.chip_depth_mm;
  const double s = so.feed_per_rev_mm;
  if (!(t > 0.05) || !(s > 0.01) || std::abs(so.engaged_depth_mm - t) > 0.05 * t) return;
  if (!(out.load_rev > ctl_.params().air_threshold * applied_.limit)) return;
  const double v = in.cutting_speed_m_per_min > 0.0
                       ? in.cutting_speed_m_per_min
                       : std::numbers::pi * 2.0 * (std::abs(in.x_mm) + t) * rpm / 1000.0;
  const double m = model_load(t, s, v);
  if (!(m > 0.0) || !std::isfinite(m)) return;
  const double k = std::clamp(out.load_rev / m, 0.2, 5.0);
  kappa_ = core::FirstOrderLag(dt, p_.specific_force_time_s).step_increment(kappa_, k);
  kappa_learned_ = true;
  const double ln_k = std::log(k);
  const double rev_s = 60.0 / rpm;
  ln_kappa_lag_ = trend ? core::FirstOrderLag(dt, rev_s).step_increment(ln_kappa_lag_, ln_k) : ln_k;
  kappa_rate_ = (ln_k - ln_kappa_lag_) / rev_s;
  kappa_trend_ = true;
}

// The drift of the feed a rising specific force takes at the limit (a hard spot coming into
// the chip) [mm/rev per s; ≤ 0]. At the limit L = κ·M(t, s, V) with M ∝ s^y (y the law's feed
// exponent, on power too: P = Pz·V), so holding L while κ rises takes
//   d ln s/dt = −(1/y)·d ln κ/dt,   ds/dt = −(s/y)·d ln κ/dt.
// The regulator's integral alone follows such a ramp only with an error of the ramp's rate over
// its integral gain: a hardness rising 30 % over 5 mm at 0.45 mm/rev is 3 % of load a
// revolution, and the per-revolution load ran 6-8 % over its limit on generated forged shafts
// (issue 47). Fed to the integral, it follows the ramp; the regulator corrects what is left.
// Only near the limit (the per-revolution load within 5 % below it or above): a harder spot
// under a load well below the limit takes no lower feed.
double AdaptiveMachine::hardness_drift(const Output& out) const noexcept {
  if (!kappa_trend_ || !(kappa_rate_ > 0.0) || applied_.mode != 2 || !out.contact) return 0.0;
  if (!(out.load_rev >= 0.95 * applied_.limit) || !(feed_exponent_ > 0.0)) return 0.0;
  const double s = co_.feed_per_rev_mm;
  return s > 0.0 ? -s * kappa_rate_ / feed_exponent_ : 0.0;
}

}  // namespace lathectl::control
