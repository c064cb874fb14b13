#include "systems/e_adaptive/metrics.hpp"

#include "lathectl/sim/per_revolution.hpp"

#include <algorithm>
#include <cmath>

namespace lathectl::sim {

MetricsE compute_metrics_e(const RigE& rig, double settle_s) {
  MetricsE m;
  const auto& rec = rig.recorder();
  const auto& cfg = rig.config();
  m.finished = rig.finished();
  m.cycle_time_s = rig.cycle_time_s();
  m.time_in_cut_s = rig.time_in_cut_s();
  m.force_limit = rig.force_limit();
  m.tool_life_used_fraction = rig.tool_life_used();
  m.tool_life_used_nominal_hardness_fraction = rig.tool_life_used_nominal_hardness();
  m.tool_life_planned_min = rig.tool_life_planned_min();
  m.tool_life_plan_fraction = rig.time_in_cut_s() / 60.0 / rig.tool_life_planned_min();
  m.material_removed_cm3 = rig.material_removed_cm3();
  m.mrr_cm3_per_min = m.material_removed_cm3 / (m.cycle_time_s / 60.0);
  m.feed_programmed_mm_per_rev = rig.programmed_feed();
  const auto t = rec.column("time_s");
  if (t.empty()) return m;
  const auto f = rec.column("force_parameter_true");
  const auto pz = rec.column("force_Pz_N");
  const auto rpm = rec.column("spindle_rpm");
  const auto in_cut = rec.column("in_cut");
  const auto depth = rec.column("depth_mm");
  const auto s = rec.column("feed_per_rev_mm");
  const auto s_cmd = rec.column("feed_cmd_mm_per_rev");
  const auto v = rec.column("speed_m_per_min");
  const auto power = rec.column("spindle_power_kW");
  const auto alarm = rec.column("alarm");
  const auto hold = rec.column("feed_hold");
  const auto reason = rec.column("reason_code");
  const double dt_rec = t.size() > 1 ? t[1] - t[0] : 1.0;

  // Per-revolution mean of the force (the same curve the report plots).
  const std::vector<double> f_rev = per_revolution_mean(f, rpm, dt_rec);
  const double limit = m.force_limit;
  const double ceiling = cfg.controller.allow_above_programmed ? cfg.controller.feed_max_mm_per_rev
                                                               : m.feed_programmed_mm_per_rev;
  double contact_t = -1e9, steady_n = 0, within_n = 0, steady_sum = 0, cut_n = 0, s_sum = 0,
         v_sum = 0;
  bool was_cutting = false;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const bool cutting = depth[i] > 0.0 && s[i] > 0.0;
    if (cutting && !was_cutting) contact_t = t[i];
    was_cutting = cutting;
    m.force_peak = std::max(m.force_peak, f[i]);
    m.force_Pz_peak_N = std::max(m.force_Pz_peak_N, pz[i]);
    m.spindle_power_peak_kW = std::max(m.spindle_power_peak_kW, power[i]);
    if (!cutting) continue;
    ++cut_n;
    s_sum += s[i];
    v_sum += v[i];
    // the first revolution after contact builds the chip: its mean is not a cut's mean yet
    if (t[i] - contact_t > 60.0 / std::max(rpm[i], 1.0))
      m.force_peak_rev_mean = std::max(m.force_peak_rev_mean, f_rev[i]);
    const bool regulating =
        s_cmd[i] < ceiling * 0.995 && s_cmd[i] > cfg.controller.feed_min_mm_per_rev * 1.005;
    if (in_cut[i] > 0.5 && regulating && t[i] - contact_t >= settle_s && hold[i] < 0.5) {
      ++steady_n;
      steady_sum += f_rev[i];
      if (std::abs(f_rev[i] - limit) <= 0.05 * limit) ++within_n;
    }
  }
  m.force_overshoot_pct = 100.0 * (m.force_peak_rev_mean - limit) / limit;
  if (steady_n > 0) {
    m.force_within_5pct_fraction = within_n / steady_n;
    m.force_mean_steady = steady_sum / steady_n;
  }
  if (cut_n > 0) {
    m.feed_mean_mm_per_rev = s_sum / cut_n;
    m.speed_mean_m_per_min = v_sum / cut_n;
  }

  m.alarms = alarm_onsets(t, alarm, reason, cfg.faults, m.first_alarm_delay_s);
  double first_fault = std::numeric_limits<double>::infinity();
  for (const auto& fl : cfg.faults) first_fault = std::min(first_fault, fl.at_s);
  if (std::isfinite(first_fault) && rig.first_feed_hold_s() >= first_fault)
    m.feed_hold_delay_s = rig.first_feed_hold_s() - first_fault;
  return m;
}

}  // namespace lathectl::sim
