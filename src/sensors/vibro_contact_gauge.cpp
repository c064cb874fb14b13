#include "lathectl/sensors/vibro_contact_gauge.hpp"

#include "lathectl/sim/config_error.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <complex>
#include <numbers>
#include <stdexcept>

namespace lathectl::sensors {

void VibroContactGauge::configure(const Params& p, double dt) {
  auto pos = [](double v, const char* what) {
    if (!(v > 0.0) || !std::isfinite(v))
      throw std::invalid_argument(std::string("vibro-contact gauge: ") + what + " must be > 0");
  };
  pos(p.supply_V, "supply voltage");
  pos(p.supply_Hz, "supply frequency");
  pos(p.coil_turns, "coil turns");
  pos(p.coil_resistance_ohm, "coil resistance");
  pos(p.coil_inductance_H, "coil inductance");
  pos(p.force_coefficient_N_per_Wb2, "force coefficient");
  pos(p.probe_mass_kg, "probe mass");
  pos(p.probe_stiffness_N_per_m, "probe stiffness");
  pos(p.contact_stiffness_N_per_m, "contact stiffness");
  pos(p.generator_V_per_m_per_s, "generator constant");
  pos(p.filter_time_constant_s, "filter time constant");
  pos(dt, "step");
  if (p.probe_damping_N_s_per_m < 0.0 || p.contact_damping_N_s_per_m < 0.0 ||
      p.generator_time_constant_s < 0.0)
    throw std::invalid_argument("vibro-contact gauge: damping and time constants must be ≥ 0");
  const double wc = std::sqrt(p.contact_stiffness_N_per_m / p.probe_mass_kg);
  if (wc * dt > 0.5)
    throw sim::ConfigError(
        "run.step_s",
        "vibro-contact gauge: step too coarse for the contact stiffness (use step_s ≤ " +
        std::to_string(0.5 / wc) + ")");
  const double w = 2.0 * std::numbers::pi * p.supply_Hz;
  if (w * dt > 0.05)
    throw sim::ConfigError("run.step_s",
                           "vibro-contact gauge: step too coarse for the supply frequency (use "
                           "step_s ≤ " +
                               std::to_string(0.05 / w) + ")");
  p_ = p;
  dt_ = dt;
  omega_ = w;
  const Steady st = steady(p);
  a0_ = st.free_amplitude_m;
  z_eq_ = st.static_offset_m;
  gain_ = st.signal_gain_V_per_m;
  const double L = p.coil_inductance_H, r = p.coil_resistance_ohm;
  coil_decay_ = std::exp(-dt * r / L);
  gen_decay_ =
      p.generator_time_constant_s > 0.0 ? std::exp(-dt / p.generator_time_constant_s) : 0.0;
  filt_decay_ = std::exp(-dt / p.filter_time_constant_s);
  reset();
}

VibroContactGauge::Steady VibroContactGauge::steady(const Params& p) noexcept {
  const double w = 2.0 * std::numbers::pi * p.supply_Hz;
  const double L = p.coil_inductance_H, r = p.coil_resistance_ohm;
  const double i_m = p.supply_V / std::sqrt(r * r + w * w * L * L);
  const double phi_m = L * i_m / p.coil_turns;
  const double f_dc = p.force_coefficient_N_per_Wb2 * phi_m * phi_m / 2.0;
  const double f_2w = f_dc;  // a·Φ_m²·sin² = a·Φ_m²/2·(1 − cos 2(ωt−θ))
  const double w2 = 2.0 * w;
  const std::complex<double> z_mech(p.probe_stiffness_N_per_m - p.probe_mass_kg * w2 * w2,
                                    p.probe_damping_N_s_per_m * w2);
  return {f_2w / std::abs(z_mech), f_dc / p.probe_stiffness_N_per_m,
          2.0 / std::numbers::pi * p.generator_V_per_m_per_s * w2 /
              std::sqrt(1.0 + std::pow(w2 * p.generator_time_constant_s, 2))};
}

VibroContactGauge::Level VibroContactGauge::settled_signal(const Params& p, double dt, double x,
                                                          double settle_s, double average_s) {
  VibroContactGauge g;
  g.configure(p, dt);
  const auto n_settle = static_cast<std::size_t>(settle_s / dt);
  const auto n_avg = std::max<std::size_t>(1, static_cast<std::size_t>(average_s / dt));
  for (std::size_t k = 0; k < n_settle; ++k) (void)g.step(x);
  double acc = 0.0, lo = 1e300, hi = -1e300;
  for (std::size_t k = 0; k < n_avg; ++k) {
    const double s = g.step(x);
    acc += s;
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  return {acc / static_cast<double>(n_avg), 0.5 * (hi - lo)};
}

void VibroContactGauge::reset() noexcept {
  // Free steady state at t = 0: current, probe and generator on their sinusoids, filter at mean.
  const double w = omega_, L = p_.coil_inductance_H, r = p_.coil_resistance_ohm;
  const double theta = std::atan2(w * L, r);
  const double i_m = p_.supply_V / std::sqrt(r * r + w * w * L * L);
  t_ = 0.0;
  i_ = i_m * std::sin(-theta);
  // Φ² = Φ_m² sin²(ωt − θ) = Φ_m²/2 (1 − cos(2ωt − 2θ)); the probe follows −cos(2ωt − 2θ − ψ).
  const double w2 = 2.0 * w;
  const double psi = std::atan2(p_.probe_damping_N_s_per_m * w2,
                                p_.probe_stiffness_N_per_m - p_.probe_mass_kg * w2 * w2);
  const double ph = -2.0 * theta - psi;
  z_ = z_eq_ - a0_ * std::cos(ph);
  v_ = a0_ * w2 * std::sin(ph);
  const double tg = p_.generator_time_constant_s;
  const double gen_phase = std::atan(w2 * tg);
  u_ = p_.generator_V_per_m_per_s * a0_ * w2 / std::sqrt(1.0 + w2 * w2 * tg * tg) *
       std::sin(ph - gen_phase);
  s_ = gain_ * a0_;
}

double VibroContactGauge::step(double x) noexcept {
  const double dt = dt_;
  // Coil: exact lag with the supply held at the step's midpoint.
  const double vin = p_.supply_V * std::sin(omega_ * (t_ + 0.5 * dt));
  const double i_ss = vin / p_.coil_resistance_ohm;
  i_ = i_ss + (i_ - i_ss) * coil_decay_;
  const double phi = p_.coil_inductance_H * i_ / p_.coil_turns;
  const double f_m = p_.force_coefficient_N_per_Wb2 * phi * phi;
  // Probe with one-sided contact; the contact stiffness and damping act implicitly.
  const double surface = z_eq_ + a0_ - x;
  const double pen = z_ - surface;
  const double m = p_.probe_mass_kg;
  double force = f_m - p_.probe_stiffness_N_per_m * z_ - p_.probe_damping_N_s_per_m * v_;
  double v_new;
  if (pen > 0.0) {
    const double kc = p_.contact_stiffness_N_per_m, cc = p_.contact_damping_N_s_per_m;
    // m(v' − v)/dt = force − kc(pen + dt·v') − cc·v'   (backward in the contact terms)
    v_new = (m * v_ + dt * (force - kc * pen)) / (m + dt * dt * kc + dt * cc);
    const double fc = kc * (pen + dt * v_new) + cc * v_new;
    if (fc < 0.0) v_new = v_ + dt * force / m;  // separating: the surface cannot pull
  } else {
    v_new = v_ + dt * force / m;
  }
  z_ += dt * v_new;
  v_ = v_new;
  // Generator, rectifier, filter.
  const double emf = p_.generator_V_per_m_per_s * v_;
  u_ = emf + (u_ - emf) * gen_decay_;
  const double g = std::abs(u_);
  s_ = g + (s_ - g) * filt_decay_;
  t_ += dt;
  return s_;
}

}  // namespace lathectl::sensors
