#include "lathectl/sensors/vibro_contact_gauge.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <numbers>
#include <stdexcept>

#include "lathectl/core/parameter_error.hpp"

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
      p.generator_time_constant_s < 0.0 || p.magnet_gap_m < 0.0 || p.pm_gap_m < 0.0 ||
      !std::isfinite(p.magnet_gap_m) || !std::isfinite(p.pm_gap_m) || !std::isfinite(p.pm_force_N))
    throw std::invalid_argument(
        "vibro-contact gauge: damping, time constants and gaps must be finite and ≥ 0");
  const double wc = std::sqrt(p.contact_stiffness_N_per_m / p.probe_mass_kg);
  if (wc * dt > 0.5)
    throw core::ParameterError(
        "step", "vibro-contact gauge: step too coarse for the contact stiffness (use a step ≤ " +
                    std::to_string(0.5 / wc) + " s)");
  const double w = 2.0 * std::numbers::pi * p.supply_Hz;
  if (w * dt > 0.05)
    throw core::ParameterError("step",
                               "vibro-contact gauge: step too coarse for the supply frequency (use "
                               "a step ≤ " +
                                   std::to_string(0.05 / w) + " s)");
  p_ = p;
  dt_ = dt;
  omega_ = w;
  const Steady st = steady(p);
  a0_ = st.free_amplitude_m;
  z_eq_ = st.static_offset_m;
  gain_ = st.signal_gain_V_per_m;
  const double L = p.coil_inductance_H, r = p.coil_resistance_ohm;
  coil_lag_ = core::FirstOrderLag::with_decay(std::exp(-dt * r / L));  // τ = L/r
  gen_lag_ = core::FirstOrderLag(dt, p.generator_time_constant_s);
  filter_.configure(filter_params(p), dt);
  linear_free_state();
  if (nonlinear()) {
    // (6), (9)-(11): the linear free state is only a start; the probe's own settling (its time
    // constant 2M/h) and one more window of measurement give the free steady state.
    const double crest = z_eq_ + a0_;
    for (double gap : {p.magnet_gap_m, p.pm_gap_m})
      if (gap > 0.0 && gap < 2.0 * crest)
        throw core::ParameterError(
            gap == p.magnet_gap_m ? "magnet_gap_m" : "pm_gap_m",
            "vibro-contact gauge: the gap must exceed twice the probe's crest "
            "excursion, " +
                std::to_string(2.0 * crest * 1e3) + " mm");
    a0_ = 1.0;  // far from any surface while settling (x = 0 then sits 1 m away)
    z_eq_ = 0.0;
    reset();
    const double tau = 2.0 * p.probe_mass_kg / std::max(p.probe_damping_N_s_per_m, 1e-9);
    const double period = 1.0 / p.supply_Hz;
    const double settle = period * std::ceil(std::min(40.0 * tau, 20.0) / period);
    const auto n_settle = static_cast<std::size_t>(std::llround(settle / dt));
    const auto n_meas = static_cast<std::size_t>(std::llround(period / dt));
    for (std::size_t k = 0; k < n_settle; ++k) (void)step(-1.0);
    double lo = 1e300, hi = -1e300, g_sum = 0.0;
    for (std::size_t k = 0; k < n_meas; ++k) {
      (void)step(-1.0);
      lo = std::min(lo, z_);
      hi = std::max(hi, z_);
      g_sum += std::abs(u_);
    }
    a0_ = 0.5 * (hi - lo);
    z_eq_ = 0.5 * (hi + lo);
    free_ = {t_ + free_.t0, phi_, z_, v_, u_, g_sum / static_cast<double>(n_meas)};
  }
  reset();
}

double VibroContactGauge::synchronous_window_s(const Params& p) noexcept {
  return sensors::GaugeFilter::window_s(filter_params(p));
}

double VibroContactGauge::filter_lag_s(const Params& p) noexcept {
  return sensors::GaugeFilter::lag_s(filter_params(p));
}

