#include "lathectl/control/operation_control.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace lathectl::control {

void IdleTare::configure(const Params& p) {
  if (!(p.rpm_max > 0.0) || !(p.rpm_min >= 0.0) || !(p.rpm_min < p.rpm_max) || !(p.tau_s > 0.0) ||
      !(p.steady_rpm_per_s > 0.0) || !(p.settle_s >= 0.0))
    throw std::invalid_argument(
        "idle tare: need 0 ≤ rpm_min < rpm_max, tau > 0, steady rate > 0, settle ≥ 0");
  *this = IdleTare{};
  p_ = p;
}

void IdleTare::update(double rpm, double drive_power_W, double dt, bool air) noexcept {
  const double n = std::abs(rpm);
  const double rate = dt > 0.0 ? std::abs(n - last_rpm_) / dt : 0.0;
  last_rpm_ = n;
  const std::size_t tail = (pend_head_ + kPending - pend_count_) % kPending;
  if (!(rate <= p_.steady_rpm_per_s)) {  // a speed change: the last settle_s is not idle power
    steady_s_ = 0.0;
    pend_count_ = 0;
    return;
  }
  steady_s_ += dt;
  const bool usable = air && steady_s_ >= p_.settle_s && n >= p_.rpm_min && n <= p_.rpm_max &&
                      std::isfinite(drive_power_W) && dt > 0.0;
  if (!usable) {  // the speed held: what is pending was idle at a steady speed
    for (; pend_count_ > 0; --pend_count_) {
      const std::size_t k = (pend_head_ + kPending - pend_count_) % kPending;
      learn(pend_rpm_[k], pend_power_[k], dt);
    }
    return;
  }
  if (pend_count_ == kPending || static_cast<double>(pend_count_) * dt >= p_.settle_s) {
    learn(pend_rpm_[tail], pend_power_[tail], dt);  // the speed stayed steady settle_s after it
    --pend_count_;
  }
  pend_rpm_[pend_head_] = n;
  pend_power_[pend_head_] = drive_power_W;
  pend_head_ = (pend_head_ + 1) % kPending;
  ++pend_count_;
}

void IdleTare::learn(double n, double drive_power_W, double dt) noexcept {
  const auto k = std::min(kBins - 1, static_cast<std::size_t>(n / p_.rpm_max * kBins));
  if (weight_s_[k] == 0.0) {
    power_[k] = drive_power_W;
    rpm_[k] = n;
    ++populated_;
  } else {
    // A running mean: the plain mean while the bin is young, then exponential (tau_s).
    const auto mean = core::FirstOrderLag::with_gain(dt / std::min(weight_s_[k] + dt, p_.tau_s));
    power_[k] = mean.step_increment(power_[k], drive_power_W);
    rpm_[k] = mean.step_increment(rpm_[k], n);
  }
  weight_s_[k] += dt;
  dirty_ = true;
  fit();
}

