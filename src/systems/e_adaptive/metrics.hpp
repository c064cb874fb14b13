#pragma once
// Metrics that answer system E's claims, from a finished RigE run. Definitions:
//   force (per revolution): the true force parameter averaged over one spindle revolution — a
//     feed drive cannot act within a revolution (the chip is the travel over the last one), so
//     runout of an eccentric blank swings the instantaneous force around this mean; the raw
//     peak is reported too
//   steady cutting: in cut, the feed regulating between its limits, ≥ settle_s after contact
//   force_within_5pct_fraction: share of steady-cutting time with |F_rev − limit| ≤ 5 %
//   force_overshoot_pct: largest (F_rev − limit)/limit anywhere in cut
//   tool_life_used_fraction: ∫ dt / T(V, s, t, h) (Palmgren–Miner, with the local hardness);
//   tool_life_used_nominal_hardness_fraction: the same at h = 1; tool_life_plan_fraction:
//     time in cut / T(V_p, S_p, t_p) — what the planned tool life would have allowed in that time

#include <cmath>
#include <limits>
#include <vector>

#include "lathectl/sim/metrics.hpp"
#include "systems/e_adaptive/rig.hpp"

namespace lathectl::sim {

struct MetricsE {
  bool finished = false;
  double cycle_time_s = 0.0;
  double time_in_cut_s = 0.0;
  double force_limit = 0.0;
  double force_peak = 0.0;           // raw (record-interval mean) peak of the true parameter
  double force_peak_rev_mean = 0.0;  // peak of the per-revolution mean
  double force_overshoot_pct = 0.0;  // of the per-revolution mean
  double force_within_5pct_fraction = std::numeric_limits<double>::quiet_NaN();
  double force_mean_steady = std::numeric_limits<double>::quiet_NaN();
  double force_Pz_peak_N = 0.0;
  double tool_life_used_fraction = 0.0;
  double tool_life_used_nominal_hardness_fraction = 0.0;  // ∫ dt / T(V, s, t, h = 1)
  double tool_life_plan_fraction = 0.0;
  double tool_life_planned_min = 0.0;
  double material_removed_cm3 = 0.0;
  double mrr_cm3_per_min = 0.0;
  double feed_mean_mm_per_rev = 0.0;  // in cut
  double speed_mean_m_per_min = 0.0;  // in cut
  double feed_programmed_mm_per_rev = 0.0;
  double spindle_power_peak_kW = 0.0;
  std::vector<AlarmEvent> alarms;
  double first_alarm_delay_s = std::numeric_limits<double>::quiet_NaN();
  double feed_hold_delay_s = std::numeric_limits<double>::quiet_NaN();  // fault → feed command 0
};

MetricsE compute_metrics_e(const RigE& rig, double settle_s = 0.5);

}  // namespace lathectl::sim