double VibroContactGauge::filter_noise_factor(const Params& p, double b) noexcept {
  switch (p.filter) {
    case Params::Filter::SecondOrder: {
      const double bt = b * 0.5 * p.filter_time_constant_s;
      return (bt + 2.0) / (2.0 * (1.0 + bt) * (1.0 + bt));
    }
    case Params::Filter::Synchronous: {
      const double x = b * synchronous_window_s(p);
      return x > 1e-6 ? 2.0 * (x - 1.0 + std::exp(-x)) / (x * x) : 1.0 - x / 3.0;
    }
    case Params::Filter::FirstOrder:
      break;
  }
  return 1.0 / (1.0 + b * p.filter_time_constant_s);
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
  // The drive's period in whole steps (exact when dt divides it, as for the examples).
  const auto per = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::llround(1.0 / (2.0 * p.supply_Hz * dt))));
  double acc = 0.0, lo = 1e300, hi = -1e300, zlo = 1e300, zhi = -1e300;
  for (std::size_t k = 0; k < n_avg; ++k) {
    const double s = g.step(x);
    acc += s;
    lo = std::min(lo, s);
    hi = std::max(hi, s);
    if (k % per == 0) {  // the Poincaré section: once per drive period, same phase
      zlo = std::min(zlo, g.probe_position_m());
      zhi = std::max(zhi, g.probe_position_m());
    }
  }
  return {acc / static_cast<double>(n_avg), 0.5 * (hi - lo), zhi > zlo ? zhi - zlo : 0.0};
}

void VibroContactGauge::linear_free_state() noexcept {
  // The seed's linear free steady state at t = 0: flux, probe and generator on their sinusoids,
  // filter at the mean.
  const double w = omega_, L = p_.coil_inductance_H, r = p_.coil_resistance_ohm;
  const double theta = std::atan2(w * L, r);
  const double i_m = p_.supply_V / std::sqrt(r * r + w * w * L * L);
  // Φ² = Φ_m² sin²(ωt − θ) = Φ_m²/2 (1 − cos(2ωt − 2θ)); the probe follows −cos(2ωt − 2θ − ψ).
  const double w2 = 2.0 * w;
  const double psi = std::atan2(p_.probe_damping_N_s_per_m * w2,
                                p_.probe_stiffness_N_per_m - p_.probe_mass_kg * w2 * w2);
  const double ph = -2.0 * theta - psi;
  const double tg = p_.generator_time_constant_s;
  const double gen_phase = std::atan(w2 * tg);
  free_ = {0.0,
           L * i_m * std::sin(-theta) / p_.coil_turns,
           z_eq_ - a0_ * std::cos(ph),
           a0_ * w2 * std::sin(ph),
           p_.generator_V_per_m_per_s * a0_ * w2 / std::sqrt(1.0 + w2 * w2 * tg * tg) *
               std::sin(ph - gen_phase),
           gain_ * a0_};
}

void VibroContactGauge::reset() noexcept {
  t_ = 0.0;
  phi_ = free_.phi;
  z_ = free_.z;
  v_ = free_.v;
  u_ = free_.u;
  filter_.reset(free_.s);
}

double VibroContactGauge::step(double x) noexcept {
  return filter_.step(std::abs(step_generator(x)));
}

double VibroContactGauge::step_generator(double x) noexcept {
  const double dt = dt_;
  // Electromagnet (7) with (6): W·Φ' = V·sin ωt − r·i, i = W·Φ·(δ − z)/(L·δ): a first-order lag of
  // rate r/(L·q), q = δ/(δ − z), with the supply at the step's midpoint and z held over it.
  const double vin = p_.supply_V * std::sin(omega_ * (t_ + free_.t0 + 0.5 * dt));
  const double L = p_.coil_inductance_H, r = p_.coil_resistance_ohm, W = p_.coil_turns;
  double q = 1.0;
  core::FirstOrderLag coil = coil_lag_;
  if (p_.magnet_gap_m > 0.0) {
    q = p_.magnet_gap_m / (p_.magnet_gap_m - z_);
    coil = core::FirstOrderLag::with_decay(std::exp(-dt * r / (L * q)));  // τ = L·q/r
  }
  const double phi_ss = vin * L * q / (W * r);
  phi_ = coil.step(phi_, phi_ss);
  const double f_m = p_.force_coefficient_N_per_Wb2 * phi_ * phi_;  // (5)
  // Permanent magnet (9)-(11): F_M = F_M0·m², the generator's gain K_g·m², m = b₂/(b₂ − z).
  const double mg = p_.pm_gap_m > 0.0 ? p_.pm_gap_m / (p_.pm_gap_m - z_) : 1.0;
  const double f_pm = p_.pm_force_N * mg * mg;
  // Probe with one-sided contact; the contact stiffness and damping act implicitly.
  const double surface = z_eq_ + a0_ - x;
  const double pen = z_ - surface;
  const double m = p_.probe_mass_kg;
  double force = f_m + f_pm - p_.probe_stiffness_N_per_m * z_ - p_.probe_damping_N_s_per_m * v_;
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
  // Generator (12).
  const double emf = p_.generator_V_per_m_per_s * mg * mg * v_;
  u_ = gen_lag_.step(u_, emf);
  t_ += dt;
  return u_;
}

}  // namespace lathectl::sensors
