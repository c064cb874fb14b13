#include "lathectl/design/vibro_gauge.hpp"

#include <cmath>
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
  p.generator_V_per_m_per_s = in.generator_V_per_m_per_s;
  p.generator_time_constant_s = in.generator_time_constant_s;
  p.filter_time_constant_s = in.filter_time_constant_s;
  const auto st = sensors::VibroContactGauge::steady(p);
  GaugeResult r;
  r.free_amplitude_m = st.free_amplitude_m;
  r.static_offset_m = st.static_offset_m;
  r.signal_gain_V_per_m = st.signal_gain_V_per_m;
  r.intercept_m = r.free_amplitude_m;
  const double K = r.signal_gain_V_per_m, A = r.intercept_m, T = in.filter_time_constant_s;
  r.signal_at_target_V = K * (A - in.target_m);
  r.threshold_V = K * (A - in.target_m - in.removal_m_per_s * (T + in.relay_response_s));
  r.end_time_s =
      in.removal_m_per_s > 0.0 ? (in.allowance_m - in.target_m) / in.removal_m_per_s : INFINITY;
  r.noise_variance_V2 = in.noise_variance_m2 * K * K / (1.0 + in.noise_beta_per_s * T);
  r.size_sigma_m = std::sqrt(in.noise_variance_m2 / (1.0 + in.noise_beta_per_s * T));
  return r;
}

}  // namespace lathectl::design
