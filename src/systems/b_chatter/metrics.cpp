#include "systems/b_chatter/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "lathectl/dynamics/beam.hpp"
#include "lathectl/dynamics/delayed_coupling.hpp"

namespace lathectl::b_chatter {

void measure(Run& r, bool twin, double dead_zone_um) {
  const auto& rec = r.rig.recorder();
  const auto t = rec.column("time_s");
  const auto y = rec.column("y_um");
  const auto yh = rec.column("y_highpass_um");
  const double start = r.rig.cut_start_s(), end = t.empty() ? 0.0 : t[t.size() - 1];
  r.t0 = start + 0.7 * (end - start);
  r.t1 = end - 0.05;
  double lo = 1e300, hi = -1e300, p = 0.0, pm = 0.0, n = 0.0, out = 0.0, ys = 0.0;
  const auto c1 = rec.column("chip1_mm"), c2 = rec.column("chip2_mm");
  const auto pw = rec.column("cut_power_W"), pwm = rec.column("cut_power_measured_W");
  const auto dl = rec.column("inter_tool_delay_rev");
  std::size_t first = t.size(), last = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t[i] < r.t0 || t[i] > r.t1) continue;
    first = std::min(first, i);
    last = i;
    r.vibration_um = std::max(r.vibration_um, std::abs(yh[i]));
    lo = std::min(lo, y[i] - yh[i]);
    hi = std::max(hi, y[i] - yh[i]);
    p += pw[i];
    pm += pwm[i];
    ys += y[i];
    n += 1.0;
    if (twin && ((c1[i] == 0.0) != (c2[i] == 0.0))) out += 1.0;
    if (dl[i] > 0.0) {
      r.delay_min_rev = std::isnan(r.delay_min_rev) ? dl[i] : std::min(r.delay_min_rev, dl[i]);
      r.delay_max_rev = std::isnan(r.delay_max_rev) ? dl[i] : std::max(r.delay_max_rev, dl[i]);
    }
  }
  if (n > 0.0) {
    r.forced_um = 0.5 * (hi - lo);
    r.static_um = ys / n;
    r.cut_power_W = p / n;
    r.cut_power_measured_W = pm / n;
    r.one_out_share = out / n;
    // Chatter frequency: crossings of ±20 % of the amplitude (hysteresis), over the window.
    int sign = 0, crossings = 0;
    double tc0 = kNaN, tc1 = kNaN;
    for (std::size_t i = first; i <= last; ++i) {
      const double h = 0.2 * r.vibration_um;
      const int s = yh[i] > h ? 1 : (yh[i] < -h ? -1 : 0);
      if (s != 0 && s != sign) {
        if (sign != 0) {
          ++crossings;
          if (std::isnan(tc0)) tc0 = t[i];
          tc1 = t[i];
        }
        sign = s;
      }
    }
    if (crossings > 4 && r.vibration_um > dead_zone_um)
      r.chatter_Hz = (crossings - 1) / (2.0 * (tc1 - tc0));
  }
  const auto z1 = rec.column("z1_mm"), z2 = rec.column("z2_mm");
  std::size_t k0 = 0;
  while (k0 < t.size() && t[k0] < start) ++k0;
  if (k0 + 1 < t.size()) {
    const double dt = t[t.size() - 1] - t[k0];
    r.feed_mean[0] = (z1[z1.size() - 1] - z1[k0]) / dt * 60.0;
    r.feed_mean[1] = (z2[z2.size() - 1] - z2[k0]) / dt * 60.0;
  }
}

Limits linear_limits(const sim::RigBConfig& b, double x_mm, double rpm, int points) {
  const auto modes = dynamics::beam_modes_at(b.part, x_mm * 1e-3, b.modes);
  double f_max = 0.0;
  for (const auto& m : modes) f_max = std::max(f_max, m.natural_frequency_Hz);
  const double tau = 60.0 / rpm;
  const auto& fp = b.cutting.material.Fp;
  const double sk = std::sin(b.cutting.approach_angle_deg * std::numbers::pi / 180.0);
  // dF_p/dt per tool at chip s: k_p/sin κ·(s·sin κ)^(1−m) [N/mm] → per metre.
  auto chip_for_gain = [&](double g) {
    return std::pow(g / (fp.k11_N_per_mm2 * 1e3 / sk), 1.0 / (1.0 - fp.m)) / sk;
  };
  Limits l;
  // The overlap μ is the coupling c of the delayed term; the gain is each tool's dF_p/db.
  const auto one = dynamics::critical_gain(modes, tau, b.overlap, 5.0, 2.5 * f_max, points);
  l.single_feed = chip_for_gain(one.gain_N_per_m);
  l.chatter_Hz = one.chatter_Hz;
  if (b.setup == sim::TwinSetup::FeedDivision) {
    const auto two =
        dynamics::critical_gain(modes, 0.5 * tau, -b.overlap, 5.0, 2.5 * f_max, points);
    l.twin_feed = 2.0 * chip_for_gain(0.5 * two.gain_N_per_m);
    l.chatter_Hz = two.chatter_Hz;
  }
  return l;
}

}  // namespace lathectl::b_chatter
