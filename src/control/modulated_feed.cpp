#include "lathectl/control/modulated_feed.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "lathectl/core/parameter_error.hpp"

namespace lathectl::control {

namespace {

int level_of(int segment, int n_s) noexcept {
  return segment <= n_s ? segment : 2 * n_s - segment;
}

// Sums over the staircase's 2n_s segments, levels x + k_j·d: k = 0 and k = n_s once, 1 .. n_s−1
// twice. Up to kDirectMax increments they are summed term by term; above, in closed form by
// the digamma function ψ and its derivative ψ₁ (Σ_{k=1}^{n−1} 1/(x + k·d) = (ψ(a+n) − ψ(a+1))/d,
// Σ 1/(x + k·d)² = (ψ₁(a+1) − ψ₁(a+n))/d², a = x/d), so a re-plan costs the same at n_s = 1000
// as at n_s = 40 (it runs inside update()).
constexpr int kDirectMax = 32;

// ψ(y) − ln(y) and ψ₁(y) after shifting y to ≥ 10 by the recurrences ψ(y) = ψ(y+1) − 1/y,
// ψ₁(y) = ψ₁(y+1) + 1/y²; asymptotic series to y^−10 / y^−11 (error < 1e-15 at y ≥ 10).
struct Shifted {
  double y = 0.0;       // the shifted argument
  double psi_r = 0.0;   // ψ(y₀) = ln(y) + psi_r
  double psi1 = 0.0;    // ψ₁(y₀)
};
Shifted shifted(double y) noexcept {
  Shifted s;
  double r = 0.0, r1 = 0.0;
  while (y < 10.0) {
    r -= 1.0 / y;
    r1 += 1.0 / (y * y);
    y += 1.0;
  }
  const double iy = 1.0 / y, f = iy * iy;
  s.y = y;
  s.psi_r = r - 0.5 * iy -
            f * (1.0 / 12 - f * (1.0 / 120 - f * (1.0 / 252 - f * (1.0 / 240 - f / 132))));
  s.psi1 = r1 + iy + 0.5 * f +
           iy * f * (1.0 / 6 - f * (1.0 / 30 - f * (1.0 / 42 - f * (1.0 / 30 - f * 5.0 / 66))));
  return s;
}

// Σ_{k=1}^{n−1} 1/(x + k·d) and Σ_{k=1}^{n−1} 1/(x + k·d)² (n > kDirectMax), d > 0.
void inner_sums(double x, double d, int n, double& s1, double& s2) noexcept {
  const double a = x / d;
  const Shifted lo = shifted(a + 1.0), hi = shifted(a + n);
  // ψ(hi) − ψ(lo) with the logarithms' difference taken as log1p (no cancellation when a ≫ n).
  s1 = (std::log1p((hi.y - lo.y) / lo.y) + hi.psi_r - lo.psi_r) / d;
  s2 = (lo.psi1 - hi.psi1) / (d * d);
}

// Σ_{k=k0}^{k1} 1/(x + k·d) = (ψ(a + k1 + 1) − ψ(a + k0))/d, a = x/d, d > 0 (0 if k1 < k0).
double partial_sum(double x, double d, int k0, int k1) noexcept {
  if (k1 < k0) return 0.0;
  if (k1 - k0 < kDirectMax) {
    double s = 0.0;
    for (int k = k0; k <= k1; ++k) s += 1.0 / (x + k * d);
    return s;
  }
  const double a = x / d;
  const Shifted lo = shifted(a + k0), hi = shifted(a + k1 + 1.0);
  return (std::log1p((hi.y - lo.y) / lo.y) + hi.psi_r - lo.psi_r) / d;
}

// start + Σ_j 1/(x + k_j·d) and, if wanted, Σ_j 1/(x + k_j·d)² over one cycle.
double staircase_sum(double x, double d, int n_s, double start,
                     double* squares = nullptr) noexcept {
  double s1 = start, s2 = 0.0;
  if (n_s <= kDirectMax || !(d > 0.0)) {
    for (int j = 0; j < 2 * n_s; ++j) {
      const double inv = 1.0 / (x + level_of(j, n_s) * d);
      s1 += inv;
      s2 += inv * inv;
    }
  } else {
    double i1 = 0.0, i2 = 0.0;
    inner_sums(x, d, n_s, i1, i2);
    const double e0 = 1.0 / x, en = 1.0 / (x + n_s * d);
    s1 = start + e0 + en + 2.0 * i1;
    s2 = e0 * e0 + en * en + 2.0 * i2;
  }
  if (squares) *squares = s2;
  return s1;
}

// Time-mean feed of a staircase with the given levels (harmonic mean over equal path lengths).
double harmonic_mean(double s_min, double ds, int n_s) noexcept {
  return 2.0 * n_s / staircase_sum(s_min, ds, n_s, 0.0);
}

// S_min giving a time-mean feed of s_p for a span D = n_s·ΔS: the root of
//   f(x) = Σ_j 1/(x + k_j·ΔS) − 2n_s/s_p,
// convex and decreasing in x. Newton's method from x₀ = s_p − D/2 (there the harmonic mean is
// below the arithmetic one, so f(x₀) ≥ 0) climbs to the root without overshooting; a few steps
// reach machine precision. (It runs in the real-time path when the module re-plans; each step
// costs O(1) in n_s, see staircase_sum.)
double s_min_for_mean(double s_p, double span, int n_s) noexcept {
  const double ds = span / n_s;
  const double target = 2.0 * n_s / s_p;
  double x = std::max(1e-9, s_p - 0.5 * span);
  for (int it = 0; it < 30; ++it) {
    double sq = 0.0;
    const double f = staircase_sum(x, ds, n_s, -target, &sq);
    const double step = f / -sq;  // ≤ 0 while f ≥ 0
    x -= step;
    if (std::abs(step) <= 1e-13 * x) break;
  }
  return x;
}

}  // namespace

double ModulationPlan::time_mean_feed() const noexcept {
  if (!active()) return s_min_mm_per_min;
  return harmonic_mean(s_min_mm_per_min, ds_mm_per_min, n_s);
}

double ModulationPlan::offset_swing_mm(double s_other) const noexcept {
  if (!active()) return 0.0;
  const double x = s_min_mm_per_min, d = ds_mm_per_min;
  if (n_s > kDirectMax && d > 0.0) {
    // The increments dl·(1 − s_other/S_k) are negative below s_other and positive above, so the
    // running offset falls, rises through the top of the staircase and falls again: its extremes
    // are after the ascent's low levels (minimum), after the descent's high levels (maximum),
    // and at the cycle's ends. Partial sums in closed form (partial_sum), O(1) in n_s.
    const int n = n_s;
    const double k_star = (s_other - x) / d;  // levels below this run slower than s_other
    auto up = [&](int J) { return J <= 0 ? 0.0 : dl_mm * (J - s_other * partial_sum(x, d, 0, J - 1)); };
    const double top = up(n + 1);
    auto down = [&](int m) {
      return m <= 0 ? top : top + dl_mm * (m - s_other * partial_sum(x, d, n - m, n - 1));
    };
    const int j_min = static_cast<int>(std::clamp(std::ceil(k_star), 0.0, static_cast<double>(n + 1)));
    const int m_max =
        static_cast<int>(std::clamp(n - 1 - std::floor(k_star), 0.0, static_cast<double>(n - 1)));
    const double end = down(n - 1);
    const double lo = std::min({0.0, up(j_min), end});
    const double hi = std::max({0.0, top, down(m_max), end});
    return hi - lo;
  }
  double c = 0.0, lo = 0.0, hi = 0.0;
  for (int j = 0; j < 2 * n_s; ++j) {
    c += dl_mm * (1.0 - s_other / (s_min_mm_per_min + level_of(j, n_s) * ds_mm_per_min));
    lo = std::min(lo, c);
    hi = std::max(hi, c);
  }
  return hi - lo;
}

void ModulatedFeedGenerator::start(const ModulationPlan& plan) noexcept {
  plan_ = plan;
  segment_ = 0;
  in_segment_mm_ = 0.0;
}

void ModulatedFeedGenerator::retune(const ModulationPlan& plan) noexcept {
  if (!plan_.active() || !plan.active()) {
    start(plan);
    return;
  }
  const double fraction = in_segment_mm_ / plan_.dl_mm;
  const double phase = static_cast<double>(segment_) / (2.0 * plan_.n_s);
  plan_ = plan;
  segment_ = std::min(2 * plan.n_s - 1, static_cast<int>(phase * 2.0 * plan.n_s));
  in_segment_mm_ = fraction * plan.dl_mm;
}

double ModulatedFeedGenerator::feed() const noexcept {
  return plan_.s_min_mm_per_min + level_of(segment_, plan_.n_s) * plan_.ds_mm_per_min;
}

double ModulatedFeedGenerator::advance(double path_mm) noexcept {
  if (!plan_.active()) return plan_.s_min_mm_per_min;
  in_segment_mm_ += std::max(0.0, path_mm);
  // A long step may cross several segments (bounded: at most one cycle's worth of loops).
  for (int guard = 0; in_segment_mm_ >= plan_.dl_mm && guard < 2 * plan_.n_s; ++guard) {
    in_segment_mm_ -= plan_.dl_mm;
    segment_ = (segment_ + 1) % (2 * plan_.n_s);
  }
  if (in_segment_mm_ >= plan_.dl_mm) in_segment_mm_ = std::fmod(in_segment_mm_, plan_.dl_mm);
  return feed();
}

void ModulatedFeedController::configure(const Params& p) {
  auto require = [](bool ok, const char* what) {
    if (!ok) {
      // The parameter is the message's first word ("coefficient must be positive").
      const std::string w(what);
      throw core::ParameterError(w.substr(0, w.find(' ')), "modulated feed: " + w);
    }
  };
  require(p.period_s > 0.0, "period_s must be positive");
  require(p.coefficient > 0.0, "coefficient must be positive");
  require(p.part_mass_kg > 0.0, "part_mass_kg must be positive");
  require(p.radial_force_ratio > 0.0, "radial_force_ratio must be positive");
  require(p.force_feed_exponent > 0.0 && p.force_feed_exponent <= 1.5,
          "force_feed_exponent must be in (0, 1.5]");
  require(p.modulation_frequency_Hz > 0.0, "modulation_frequency_Hz must be positive");
  require(p.drive_bandwidth_Hz > 0.0, "drive_bandwidth_Hz must be positive");
  require(p.n_s >= 1 && p.n_s <= 1000, "n_s must be in 1..1000");
  require(p.ds_quantum_mm_per_min > 0.0, "ds_quantum_mm_per_min must be positive");
  require(p.resolution_mm > 0.0, "resolution_mm must be positive");
  require(p.s_min_fraction > 0.0 && p.s_min_fraction < 1.0, "s_min_fraction must be in (0, 1)");
  require(p.s_max_fraction > 1.0, "s_max_fraction must exceed 1");
  require(p.engage_time_s >= 0.0 && p.release_time_s >= 0.0,
          "engage_time_s and release_time_s must be non-negative");
  require(p.replan_period_s > 0.0,
          "replan_period_s must be positive");
  p_ = p;
  configured_ = true;
  gen_.stop();
  engaged_ = false;
  was_block_ = false;
  counts_ = {};
}

ModulationPlan ModulatedFeedController::plan_for(double a0, double omega_d, double cut_power_W,
                                                 double speed_m_per_min, double s_p, double rpm,
                                                 double& omega_m, double& required_N,
                                                 double& planned_N, bool& limited) const noexcept {
  using std::numbers::pi;
  limited = false;
  ModulationPlan plan{};
  plan.n_s = p_.n_s;
  // ω_m: the wanted frequency, below a quarter of the drives' bandwidth, and out of the
  // entrainment bands around ω_d·{1/3, 1/2, 1, 2, 3} (±15 %): if inside one, go below it.
  double f_m = std::min(p_.modulation_frequency_Hz, 0.25 * p_.drive_bandwidth_Hz);
  const double f_d = omega_d / (2.0 * pi);
  for (double ratio : {3.0, 2.0, 1.0, 0.5, 1.0 / 3.0}) {
    const double c = ratio * f_d;
    if (f_m > 0.85 * c && f_m < 1.15 * c) f_m = 0.8 * c;
  }
  // Δl from the cycle length at the programmed feed, in whole resolution units (≥ 1).
  auto set_dl = [&](double dl) {
    plan.dl_mm = std::max(1.0, std::ceil(dl / p_.resolution_mm - 1e-9)) * p_.resolution_mm;
    omega_m = 2.0 * pi * (s_p / 60.0) / plan.cycle_length_mm();
    required_N =
        p_.coefficient * a0 * p_.part_mass_kg * std::abs(omega_d * omega_d - omega_m * omega_m);
  };
  set_dl(s_p / 60.0 / f_m / (2.0 * p_.n_s));
  // Force along the vibration from the cutting power: F = r·N_c/V.
  const double force = p_.radial_force_ratio * cut_power_W / (speed_m_per_min / 60.0);
  const double e = p_.force_feed_exponent;
  auto amplitude = [&](double s_min, double s_max) {
    return 0.5 * force * (std::pow(s_max / s_p, e) - std::pow(s_min / s_p, e));
  };
  // Largest span the limits allow: S_min ≥ f_min·S_p and S_max ≤ f_max·S_p with the mean kept.
  auto within = [&](double span) {
    const double lo = s_min_for_mean(s_p, span, p_.n_s);
    return lo >= p_.s_min_fraction * s_p && lo + span <= p_.s_max_fraction * s_p;
  };
  double span_max = 0.0, hi = (p_.s_max_fraction - p_.s_min_fraction) * s_p;
  for (int it = 0; it < 45; ++it) {
    const double mid = 0.5 * (span_max + hi);
    (within(mid) ? span_max : hi) = mid;
  }
  // Smallest span meeting the quenching condition (A_P rises with the span).
  double span = 0.0;
  const double s_lo_max = s_min_for_mean(s_p, span_max, p_.n_s);
  if (amplitude(s_lo_max, s_lo_max + span_max) < required_N) {
    span = span_max;
    limited = true;
  } else {
    double lo = 0.0, up = span_max;
    for (int it = 0; it < 45; ++it) {
      const double mid = 0.5 * (lo + up);
      const double s = s_min_for_mean(s_p, mid, p_.n_s);
      (amplitude(s, s + mid) < required_N ? lo : up) = mid;
    }
    span = up;
  }
  // ΔS in whole quanta (rounded up so the condition still holds, down if that breaks a limit).
  const double q = p_.ds_quantum_mm_per_min;
  plan.ds_mm_per_min = std::max(q, std::ceil(span / p_.n_s / q - 1e-9) * q);
  if (!within(plan.ds_mm_per_min * p_.n_s) && plan.ds_mm_per_min > q)
    plan.ds_mm_per_min = std::max(q, std::floor(span_max / p_.n_s / q) * q);
  const double full = plan.ds_mm_per_min * p_.n_s;
  plan.s_min_mm_per_min = std::max(q, std::round(s_min_for_mean(s_p, full, p_.n_s) / q) * q);
  // Desynchronise the turrets (feed division): lengthen Δl until the offset swing reaches
  // desync_fraction · s. The swing is proportional to Δl.
  if (p_.desync_fraction > 0.0 && rpm > 0.0) {
    const double swing = plan.offset_swing_mm(s_p);
    const double wanted = p_.desync_fraction * s_p / rpm;
    if (swing > 0.0 && swing < wanted) set_dl(plan.dl_mm * wanted / swing);
  }
  planned_N = amplitude(plan.s_min_mm_per_min, plan.s_max_mm_per_min());
  if (planned_N < required_N * (1.0 - 1e-3)) limited = true;  // (quantisation of S_min)
  return plan;
}

void ModulatedFeedController::apply(const ModulationPlan& plan, double a0) noexcept {
  if (engaged_)
    gen_.retune(plan);
  else
    gen_.start(plan);
  engaged_ = true;
  a0_planned_ = a0;
  since_plan_s_ = 0.0;
}

bool ModulationPlanner::run(const ModulatedFeedController& c) noexcept {
  alive_.store(true, std::memory_order_release);
  if (!requests_.fetch()) return false;
  const Request q = requests_.front();  // a request not planned yet (fetch: only new ones)
  Result& r = results_.back();
  r.id = q.id;
  r.a0_m = q.a0_m;
  r.plan = c.plan_for(q.a0_m, q.omega_d, q.cut_power_W, q.speed_m_per_min, q.feed_programmed,
                      q.rpm, r.omega_m, r.required_N, r.planned_N, r.limited);
  results_.publish();
  return true;
}

// update()'s phases.

// A programmed modulation (the NC's plan): started with the block, followed along the path.
void ModulatedFeedController::follow_programmed(const Input& in, int t, double step,
                                                Output& out) noexcept {
  if (!gen_.plan().active() && in.programmed.active()) gen_.start(in.programmed);
  out.plan = gen_.plan();
  out.engaged = out.plan.active();
  if (out.engaged) {
    out.feed_mm_per_min[t] = gen_.advance(step);
    out.omega_m_rad_per_s =
        2.0 * std::numbers::pi * (out.plan.time_mean_feed() / 60.0) / out.plan.cycle_length_mm();
  }
  out.reason = Reason::ModulationProgrammed;
}

// The planner's answer to the request waiting, when it has come: the plan applied.
void ModulatedFeedController::take_planner_answer(Output& out) noexcept {
  if (planner_ && waiting_id_ != 0 && planner_->results_.fetch() &&
      planner_->results_.front().id == waiting_id_) {  // the planner's answer
    const auto& r = planner_->results_.front();
    omega_m_ = r.omega_m;
    required_N_ = r.required_N;
    planned_N_ = r.planned_N;
    limited_ = r.limited;
    apply(r.plan, r.a0_m);
    ++counts_.taken;
    waiting_id_ = 0;
    out.reason = Reason::ModulationEngaged;
  }
}

// A plan for the vibration measured: posted to the planner thread (its answer comes in a later
// call), or made here without one; none without the cutting force it needs.
void ModulatedFeedController::request_plan(const Input& in, double s_p, Output& out) noexcept {
  if (!(in.cut_power_W > 0.0) || !(in.speed_m_per_min > 0.0) || !(s_p > 0.0)) {
    out.reason = Reason::ModulationNoForce;
  } else if (planner_ && planner_->alive()) {  // post it; the plan comes back in a later call
    const double a0 = std::max(in.a0_m, a0_planned_);
    waiting_id_ = ++next_id_ == 0 ? ++next_id_ : next_id_;
    auto& q = planner_->requests_.back();
    q = {waiting_id_, a0, in.omega_d_rad_per_s, in.cut_power_W, in.speed_m_per_min, s_p, in.rpm};
    planner_->requests_.publish();
  } else {
    const double a0 = std::max(in.a0_m, a0_planned_);
    const ModulationPlan plan =
        plan_for(a0, in.omega_d_rad_per_s, in.cut_power_W, in.speed_m_per_min, s_p, in.rpm,
                 omega_m_, required_N_, planned_N_, limited_);
    apply(plan, a0);
    ++counts_.made_inline;
    out.reason = Reason::ModulationEngaged;
  }
}

void ModulatedFeedController::update(const Input& in, Output& out) noexcept {
  out = Output{};
  if (!configured_) return;
  const int t = static_cast<int>(in.turret);
  for (int k = 0; k < 2; ++k) out.feed_mm_per_min[k] = in.feed_programmed_mm_per_min[k];

  // A new block (or the turret flag changed): modulation ends, the staircase restarts.
  const bool new_block = in.feed_block && (!was_block_ || in.turret != turret_);
  if (!in.feed_block || new_block) {
    if (engaged_) out.reason = Reason::ModulationReleased;
    engaged_ = false;
    gen_.stop();
    above_s_ = below_s_ = 0.0;
    a0_planned_ = 0.0;
    waiting_id_ = 0;  // a plan still coming is for the old block
  }
  was_block_ = in.feed_block;
  turret_ = in.turret;
  if (!in.feed_block) return;
  const double step = new_block ? 0.0 : in.path_mm[t] - last_path_[t];
  last_path_[0] = in.path_mm[0];
  last_path_[1] = in.path_mm[1];
  const double s_p = in.feed_programmed_mm_per_min[t];

  if (in.source == ModulationSource::Programmed) {
    follow_programmed(in, t, step, out);
    return;
  }
  if (in.source == ModulationSource::None) return;

  // Automatic: a0 = 0 and ω_d = 0 below the amplifier's dead zone.
  const bool vibrating = in.a0_m > 0.0 && in.omega_d_rad_per_s > 0.0 && std::isfinite(in.a0_m) &&
                         std::isfinite(in.omega_d_rad_per_s);
  above_s_ = vibrating ? above_s_ + p_.period_s : 0.0;
  below_s_ = vibrating ? 0.0 : below_s_ + p_.period_s;
  since_plan_s_ += p_.period_s;

  if (engaged_ && p_.release_below_dead_zone && below_s_ >= p_.release_time_s) {
    engaged_ = false;
    gen_.stop();
    a0_planned_ = 0.0;
    waiting_id_ = 0;
    out.reason = Reason::ModulationReleased;
    return;
  }
  take_planner_answer(out);
  const bool want_plan =
      vibrating && above_s_ >= p_.engage_time_s && waiting_id_ == 0 &&
      (!engaged_ || (since_plan_s_ >= p_.replan_period_s && in.a0_m > a0_planned_));
  if (want_plan) request_plan(in, s_p, out);
  if (engaged_) {
    out.feed_mm_per_min[t] = gen_.advance(step);
    out.plan = gen_.plan();
    out.engaged = true;
    out.omega_m_rad_per_s = omega_m_;
    out.force_amplitude_required_N = required_N_;
    out.force_amplitude_planned_N = planned_N_;
    if (out.reason == Reason::None)
      out.reason = limited_ ? Reason::ModulationLimited : Reason::ModulationEngaged;
  }
}

}  // namespace lathectl::control
