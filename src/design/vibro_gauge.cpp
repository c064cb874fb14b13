#include "lathectl/design/vibro_gauge.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "lathectl/sensors/vibro_contact_gauge.hpp"

namespace lathectl::design {

GaugeResult gauge(const GaugeInput& in) {
  auto nonneg = [](double v, const char* what) {
    if (!(v >= 0.0) || !std::isfinite(v))
      throw std::invalid_argument(std::string(what) + " must be ≥ 0");
  };
  nonneg(in.relay_response_s, "relay response time");
  nonneg(in.removal_m_per_s, "removal rate a");
  nonneg(in.noise_variance_m2, "noise variance D");
  nonneg(in.noise_beta_per_s, "noise β");
  if (!std::isfinite(in.allowance_m) || !std::isfinite(in.target_m))
    throw std::invalid_argument("allowance and target must be finite");
  auto positive = [](double v, const char* what) {
    if (!(v > 0.0) || !std::isfinite(v))
      throw std::invalid_argument(std::string(what) + " must be > 0");
  };
  positive(in.supply_V, "supply voltage");
  positive(in.supply_Hz, "supply frequency");
  positive(in.coil_turns, "coil turns");
  positive(in.coil_resistance_ohm, "coil resistance");
  positive(in.coil_inductance_H, "coil inductance");
  positive(in.force_coefficient_N_per_Wb2, "force coefficient");
  positive(in.probe_mass_kg, "probe mass");
  positive(in.probe_stiffness_N_per_m, "probe stiffness");
  positive(in.generator_V_per_m_per_s, "generator constant");
  positive(in.contact_stiffness_N_per_m, "contact stiffness");
  nonneg(in.contact_damping_N_s_per_m, "contact damping");
  positive(in.filter_time_constant_s, "filter time constant");
  nonneg(in.probe_damping_N_s_per_m, "probe damping");
  nonneg(in.generator_time_constant_s, "generator time constant");
  sensors::VibroContactGauge::Params p;
  p.supply_V = in.supply_V;
  p.supply_Hz = in.supply_Hz;
  p.coil_turns = in.coil_turns;
  p.coil_resistance_ohm = in.coil_resistance_ohm;
  p.coil_inductance_H = in.coil_inductance_H;
  p.force_coefficient_N_per_Wb2 = in.force_coefficient_N_per_Wb2;
  p.probe_mass_kg = in.probe_mass_kg;
  p.probe_damping_N_s_per_m = in.probe_damping_N_s_per_m;
  p.probe_stiffness_N_per_m = in.probe_stiffness_N_per_m;
  p.contact_stiffness_N_per_m = in.contact_stiffness_N_per_m;
  p.contact_damping_N_s_per_m = in.contact_damping_N_s_per_m;
  p.generator_V_per_m_per_s = in.generator_V_per_m_per_s;
  p.generator_time_constant_s = in.generator_time_constant_s;
  p.filter_time_constant_s = in.filter_time_constant_s;
  p.filter = in.filter;
  p.magnet_gap_m = in.magnet_gap_m;
  p.pm_force_N = in.pm_force_N;
  p.pm_gap_m = in.pm_gap_m;
  const auto st = sensors::VibroContactGauge::steady(p);
  GaugeResult r;
  r.free_amplitude_m = st.free_amplitude_m;
  r.static_offset_m = st.static_offset_m;
  r.signal_gain_V_per_m = st.signal_gain_V_per_m;
  r.intercept_m = r.free_amplitude_m;
  if (in.magnet_gap_m > 0.0 || in.pm_gap_m > 0.0 || in.pm_force_N != 0.0) {
    // (6), (9)-(11): the free oscillation is simulated (configure()), not the closed form.
    sensors::VibroContactGauge g;
    g.configure(p, full_model_step(p));
    r.free_amplitude_m = r.intercept_m = g.free_amplitude_m();
    r.static_offset_m = g.static_offset_m();
  }
  const auto pn = process_numbers({r.signal_gain_V_per_m, r.intercept_m}, in);
  r.signal_at_target_V = pn.signal_at_target_V;
  r.threshold_V = pn.threshold_V;
  r.end_time_s = pn.end_time_s;
  r.noise_variance_V2 = pn.noise_variance_V2;
  r.size_sigma_m = pn.size_sigma_m;
  const double dt = full_model_step(p);
  r.range = signal_range(p, dt, in.allowance_m, std::sqrt(r.noise_variance_V2));
  const double lag = pn.lag_m;
  r.largest_target_m = size_at_signal(p, dt, r.range.low_V, 0.0, r.range.floor_start_m) - lag;
  const double x_trip = in.target_m + lag;
  r.trip_spread_m =
      sensors::VibroContactGauge::settled_signal(p, dt, x_trip, full_model_settle(p), 0.4).spread_m;
  r.regular = r.trip_spread_m <= kRegularSpread * r.free_amplitude_m;
  return r;
}

ProcessNumbers process_numbers(const GaugeLine& line, const GaugeInput& in) {
  sensors::VibroContactGauge::Params p;  // the filter's part: its kind, T_f, the supply's ω
  p.supply_Hz = in.supply_Hz;
  p.filter_time_constant_s = in.filter_time_constant_s;
  p.filter = in.filter;
  const double K = line.gain_V_per_m;
  const double lag_s = sensors::VibroContactGauge::filter_lag_s(p) + in.relay_response_s;
  ProcessNumbers n;
  n.signal_at_target_V = K * (line.intercept_m - in.target_m);
  n.threshold_V = threshold_23(line, in.target_m, in.removal_m_per_s, lag_s);
  n.end_time_s =
      in.removal_m_per_s > 0.0 ? (in.allowance_m - in.target_m) / in.removal_m_per_s : INFINITY;
  // (25), extended to the filter: 1/(1 + βT_f) for the seed's first order.
  const double factor = sensors::VibroContactGauge::filter_noise_factor(p, in.noise_beta_per_s);
  n.noise_variance_V2 = in.noise_variance_m2 * K * K * factor;
  n.size_sigma_m = std::sqrt(in.noise_variance_m2 * factor);
  n.lag_m = in.removal_m_per_s * lag_s;
  return n;
}

double threshold_23(const GaugeLine& line, double target_m, double removal_m_per_s, double lag_s) {
  return line.gain_V_per_m * (line.intercept_m - target_m - removal_m_per_s * lag_s);
}

GaugeLine calibrated_line(const sensors::VibroContactGauge::Params& p, double dt, double x_trip) {
  const double settle = full_model_settle(p);
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  constexpr double n = 5.0;
  double spread = 0.0;
  for (int i = -2; i <= 2; ++i) {
    const double x = x_trip + 10e-6 * i;
    const auto lv = sensors::VibroContactGauge::settled_signal(p, dt, x, settle, 0.4);
    const double y = lv.mean_V;
    spread = std::max(spread, lv.spread_m);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  const double c1 = (n * sxy - sx * sy) / (n * sxx - sx * sx);  // S = c0 + c1·x
  const double c0 = (sy - c1 * sx) / n;
  return {-c1, c0 / -c1, spread};
}

double full_model_step(const sensors::VibroContactGauge::Params& p) {
  // configure(): dt·sqrt(k_c/M) ≤ 0.5 and ω·dt ≤ 0.05; here half of each, and 2e-5 s at most.
  const double wc = std::sqrt(p.contact_stiffness_N_per_m / p.probe_mass_kg);
  const double w = 2.0 * std::numbers::pi * p.supply_Hz;
  return std::min({2e-5, 0.25 / wc, 0.025 / w});
}

double full_model_settle(const sensors::VibroContactGauge::Params& p) {
  return std::max(0.8, 8.0 * p.filter_time_constant_s);
}

SignalRange signal_range(const sensors::VibroContactGauge::Params& p, double dt, double allowance_m,
                         double noise_sigma_V) {
  using G = sensors::VibroContactGauge;
  const double settle = full_model_settle(p);
  constexpr int kGrid = 24;  // x = allowance·i/24: the floor is found to 4 % of the allowance
  std::array<G::Level, kGrid + 1> lv{};
  for (int i = 0; i <= kGrid; ++i)
    lv[static_cast<std::size_t>(i)] =
        G::settled_signal(p, dt, allowance_m * i / kGrid, settle, 0.4);
  SignalRange r;
  r.free_V = lv[0].mean_V;
  r.start_V = lv[kGrid].mean_V;
  // The floor: walking back from the allowance, up to the first step where S falls (towards the
  // allowance) by more than its ripple. (Not from x = 0: with the resonance below 2ω a light
  // contact first raises the signal.)
  std::size_t k = kGrid;
  while (k > 0 && !(lv[k - 1].mean_V > lv[k].mean_V + lv[k - 1].ripple_V)) --k;
  r.floor_start_m = allowance_m * static_cast<double>(k) / kGrid;
  double top = 0.0;
  for (const auto& l : lv) top = std::max(top, l.mean_V);
  for (std::size_t i = k; i <= kGrid; ++i) {
    r.floor_V = std::max(r.floor_V, lv[i].mean_V);
    r.ripple_V = std::max(r.ripple_V, lv[i].ripple_V);
  }
  r.noise_sigma_V = noise_sigma_V;
  const double margin = r.ripple_V + 4.0 * noise_sigma_V;
  r.low_V = r.floor_V + margin;
  r.high_V = top - margin;  // the largest signal the cut reaches
  return r;
}

double size_at_signal(const sensors::VibroContactGauge::Params& p, double dt, double level,
                      double lo, double hi) {
  using G = sensors::VibroContactGauge;
  const double settle = full_model_settle(p);
  auto s = [&](double x) { return G::settled_signal(p, dt, x, settle, 0.2).mean_V; };
  if (level >= s(lo)) return lo;
  if (level <= s(hi)) return hi;
  for (int i = 0; i < 24 && hi - lo > 1e-8; ++i) {  // to 0.01 µm
    const double mid = 0.5 * (lo + hi);
    (s(mid) > level ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace lathectl::design
