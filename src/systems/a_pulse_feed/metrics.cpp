// System A's metrics (definitions in metrics.hpp).
#include "systems/a_pulse_feed/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lathectl::systems::a_pulse_feed {

MetricsAccumulator::MetricsAccumulator(const Rig& rig, double last_t)
    : rig_(&rig), onsets_(rig.config().faults) {
  const auto& rec = rig.recorder();
  const auto& cfg = rig.config();
  t_ = rec.index("time_s");
  feed_ = rec.index("feed_mm_per_min");
  force_ = rec.index("force_Py_N");
  flow_ = rec.index("flow_cm3_per_min");
  alarm_ = rec.index("alarm");
  reason_ = rec.index("reason_code");
  roughing_ = cfg.controller.mode == control::PulseFeedController::Mode::Roughing;
  set_ = cfg.controller.force_set_N;
  k_um_ = cfg.sensor.holder_stiffness_N_per_m * 1e-6;  // N per µm
  feed_window_s_ = cfg.feed_window_s;
  rpm_ = cfg.spindle_rpm;
  T_ = last_t;
  const double T = T_;
  t_settle_ = std::min(0.5, 0.1 * T);
  feed_all_ = {t_settle_, T + 1.0};
  feed_end90_ = {0.9 * T, T + 1.0};
  feed_end95_ = {0.95 * T, T + 1.0};
  feed_early_ = {0.05 * T, 0.10 * T};
  force_end90_ = {0.9 * T, T + 1.0};
  flow_all_ = {t_settle_, T + 1.0};
  f_rev_end90_ = {0.9 * T, T + 1.0};
  // The second before t_d, at the record interval (and a margin).
  const double ri = rig.record_interval();
  past_.resize(static_cast<std::size_t>(std::ceil(1.0 / (ri > 0.0 ? ri : 1.0))) + 4);
  // The moving averages at the record interval, so that row() allocates nothing when the rows
  // come at it (a plant stepped in a real-time thread).
  if (ri > 0.0) {
    windows(ri, w_, rev_, w_flow_);
    py_ = sim::MovingAverage(w_);
    f_rev_ = sim::MovingAverage(rev_);
    flow_avg_ = sim::MovingAverage(w_flow_);
  }
}

void MetricsAccumulator::windows(double dt_rec, std::size_t& w, std::size_t& rev,
                                 std::size_t& w_flow) const noexcept {
  w = static_cast<std::size_t>(std::max(1.0, std::round(feed_window_s_ / dt_rec)));
  rev = static_cast<std::size_t>(std::llround(60.0 / rpm_ / dt_rec));
  w_flow = static_cast<std::size_t>(std::max(1.0, feed_window_s_ / dt_rec));
}

void MetricsAccumulator::start_windows(double dt_rec) {
  // The constructor sized the averages for the rig's record interval; the rows' own spacing
  // decides, and only a window that came out different is allocated again here.
  const std::size_t w0 = w_, rev0 = rev_, w_flow0 = w_flow_;
  windows(dt_rec, w_, rev_, w_flow_);
  if (w_ != w0) py_ = sim::MovingAverage(w_);
  if (rev_ != rev0) f_rev_ = sim::MovingAverage(rev_);
  if (w_flow_ != w_flow0) flow_avg_ = sim::MovingAverage(w_flow_);
  // the first row again, now that the windows are known (its means are itself)
  (void)py_.push(row0_force_);
  (void)f_rev_.push(row0_force_);
  (void)flow_avg_.push(row0_flow_);
  if (plot_) flow_plot_.push(t_first_, 1 < w_flow_ ? std::nan("") : row0_flow_ / 1.0);
}

// The means over the second before t_d, from the rows kept (all earlier than t_d).
void MetricsAccumulator::on_disturbance(double t_settle) {
  td_seen_ = true;
  const double t0 = std::max(t_settle, td_ - 1.0);
  sim::MeanBetween feed{t0, td_}, force{t0, td_};
  const std::size_t cap = past_.size(), kept = std::min(past_n_, cap);
  for (std::size_t k = past_n_ - kept; k < past_n_; ++k) {
    const Past& p = past_[k % cap];
    feed.push(p.t, p.feed);
    force.push(p.t, p.force);
  }
  ref_ = feed.value();
  d_ref_ = force.value() / k_um_;
  last_out_ = td_;
}

