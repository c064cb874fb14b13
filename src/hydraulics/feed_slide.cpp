#include "lathectl/hydraulics/feed_slide.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lathectl::hydraulics {

void FeedSlide::configure(const Params& p) {
  if (!(p.piston_area_m2 > 0.0) || !(p.dead_volume_m3 > 0.0) || !(p.bulk_modulus_Pa > 0.0) ||
      !(p.mass_kg > 0.0))
    throw std::invalid_argument("feed slide: area, volume, bulk modulus and mass must be > 0");
  if (p.leak_m3_per_s_Pa < 0.0 || p.coulomb_friction_N < 0.0 || p.viscous_friction_N_s_per_m < 0.0)
    throw std::invalid_argument("feed slide: leakage and friction must be ≥ 0");
  if (p.damper_capacitance_m3_per_Pa < 0.0 ||
      (p.damper_capacitance_m3_per_Pa > 0.0 && !(p.damper_resistance_Pa_s_per_m3 > 0.0)))
    throw std::invalid_argument("feed slide: a damper needs capacitance ≥ 0 and resistance > 0");
  p_ = p;
  s_ = {};
  ledger_ = {};
}

void FeedSlide::set_steady(double v, double load_N) noexcept {
  const double drive =
      load_N + p_.viscous_friction_N_s_per_m * v + (v > 0.0 ? p_.coulomb_friction_N : 0.0);
  s_.v_m_per_s = v;
  s_.void_m3 = 0.0;
  s_.p_cyl_Pa = std::max(drive / p_.piston_area_m2, 0.0);
  const double q = p_.piston_area_m2 * v + p_.leak_m3_per_s_Pa * s_.p_cyl_Pa;
  s_.p_damper_Pa =
      s_.p_cyl_Pa +
      (p_.damper_capacitance_m3_per_Pa > 0.0 ? q * p_.damper_resistance_Pa_s_per_m3 : 0.0);
}

double FeedSlide::hydraulic_omega() const noexcept {
  const double vol = p_.dead_volume_m3 + p_.piston_area_m2 * std::max(s_.x_m, 0.0);
  return p_.piston_area_m2 * std::sqrt(p_.bulk_modulus_Pa / (vol * p_.mass_kg));
}

void FeedSlide::step(double dt, double q_in, double load_N) noexcept {
  const double F = p_.piston_area_m2;
  // Velocity (semi-implicit in viscous friction).
  const double drive = F * s_.p_cyl_Pa - load_N;
  const double fc = p_.coulomb_friction_N;
  const double m = p_.mass_kg;
  const double b = p_.viscous_friction_N_s_per_m;
  double v = s_.v_m_per_s;
  if (v == 0.0 && std::abs(drive) <= fc) {
    v = 0.0;  // stuck: static friction balances the drive
  } else {
    const double sgn = v != 0.0 ? (v > 0.0 ? 1.0 : -1.0) : (drive > 0.0 ? 1.0 : -1.0);
    const double v_new = (m * v + dt * (drive - fc * sgn)) / (m + dt * b);
    // Crossing zero: stop there; it moves on next step only if the drive beats stiction.
    v = (v != 0.0 && v_new * v < 0.0) ? 0.0 : v_new;
  }
  s_.v_m_per_s = v;
  s_.x_m += v * dt;
  // Pressures with the new velocity.
  double q_d = q_in;
  if (p_.damper_capacitance_m3_per_Pa > 0.0) {
    // The damper delivers at most what it holds (p_d ≥ 0).
    q_d = std::min((s_.p_damper_Pa - s_.p_cyl_Pa) / p_.damper_resistance_Pa_s_per_m3,
                   q_in + p_.damper_capacitance_m3_per_Pa * s_.p_damper_Pa / dt);
    s_.p_damper_Pa += dt * (q_in - q_d) / p_.damper_capacitance_m3_per_Pa;
    s_.p_damper_Pa = std::max(s_.p_damper_Pa, 0.0);
  }
  const double vol = p_.dead_volume_m3 + F * std::max(s_.x_m, 0.0);
  const double swept = F * v * dt;
  const double leak = p_.leak_m3_per_s_Pa * s_.p_cyl_Pa;  // 0 while cavitated
  ledger_.delivered_m3 += q_in * dt;
  ledger_.leaked_m3 += leak * dt;
  const double p_old = s_.p_cyl_Pa;
  if (s_.void_m3 > 0.0) {
    // Cavitated: the chamber sits at p_cav = 0; net inflow refills the void first.
    s_.void_m3 -= q_d * dt - swept;
    if (s_.void_m3 < 0.0) {  // refilled within the step: the rest compresses the oil
      s_.p_cyl_Pa = -s_.void_m3 * p_.bulk_modulus_Pa / vol;
      s_.void_m3 = 0.0;
    }
  } else {
    s_.p_cyl_Pa += dt * p_.bulk_modulus_Pa / vol * (q_d - F * v - leak);
    if (s_.p_cyl_Pa < 0.0) {  // no tension in oil: the deficit opens a void (cavitation)
      s_.void_m3 = -s_.p_cyl_Pa * vol / p_.bulk_modulus_Pa;
      s_.p_cyl_Pa = 0.0;
    }
  }
  ledger_.compressed_m3 += (s_.p_cyl_Pa - p_old) * vol / p_.bulk_modulus_Pa;
}

}  // namespace lathectl::hydraulics
