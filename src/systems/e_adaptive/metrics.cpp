#include "systems/e_adaptive/metrics.hpp"

#include <algorithm>
#include <cmath>

namespace lathectl::systems::e_adaptive {

MetricsAccumulator::MetricsAccumulator(const Rig& rig, double settle_s)
    : settle_s_(settle_s), rig_(rig), onsets_(rig.config().faults) {
  const auto& rec = rig.recorder();
  const auto& cfg = rig.config();
  t_ = rec.index("time_s");
  f_ = rec.index("force_parameter_true");
  pz_ = rec.index("force_Pz_N");
  rpm_ = rec.index("spindle_rpm");
  in_cut_ = rec.index("in_cut");
  depth_ = rec.index("depth_mm");
  s_ = rec.index("feed_per_rev_mm");
  s_cmd_ = rec.index("feed_cmd_mm_per_rev");
  v_ = rec.index("speed_m_per_min");
  power_ = rec.index("spindle_power_kW");
  alarm_ = rec.index("alarm");
  hold_ = rec.index("feed_hold");
  reason_ = rec.index("reason_code");
  limit_ = rig.load_limit();
  ceiling_ = cfg.controller.allow_above_programmed ? cfg.controller.feed_max_mm_per_rev
                                                   : rig.programmed_feed();
  feed_min_ = cfg.controller.feed_min_mm_per_rev;
}

MetricsAccumulator::ReasonSpan& MetricsAccumulator::reason_entry(int code) {
  auto it = std::find_if(reasons_.begin(), reasons_.end(),
                         [&](const ReasonSpan& a) { return a.code == code; });
  if (it != reasons_.end()) return *it;
  reasons_.push_back({code});
  return reasons_.back();
}

void MetricsAccumulator::row(std::span<const double> v) noexcept {
  const std::size_t i = n_++;
  const double t = v[t_];
  // The record interval, as the whole-record forms took it: t[1] − t[0].
  if (i == 0) t0_ = t;
  if (i == 1) {
    dt_rec_ = t - t0_;
    if (first_row_code_pending_) reason_entry(prev_code_).total_s += dt_rec_;
  }
  const bool cutting = v[depth_] > 0.0 && v[s_] > 0.0;
  const control::PerRevolutionPeak& rev = rig_.load_rev();  // up to this row's step
  const double f_rev = rev.value();
  onsets_.push(t, v[alarm_], v[reason_]);

  // Decisions by reason code.
  const int code = static_cast<int>(v[reason_]);
  if (code != 0) {
    ReasonSpan& a = reason_entry(code);
    if (i == 0)
      first_row_code_pending_ = true;  // its interval is known at the second row
    else
      a.total_s += dt_rec_;
    if (a.first_s < 0) a.first_s = t;
    a.last_s = t;
    if (i == 0 || prev_code_ != code) ++a.episodes;
  }
  prev_code_ = code;

  m_.force_peak = std::max(m_.force_peak, v[f_]);
  m_.force_Pz_peak_N = std::max(m_.force_Pz_peak_N, v[pz_]);
  m_.spindle_power_peak_kW = std::max(m_.spindle_power_peak_kW, v[power_]);
  if (!cutting) return;
  ++cut_n_;
  s_sum_ += v[s_];
  v_sum_ += v[v_];
  const bool regulating = v[s_cmd_] < ceiling_ * 0.995 && v[s_cmd_] > feed_min_ * 1.005;
  if (v[in_cut_] > 0.5 && regulating && rev.since_contact_s(t) >= settle_s_ && v[hold_] < 0.5) {
    ++steady_n_;
    steady_sum_ += f_rev;
    if (std::abs(f_rev - limit_) <= 0.05 * limit_) ++within_n_;
  }
}

std::vector<MetricsAccumulator::ReasonSpan> MetricsAccumulator::reasons() const {
  auto out = reasons_;
  std::sort(out.begin(), out.end(),
            [](const ReasonSpan& a, const ReasonSpan& b) { return a.code < b.code; });
  return out;
}

Metrics MetricsAccumulator::result(const Rig& rig) const {
  Metrics m;
  const auto& cfg = rig.config();
  m.finished = rig.finished();
  m.cycle_time_s = rig.cycle_time_s();
  m.time_in_cut_s = rig.time_in_cut_s();
  m.load_limit = rig.load_limit();
  m.tool_life_used_fraction = rig.tool_life_used();
  m.tool_life_used_nominal_hardness_fraction = rig.tool_life_used_nominal_hardness();
  m.tool_life_planned_min = rig.tool_life_planned_min();
  m.tool_life_plan_fraction = rig.time_in_cut_s() / 60.0 / rig.tool_life_planned_min();
  m.material_removed_cm3 = rig.material_removed_cm3();
  m.mrr_cm3_per_min = m.material_removed_cm3 / (m.cycle_time_s / 60.0);
  m.feed_programmed_mm_per_rev = rig.programmed_feed();
  if (n_ == 0) return m;
  m.force_peak = m_.force_peak;
  m.force_Pz_peak_N = m_.force_Pz_peak_N;
  m.spindle_power_peak_kW = m_.spindle_power_peak_kW;
  m.force_peak_rev_mean = rig.load_rev().peak();
  const double limit = m.load_limit;
  m.force_overshoot_pct = 100.0 * (m.force_peak_rev_mean - limit) / limit;
  if (steady_n_ > 0) {
    m.force_within_5pct_fraction = within_n_ / steady_n_;
    m.force_mean_steady = steady_sum_ / steady_n_;
  }
  if (cut_n_ > 0) {
    m.feed_mean_mm_per_rev = s_sum_ / cut_n_;
    m.speed_mean_m_per_min = v_sum_ / cut_n_;
  }
  m.alarms = onsets_.events();
  m.first_alarm_delay_s = onsets_.first_delay_s();
  double first_fault = std::numeric_limits<double>::infinity();
  for (const auto& fl : cfg.faults) first_fault = std::min(first_fault, fl.at_s);
  if (std::isfinite(first_fault) && rig.first_feed_hold_s() >= first_fault)
    m.feed_hold_delay_s = rig.first_feed_hold_s() - first_fault;
  return m;
}

}  // namespace lathectl::systems::e_adaptive