void MetricsAccumulator::row(std::span<const double> v) noexcept {
  const std::size_t i = n_++;
  const double t = v[t_], feed = v[feed_], force = v[force_], flow = v[flow_];
  const double t_prev = t_last_;
  t_last_ = t;
  double py = force, f_rev = force;  // row 0: a window of one
  if (i == 0) {
    t_first_ = t;
    row0_force_ = force;
    row0_flow_ = flow;
    force_peak_ = force;
  } else {
    if (i == 1) start_windows(t - t_first_);
    py = py_.push(force);
    f_rev = f_rev_.push(force);
    const double fa = flow_avg_.push(flow);
    if (plot_) flow_plot_.push(t, i + 1 < w_flow_ ? std::nan("") : fa);
    if (force_peak_ < force) force_peak_ = force;  // std::max_element's first largest
    if (roughing_ && f_rev > 1.05 * set_) over_band_s_ += t - t_prev;
  }
  feed_all_.push(t, feed);
  feed_end90_.push(t, feed);
  feed_end95_.push(t, feed);
  feed_early_.push(t, feed);
  force_end90_.push(t, force);
  flow_all_.push(t, flow);
  if (roughing_) f_rev_end90_.push(t, f_rev);
  onsets_.push(t, v[alarm_], v[reason_]);
  if (t >= t_settle_) {
    any_late_ = true;
    if (feed > feed_max_) feed_max_ = feed;
    if (feed < feed_min_) feed_min_ = feed;
  }
  if (!td_seen_) {
    td_ = rig_->first_disturbance_time();
    if (td_ > 0.0 && t >= td_) {
      on_disturbance(t_settle_);
    } else {
      past_[past_n_++ % past_.size()] = {t, feed, force};
      return;
    }
  }
  late_row(t, feed, force, f_rev, py, i);
}

// A row at t ≥ t_d.
void MetricsAccumulator::late_row(double t, double feed, double, double f_rev, double py,
                                  std::size_t i) {
  dev_ = std::max(dev_, std::abs(feed - ref_));
  if (i >= w_) peak_ = std::max(peak_, std::abs(py / k_um_ - d_ref_));
  if (roughing_ && std::abs(f_rev - set_) > 0.05 * set_) last_out_ = t;
}

Metrics MetricsAccumulator::result(const Rig& rig) const {
  const auto& cfg = rig.config();
  Metrics m;
  {
    const auto vb = rig.volume_balance();
    m.volume_balance_pct = vb.travel_unexplained_pct;
    m.volume_conservation_error_pct = vb.conservation_error_pct;
  }
  if (n_ == 0) return m;
  MetricsAccumulator last = *this;  // (t_d may still have to be closed below)
  const double T = T_;
  const double td = rig.first_disturbance_time();
  // t_d after the last row: the second before it is all in the ring.
  if (td > 0.0 && !last.td_seen_) {
    last.td_ = td;
    last.on_disturbance(t_settle_);
  }

  m.feed_rate_programmed_mm_per_min = cfg.controller.feed_m_per_s * 60000.0;
  m.feed_rate_mean_mm_per_min = feed_all_.value();
  m.force_nominal_N = rig.nominal_force_N();
  m.force_peak_N = force_peak_;
  double dev = 0.0;
  if (td > 0.0) {
    m.first_disturbance_s = td;
    m.feed_rate_reference_mm_per_min = last.ref_;
    dev = last.dev_;
  } else {
    m.feed_rate_reference_mm_per_min = m.feed_rate_mean_mm_per_min;
    // max |S − ref| over t ≥ t_settle: at the largest or the smallest S (x − ref rounds
    // monotonically in x), so the same number as over every row.
    const double ref = m.feed_rate_reference_mm_per_min;
    if (any_late_) {
      dev = std::max(dev, std::abs(feed_max_ - ref));
      dev = std::max(dev, std::abs(feed_min_ - ref));
    }
  }
  const double ref = m.feed_rate_reference_mm_per_min;
  m.feed_rate_deviation_pct = 100.0 * dev / ref;
  m.feed_rate_steady_deviation_pct = 100.0 * std::abs(feed_end90_.value() - ref) / ref;
  const double early = feed_early_.value();
  m.feed_drift_pct = 100.0 * (feed_end95_.value() - early) / early;

  if (td > 0.0) {
    const double d_ref = last.d_ref_;
    m.deflection_reference_um = d_ref;
    m.deflection_end_um = force_end90_.value() / k_um_;
    m.size_error_diameter_um = 2.0 * (m.deflection_end_um - d_ref);
    m.size_error_peak_diameter_um = 2.0 * last.peak_;
  }
  m.flow_mean_cm3_per_min = flow_all_.value();
  if (cfg.controller_kind == ControllerKind::None && cfg.regulator_kind == RegulatorKind::Pulsed) {
    m.flow_formula_cm3_per_min = cfg.regulator.orifice.gain_per_m() * rig.fixed_actuator() *
                                 cfg.pulse_width_s * cfg.frequency_Hz * 6e7;
    m.flow_formula_error_pct =
        100.0 * (m.flow_mean_cm3_per_min - m.flow_formula_cm3_per_min) / m.flow_formula_cm3_per_min;
  }
  if (roughing_) {
    m.force_setpoint_N = set_;
    m.force_final_error_pct = 100.0 * (f_rev_end90_.value() - set_) / set_;
    if (td > 0.0 && last.last_out_ < T - 1e-9) m.force_settling_time_s = last.last_out_ - td;
    m.force_over_band_s = over_band_s_;
  }
  if (cfg.cutting.material.tool_life_ranges > 0) {
    m.tool_life_used_pct = 100.0 * rig.tool_life_used();
    const double travel_m = rig.travel_after_disturbance_mm() * 1e-3;
    if (travel_m > 0.0)
      m.tool_life_per_m_after_disturbance_pct =
          100.0 * rig.tool_life_used_after_disturbance() / travel_m;
  }
  m.alarms = onsets_.events();
  m.first_alarm_delay_s = onsets_.first_delay_s();
  return m;
}

