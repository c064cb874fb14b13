// The recommendation of `lathectl lobes` (lobes.hpp, recommend_pockets): the best pockets of the
// frequency-domain envelope, each with a depth a machinist can set.
//
// The envelope b(n) is sampled on kGrid + 1 speeds across the range (envelope_depth is
// O(runs · log points) a query); each local maximum is a pocket's top (a cusp where two lobes
// cross, or a range end where the envelope still rises). A speed no lobe reaches has no known
// limit and is never recommended.
// At the top n_top, of depth b_top:
//   b_rec = min(b_top/S, b_P, b_T),  S the safety factor,
//   b_P = P_max/(k_c·h·v),  v = π·D·n/60   (spindle power P = F_c·v, F_c = k_c·b·h),
//   b_T = 2·T_max/(k_c·h·D)               (spindle torque T = F_c·D/2),
//   Q = v·h·b_rec                         (metal-removal rate).
// The top is a cusp: one side falls steeply (the next lobe), so the speed recommended is the
// middle of the interval around the top in which b(n) ≥ b_rec, and the margins are the distances
// in rpm from it to the interval's ends: how far the spindle speed (or, proportionally, the
// structure's frequencies) may drift before the recommended depth chatters.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "systems/b_chatter/lobes.hpp"

namespace lathectl::systems::b_chatter {

namespace {
constexpr int kGrid = 20000;  // b_part.toml: 1800 rpm / 20000 = 0.09 rpm a step
// The least margin, relative to the speed, of a pocket ranked as usable: 1 % is about what a
// spindle's speed holds under load and what a tap test's frequencies shift between set-ups.
constexpr double kMinMargin = 0.01;

// The envelope b(n) on the grid; a speed no lobe reaches (the lobes' grid ends short of a range
// end, or the measured band is too narrow) has no known limit, which is not a stable speed: -inf.
struct Envelope {
  std::vector<double> n, b;
  std::size_t last = 0;

  // The speed interval around grid index i where the envelope stays at or above depth b_min.
  std::pair<std::size_t, std::size_t> interval(std::size_t i, double b_min) const {
    std::size_t lo = i, hi = i;
    while (lo > 0 && b[lo - 1] >= b_min) --lo;
    while (hi < last && b[hi + 1] >= b_min) ++hi;
    return {lo, hi};
  }
};

Envelope envelope_on_grid(const dynamics::FrequencyDomainResult& fd, const LobesInput& in) {
  Envelope e;
  e.n.resize(kGrid + 1);
  e.b.resize(kGrid + 1);
  for (int k = 0; k <= kGrid; ++k) {
    const auto i = static_cast<std::size_t>(k);
    e.n[i] = in.min_rpm + (in.max_rpm - in.min_rpm) * k / kGrid;
    e.b[i] = dynamics::envelope_depth(fd, e.n[i]);
    if (!std::isfinite(e.b[i])) e.b[i] = -std::numeric_limits<double>::infinity();
  }
  e.last = e.n.size() - 1;
  return e;
}

// The pockets' tops: local maxima (a run of equal values, e.g. +inf, counts once, at its middle).
std::vector<std::size_t> pocket_tops(const Envelope& e) {
  std::vector<std::size_t> tops;
  const auto& b = e.b;
  for (std::size_t i = 0; i <= e.last;) {
    std::size_t j = i;
    while (j < e.last && b[j + 1] == b[i]) ++j;
    const bool left_ok = i == 0 || b[i - 1] < b[i];
    const bool right_ok = j == e.last || b[j + 1] < b[i];
    if (left_ok && right_ok && b[i] > 0.0) tops.push_back((i + j) / 2);
    i = j + 1;
  }
  return tops;
}

// The spindle's limits on the depth: b_P (power) and b_T (torque) at a speed.
struct Spindle {
  const LobesRecommend& r;
  double kc, h, D;

