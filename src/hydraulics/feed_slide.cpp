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

}  // namespace lathectl::hydraulics