Metrics compute_metrics(const Rig& rig) {
  const auto t = rig.recorder().column("time_s");
  MetricsAccumulator acc(rig, t.empty() ? -1.0 : t.back());
  rig.recorder().replay(acc);
  return acc.result(rig);
}

std::vector<double> regulator_characteristic(const hydraulics::PulseRegulator::Params& p,
                                             double slot_m, double f,
                                             const std::vector<double>& widths, int periods) {
  std::vector<double> out;
  out.reserve(widths.size());
  hydraulics::PulseRegulator reg;
  for (const double w : widths) {
    reg.configure(p);
    const double T = 1.0 / f;
    const int per_period = 100;
    const double dt = T / per_period;
    double volume = 0.0;
    for (int k = 0; k < periods * per_period; ++k) {
      const double q = reg.step(dt, slot_m, f, w);
      if (k >= per_period) volume += q * dt;
    }
    out.push_back(volume / (T * (periods - 1)));
  }
  return out;
}

SwitchingLimits regulator_switching_limits(const hydraulics::PulseRegulator::Params& p,
                                           double slot_m, double f) {
  auto flow_at = [&](double duty) {
    return regulator_characteristic(p, slot_m, f, {duty / f}, 6).front();
  };
  SwitchingLimits lim;
  double lo = 0.0, hi = 1.0;  // flow(lo) == 0, flow(hi) > 0
  if (flow_at(1e-9) > 0.0) {
    lo = 0.0;
  } else {
    for (int k = 0; k < 40; ++k) {
      const double mid = 0.5 * (lo + hi);
      (flow_at(mid) > 1e-18 ? hi : lo) = mid;
    }
  }
  lim.dead_zone_duty = lo;
  auto closes = [&](double duty) {
    hydraulics::PulseRegulator reg;
    reg.configure(p);
    const double T = 1.0 / f;
    const int n = 2000;
    double y_min = 1e300;
    for (int k = 0; k < 6 * n; ++k) {
      (void)reg.step(T / n, slot_m, f, duty / f);
      if (k >= 5 * n) y_min = std::min(y_min, reg.spool_position_m());
    }
    return y_min <= -p.lap_m + 1e-12;
  };
  lo = 0.0;
  hi = 1.0;  // closes(lo), !closes(hi)
  for (int k = 0; k < 30; ++k) {
    const double mid = 0.5 * (lo + hi);
    (closes(mid) ? lo : hi) = mid;
  }
  lim.saturation_duty = hi;
  return lim;
}

PulseMeanFlowPlot::PulseMeanFlowPlot(const sim::Recorder& rec, double window_s)
    : t_(rec.index("time_s")),
      flow_(rec.index("flow_cm3_per_min")),
      freq_(rec.index("frequency_Hz")),
      window_s_(window_s),
      value_(std::nan("")) {
  opens_.reserve(kMaxPeriods + 1);
}

void PulseMeanFlowPlot::row(std::span<const double> v) noexcept {
  const double x = v[flow_];
  if (n_ > 0 && prev_flow_ <= 0.0 && x > 0.0) {  // a pulse opens at sample n_
    if (opens_.size() == kMaxPeriods + 1) opens_.erase(opens_.begin());
    opens_.emplace_back(n_, sum_);
    ++opens_seen_;
    const auto periods =
        static_cast<std::size_t>(std::max(1.0, std::round(window_s_ * v[freq_])));
    if (periods < opens_.size()) {
      const auto& a = opens_[opens_.size() - 1 - periods];
      value_ = (sum_ - a.second) / static_cast<double>(n_ - a.first);
    } else {
      value_ = std::nan("");
    }
  }
  plot_.push(v[t_], value_);
  sum_ += x;
  prev_flow_ = x;
  ++n_;
}

std::shared_ptr<const sim::PlotPyramid> PulseMeanFlowPlot::plot() const {
  if (opens_seen_ < 2) return nullptr;
  return plot_.finished();
}

}  // namespace lathectl::systems::a_pulse_feed
