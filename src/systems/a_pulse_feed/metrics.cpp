// System A's metrics (definitions in metrics.hpp).
#include "systems/a_pulse_feed/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lathectl::sim {

MetricsA compute_metrics_a(const RigA& rig) {
  const auto& rec = rig.recorder();
  const auto& cfg = rig.config();
  MetricsA m;
  {
    const auto vb = rig.volume_balance();
    m.volume_balance_pct = vb.travel_unexplained_pct;
    m.volume_conservation_error_pct = vb.conservation_error_pct;
  }
  const auto t = rec.column("time_s");
  const auto feed = rec.column("feed_mm_per_min");
  const auto force = rec.column("force_Py_N");
  const auto flow = rec.column("flow_cm3_per_min");
  const auto alarm = rec.column("alarm");
  const auto reason = rec.column("reason_code");
  if (t.empty()) return m;
  const double T = t.back();
  const double t_settle = std::min(0.5, 0.1 * T);

  m.feed_rate_programmed_mm_per_min = cfg.controller.feed_m_per_s * 60000.0;
  m.feed_rate_mean_mm_per_min = mean_between(t, feed, t_settle, T + 1.0);
  m.force_nominal_N = rig.nominal_force_N();
  m.force_peak_N = *std::max_element(force.begin(), force.end());

  const double td = rig.first_disturbance_time();
  if (td > 0.0) {
    m.first_disturbance_s = td;
    m.feed_rate_reference_mm_per_min = mean_between(t, feed, std::max(t_settle, td - 1.0), td);
  } else {
    m.feed_rate_reference_mm_per_min = m.feed_rate_mean_mm_per_min;
  }
  const double ref = m.feed_rate_reference_mm_per_min;
  const double from = td > 0.0 ? td : t_settle;
  double dev = 0.0;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t[i] >= from) dev = std::max(dev, std::abs(feed[i] - ref));
  m.feed_rate_deviation_pct = 100.0 * dev / ref;
  m.feed_rate_steady_deviation_pct =
      100.0 * std::abs(mean_between(t, feed, 0.9 * T, T + 1.0) - ref) / ref;
  const double early = mean_between(t, feed, 0.05 * T, 0.10 * T);
  m.feed_drift_pct = 100.0 * (mean_between(t, feed, 0.95 * T, T + 1.0) - early) / early;

  if (td > 0.0) {
    const double k_um = cfg.sensor.holder_stiffness_N_per_m * 1e-6;  // N per µm
    const double dt_rec = t.size() > 1 ? t[1] - t[0] : 1.0;
    const auto w = static_cast<std::size_t>(std::max(1.0, std::round(cfg.feed_window_s / dt_rec)));
    const auto py = moving_average(force, w);
    const double d_ref = mean_between(t, force, std::max(t_settle, td - 1.0), td) / k_um;
    m.deflection_reference_um = d_ref;
    m.deflection_end_um = mean_between(t, force, 0.9 * T, T + 1.0) / k_um;
    m.size_error_diameter_um = 2.0 * (m.deflection_end_um - d_ref);
    double peak = 0.0;
    for (std::size_t i = w; i < t.size(); ++i)
      if (t[i] >= td) peak = std::max(peak, std::abs(py[i] / k_um - d_ref));
    m.size_error_peak_diameter_um = 2.0 * peak;
  }
  m.flow_mean_cm3_per_min = mean_between(t, flow, t_settle, T + 1.0);
  if (cfg.controller_kind == ControllerKind::None && cfg.regulator_kind == RegulatorKind::Pulsed) {
    m.flow_formula_cm3_per_min = cfg.regulator.orifice.gain_per_m() * rig.fixed_actuator() *
                                 cfg.pulse_width_s * cfg.frequency_Hz * 6e7;
    m.flow_formula_error_pct =
        100.0 * (m.flow_mean_cm3_per_min - m.flow_formula_cm3_per_min) / m.flow_formula_cm3_per_min;
  }

  if (cfg.controller.mode == control::PulseFeedController::Mode::Roughing) {
    const double set = cfg.controller.force_set_N;
    m.force_setpoint_N = set;
    const double dt_rec = t.size() > 1 ? t[1] - t[0] : 1.0;
    const auto rev = static_cast<std::size_t>(std::llround(60.0 / cfg.spindle_rpm / dt_rec));
    const auto f_rev = moving_average(force, rev);
    m.force_final_error_pct = 100.0 * (mean_between(t, f_rev, 0.9 * T, T + 1.0) - set) / set;
    if (td > 0.0) {
      double last_out = td;
      for (std::size_t i = 0; i < t.size(); ++i)
        if (t[i] >= td && std::abs(f_rev[i] - set) > 0.05 * set) last_out = t[i];
      if (last_out < T - 1e-9) m.force_settling_time_s = last_out - td;
    }
  }

  m.alarms = alarm_onsets(t, alarm, reason, cfg.faults, m.first_alarm_delay_s);
  return m;
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

}  // namespace lathectl::sim
