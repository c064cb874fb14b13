#pragma once
// Metrics that answer system E's claims, from a Rig run (row by row as it records). Definitions:
//   force (per revolution): the true force parameter averaged over one spindle revolution — a
//     feed drive cannot act within a revolution (the chip is the travel over the last one), so
//     runout of an eccentric blank swings the instantaneous force around this mean; the raw
//     peak is reported too. The mean is the rig's, of every simulation step (Rig::load_rev),
//     read at each recorded row
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
#include "lathectl/control/per_revolution.hpp"
#include "lathectl/sim/recorder.hpp"
#include "systems/e_adaptive/rig.hpp"

namespace lathectl::systems::e_adaptive {

struct Metrics {
  bool finished = false;
  double cycle_time_s = 0.0;
  double time_in_cut_s = 0.0;
  double load_limit = 0.0;
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
  std::vector<sim::AlarmEvent> alarms;
  double first_alarm_delay_s = std::numeric_limits<double>::quiet_NaN();
  double feed_hold_delay_s = std::numeric_limits<double>::quiet_NaN();  // fault → feed command 0
};

// The metrics computed row by row as the rig records (a RowSink attached to its streamed
// recorder between configure and run): nothing of the record is kept but a few sums, the
// per-revolution window and a bounded plot of the per-revolution mean, so a run of any length
// takes the same memory.
class MetricsAccumulator final : public sim::RowSink {
 public:
  // rig: configured (its configuration and controller limits are read here).
  explicit MetricsAccumulator(const Rig& rig, double settle_s = 0.5);
  void row(std::span<const double> v) noexcept override;
  // After the run.
  [[nodiscard]] Metrics result(const Rig& rig) const;
  // How long each non-zero reason code held in the record (rows × record interval), in how many
  // episodes, first and last time; sorted by code.
  struct ReasonSpan {
    int code = 0;
    double total_s = 0.0, first_s = -1.0, last_s = -1.0;
    int episodes = 0;
  };
  [[nodiscard]] std::vector<ReasonSpan> reasons() const;

 private:
  ReasonSpan& reason_entry(int code);
  std::size_t t_, f_, pz_, rpm_, in_cut_, depth_, s_, s_cmd_, v_, power_, alarm_, hold_, reason_;
  double settle_s_, limit_, ceiling_, feed_min_;
  Metrics m_;
  const Rig& rig_;  // its per-revolution mean and peak over the cuts (Rig::load_rev)
  sim::AlarmOnsets onsets_;
  std::size_t n_ = 0;
  double t0_ = 0.0, dt_rec_ = 0.0;
  double steady_n_ = 0, within_n_ = 0, steady_sum_ = 0, cut_n_ = 0, s_sum_ = 0,
         v_sum_ = 0;
  int prev_code_ = 0;
  bool first_row_code_pending_ = false;
  std::vector<ReasonSpan> reasons_;
};

}  // namespace lathectl::systems::e_adaptive