  double depth(double rpm, std::string& by) const {
    const double v = std::numbers::pi * D * rpm / 60.0;
    double depth = std::numeric_limits<double>::infinity();
    if (r.power_W > 0.0 && r.power_W / (kc * h * v) < depth) {
      depth = r.power_W / (kc * h * v);
      by = "power";
    }
    if (r.torque_Nm > 0.0 && 2.0 * r.torque_Nm / (kc * h * D) < depth) {
      depth = 2.0 * r.torque_Nm / (kc * h * D);
      by = "torque";
    }
    return depth;
  }
};

// The pocket at a top and its stable interval; false when neither chatter nor the machine bounds
// its depth.
bool pocket_at(std::size_t top, const Envelope& e, const Spindle& sp, Pocket& p,
               std::pair<std::size_t, std::size_t>& span) {
  const auto &n = e.n, &b = e.b;
  const double chatter_depth = b[top] / sp.r.safety_factor;
  // The depth: the pocket's top over the safety factor, or what the spindle allows; the speed:
  // the middle of the interval in which the envelope stays above that depth, so the speed may
  // drift equally either way (twice: the spindle's limit depends on the speed).
  std::size_t at = top;
  double depth = chatter_depth;
  for (int pass = 0; pass < 2; ++pass) {
    std::string by = "chatter";
    const double m = sp.depth(n[at], by);
    depth = std::min(chatter_depth, m);
    if (!std::isfinite(depth)) break;
    const auto [lo, hi] = e.interval(top, depth);
    at = (lo + hi) / 2;
  }
  if (!std::isfinite(depth)) return false;
  std::string by = "chatter";
  const double m = sp.depth(n[at], by);
  p.limited_by = m < chatter_depth ? by : "chatter";
  p.depth_m = std::min(chatter_depth, m);
  p.pocket_top_rpm = n[top];
  p.pocket_top_depth_m = b[top];
  p.speed_rpm = n[at];
  p.limit_depth_m = b[at];
  const double v = std::numbers::pi * sp.D * n[at] / 60.0;
  p.mrr_m3_per_s = v * sp.h * p.depth_m;
  p.power_W = sp.kc * p.depth_m * sp.h * v;
  p.torque_Nm = sp.kc * p.depth_m * sp.h * sp.D / 2.0;
  span = e.interval(at, p.depth_m);
  const auto [lo, hi] = span;
  // The range's ends (or the speeds next to them no lobe reaches): the lobes beyond are not
  // computed, so the margin that side is only known to be at least this.
  p.below_reaches_range_end = lo == 0 || !std::isfinite(b[lo - 1]);
  p.above_reaches_range_end = hi == e.last || !std::isfinite(b[hi + 1]);
  p.margin_below_rpm = n[at] - n[lo];
  p.margin_above_rpm = n[hi] - n[at];
  return true;
}

// Usable first: a pocket the spindle can hold, at least kMinMargin of its speed from the
// nearest known lobe on each side (a cusp at a range end can leave no margin at all); then by
// removal rate, then by margin.
void rank(std::vector<Pocket>& out) {
  auto margin = [](const Pocket& q) {
    const double inf = std::numeric_limits<double>::infinity();
    return std::min(q.below_reaches_range_end ? inf : q.margin_below_rpm,
                    q.above_reaches_range_end ? inf : q.margin_above_rpm);
  };
  auto usable = [&](const Pocket& q) { return margin(q) >= kMinMargin * q.speed_rpm; };
  std::stable_sort(out.begin(), out.end(), [&](const Pocket& a, const Pocket& c) {
    if (usable(a) != usable(c)) return usable(a);
    if (a.mrr_m3_per_s != c.mrr_m3_per_s) return a.mrr_m3_per_s > c.mrr_m3_per_s;
    return margin(a) > margin(c);
  });
}

}  // namespace

std::vector<Pocket> recommend_pockets(const dynamics::FrequencyDomainResult& fd,
                                      const LobesInput& in) {
  const auto& r = in.recommend;
  const Spindle sp{r, r.kc_N_per_m2 > 0.0 ? r.kc_N_per_m2 : in.system.kf_N_per_m2, r.feed_m,
                   recommend_diameter_m(in)};
  const Envelope e = envelope_on_grid(fd, in);
  std::vector<Pocket> out;
  std::vector<std::pair<std::size_t, std::size_t>> spans;  // each pocket's stable interval
  for (const std::size_t top : pocket_tops(e)) {
    Pocket p;
    std::pair<std::size_t, std::size_t> span;
    if (!pocket_at(top, e, sp, p, span)) continue;  // neither chatter nor the machine bounds it
    // Limited by the spindle below several tops, one interval holds them all: one pocket.
    if (std::find(spans.begin(), spans.end(), span) != spans.end()) continue;
    spans.push_back(span);
    out.push_back(p);
  }
  rank(out);
  if (out.size() > static_cast<std::size_t>(r.pockets))
    out.resize(static_cast<std::size_t>(r.pockets));
  return out;
}

}  // namespace lathectl::systems::b_chatter