void IdleTare::fit() noexcept {
  if (!dirty_) return;
  dirty_ = false;
  // Least squares of p0 + p1·x + p2·x² (x = n/1000) over the learned bins, one equation each.
  // Fewer than three bins (or a range too narrow for a curvature): a line, or a constant.
  double s[5] = {0, 0, 0, 0, 0}, b[3] = {0, 0, 0};
  double lo = 1e300, hi = -1e300;
  for (std::size_t k = 0; k < kBins; ++k) {
    if (weight_s_[k] == 0.0) continue;
    const double x = rpm_[k] / 1000.0;
    double xp = 1.0;
    for (int i = 0; i < 5; ++i, xp *= x) s[i] += xp;
    b[0] += power_[k];
    b[1] += power_[k] * x;
    b[2] += power_[k] * x * x;
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  const double n = s[0];
  c_ = {0.0, 0.0, 0.0};
  if (n == 0.0) return;
  const double span = hi - lo;
  if (n >= 3.0 && span > 0.2 * p_.rpm_max / 1000.0) {
    // Cramer's rule on the 3×3 normal equations.
    const double m[3][3] = {{s[0], s[1], s[2]}, {s[1], s[2], s[3]}, {s[2], s[3], s[4]}};
    auto det3 = [](const double a[3][3]) {
      return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
             a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
             a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    };
    const double d = det3(m);
    if (std::abs(d) > 1e-12 * std::max(1.0, s[4] * s[4] * s[0])) {
      double q[3];
      for (int j = 0; j < 3; ++j) {
        double mj[3][3];
        for (int r = 0; r < 3; ++r)
          for (int col = 0; col < 3; ++col) mj[r][col] = col == j ? b[r] : m[r][col];
        q[j] = det3(mj) / d;
      }
      c_ = {q[0], q[1] / 1000.0, q[2] / 1e6};
      return;
    }
  }
  if (n >= 2.0 && span > 0.0) {
    const double d = s[0] * s[2] - s[1] * s[1];
    const double q1 = (s[0] * b[1] - s[1] * b[0]) / d;
    c_ = {(b[0] - q1 * s[1]) / s[0], q1 / 1000.0, 0.0};
    return;
  }
  c_ = {b[0] / s[0], 0.0, 0.0};
}

double IdleTare::idle_W(double rpm) const noexcept {
  if (populated_ == 0) return std::numeric_limits<double>::quiet_NaN();
  const double n = std::abs(rpm);
  return c_[0] + c_[1] * n + c_[2] * n * n;
}

double IdleTare::nearest_bin_rpm(double rpm) const noexcept {
  const double n = std::abs(rpm);
  double best = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t k = 0; k < kBins; ++k)
    if (weight_s_[k] != 0.0 && !(std::abs(rpm_[k] - n) >= std::abs(best - n))) best = rpm_[k];
  return best;
}

bool IdleTare::covers(double rpm) const noexcept {
  const double n = std::abs(rpm);
  const double near = std::max(0.1 * n, p_.rpm_max / static_cast<double>(kBins));
  double lo = 1e300, hi = -1e300;
  for (std::size_t k = 0; k < kBins; ++k) {
    if (weight_s_[k] == 0.0) continue;
    if (std::abs(rpm_[k] - n) <= near) return true;
    lo = std::min(lo, rpm_[k]);
    hi = std::max(hi, rpm_[k]);
  }
  return populated_ >= 3 && n >= lo && n <= hi;
}

void TeachIn::start() noexcept {
  const Params p = p_;
  *this = TeachIn{};
  p_ = p;
  running_ = true;
}

void TeachIn::take(double sum, double n) noexcept {
  sum_ += sum;
  n_ += n;
  revs_ += 1.0;
}

bool TeachIn::sample(double load, double rpm, double dt, bool in_cut) noexcept {
  if (!running_) return false;
  if (!in_cut || !std::isfinite(load) || !(rpm > 0.0)) {
    if (cutting_) {
      // The exit: of the revolutions held back, those like the steady cut are taken (oldest
      // first, up to the first that is not), never the last whole one nor the partial one.
      cutting_ = false;
      for (std::size_t i = 0; i + 1 < held_count_; ++i) {
        const std::size_t k = (held_head_ + kHeld - held_count_ + i) % kHeld;
        const double m = held_sum_[k] / held_n_[k];
        const double ref = n_ > 0.0 ? sum_ / n_ : m;
        if (std::abs(m - ref) > p_.steady_tol * std::abs(ref)) break;
        take(held_sum_[k], held_n_[k]);
      }
      held_count_ = 0;
      if (revs_ >= p_.min_revs && n_ > 0.0) {
        reference_ = sum_ / n_;
        running_ = false;
        return true;
      }
      sum_ = n_ = revs_ = 0.0;  // too short a cut to teach: wait for the next one
    }
    return false;
  }
  if (!cutting_) {
    cutting_ = true;
    steady_ = false;
    last_rev_mean_ = 0.0;
    t_in_revs_ = rev_phase_ = 0.0;
    cur_sum_ = cur_n_ = 0.0;
    held_count_ = 0;
  }
  const double revs = dt * rpm / 60.0;
  t_in_revs_ += revs;
  cur_sum_ += load;
  cur_n_ += 1.0;
  rev_phase_ += revs;
  if (rev_phase_ < 1.0) return false;
  rev_phase_ -= 1.0;  // a whole revolution
  if (!steady_) {     // settling: is this revolution like the one before?
    const double m = cur_sum_ / cur_n_;
    steady_ = t_in_revs_ >= p_.settle_revs &&
              std::abs(m - last_rev_mean_) <= p_.steady_tol * std::abs(last_rev_mean_);
    last_rev_mean_ = m;
  } else {
    if (held_count_ == kHeld) {  // the oldest held revolution is surely not the exit
      const std::size_t k = held_head_;  // == the oldest when the ring is full
      take(held_sum_[k], held_n_[k]);
      --held_count_;
    }
    held_sum_[held_head_] = cur_sum_;
    held_n_[held_head_] = cur_n_;
    held_head_ = (held_head_ + 1) % kHeld;
    ++held_count_;
  }
  cur_sum_ = cur_n_ = 0.0;
  return false;
}

void OperationStats::sample(double load, double load_rev, bool whole_rev, double feed_factor,
                            double dt, bool in_cut) noexcept {
  t_ += dt;
  if (!in_cut || !std::isfinite(load)) return;
  t_cut_ += dt;
  feed_min_ = std::min(feed_min_, feed_factor);
  feed_int_ += feed_factor * dt;
  load_int_ += load * dt;
  if (whole_rev && std::isfinite(load_rev)) rev_peak_ = std::max(rev_peak_, load_rev);
}

bool PathBreakage::update(double load, double limit, double nominal_depth_mm,
                          double guaranteed_depth_mm, double dt) noexcept {
  if (!std::isfinite(load) || !(limit > 0.0)) return false;
  // Kept if loaded, as its level: fell_to asks only whether one lies in the window, and equal
  // levels keep the queue at one sample (no aging of a queue of loads each period).
  collapse_.push(0.5 * limit, dt, load > 0.5 * limit);
  if (load > 0.5 * limit) {
    depth_high_ = nominal_depth_mm;
    return false;
  }
  return collapse_.fell_to(load, p_.air * limit) &&
         guaranteed_depth_mm >= std::max(p_.min_depth_mm, p_.keep * depth_high_);
}

SettingError check_limit(double limit, const OperationRating& r) noexcept {
  if (!std::isfinite(limit)) return SettingError::LimitNotFinite;
  if (limit < 0.0) return SettingError::LimitNegative;
  if (limit > r.limit_max) return SettingError::LimitAboveRating;
  return SettingError::None;
}

SettingError check_feeds(double feed_min, double feed_max, const OperationRating& r) noexcept {
  if (!std::isfinite(feed_min) || !std::isfinite(feed_max) || feed_min < 0.0 || feed_max < 0.0 ||
      feed_max > r.feed_max_mm_per_rev || (feed_min > 0.0 && feed_max > 0.0 && feed_min >= feed_max))
    return SettingError::FeedBounds;
  return SettingError::None;
}

FeedOverride split_feed_override(double factor, double knob, double max, double step,
                                 double scale_before, double scale_in_motion,
                                 bool feed_move) noexcept {
  if (!(max > 0.0) || !std::isfinite(max)) max = 1.0;
  knob = knob > 0.0 ? std::min(knob, max) : 0.0;  // NaN → 0
  factor = factor > 0.0 ? factor : 0.0;
  FeedOverride o;
  o.net = feed_move ? std::min(knob * factor, max) : knob;
  o.scale = feed_move ? std::max({scale_before > 0.0 ? std::min(scale_before, max) : 0.0, o.net,
                                  knob})
                      : knob;
  if (step > 0.0) o.scale = std::min(std::ceil(o.scale / step - 1e-9) * step, max);
  const double divisor = std::max(o.scale, scale_in_motion > 0.0 ? scale_in_motion : 0.0);
  o.adaptive = !feed_move ? 1.0 : divisor > 0.0 ? std::min(1.0, o.net / divisor) : 0.0;
  return o;
}

}  // namespace lathectl::control
