#include "lathectl/cutting/cutting_model.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "lathectl/cutting/feed_range.hpp"

namespace lathectl::cutting {

void CuttingModel::configure(const Params& p) {
  const Material& m = p.material;
  if (!(m.strength > 0.0) || !(m.strength_base > 0.0))
    throw std::invalid_argument("material '" + m.name + "': strength must be > 0");
  if (p.form == ForceForm::Handbook && !(m.Pz.Cp > 0.0 && m.Py.Cp > 0.0 && m.Px.Cp > 0.0))
    throw std::invalid_argument("material '" + m.name + "': handbook coefficients missing");
  if (p.form == ForceForm::Kienzle &&
      !(m.Fc.k11_N_per_mm2 > 0.0 && m.Fp.k11_N_per_mm2 > 0.0 && m.Ff.k11_N_per_mm2 > 0.0))
    throw std::invalid_argument("material '" + m.name + "': Kienzle coefficients missing");
  // Past 90° (93° and 95° tools) the chip is still b = t/sin κ wide and h = s·sin κ thick: the
  // straight edge's geometry; the Kienzle constants are fitted at κ ≤ 90° and extrapolated there.
  if (!(p.approach_angle_deg > 0.0 && p.approach_angle_deg <= 95.0))
    throw std::invalid_argument("approach angle must be in (0, 95] degrees");
  if (!(p.nose_radius_mm > 0.0)) throw std::invalid_argument("nose radius must be > 0");
  p_ = p;
  cached_speed_ = -1.0;
  kmp_ = std::pow(m.strength / m.strength_base, m.kmp_exponent);
  sin_kappa_ = std::sin(p.approach_angle_deg * std::numbers::pi / 180.0);
}

double CuttingModel::radial_force_kienzle(const CutState& c, double k) const noexcept {
  return kienzle(p_.material.Fp, c.depth_mm / sin_kappa_, c.feed_mm_per_rev * sin_kappa_) * k /
         kmp_;
}

double CuttingModel::power_W(const Forces& f, double speed_m_per_min) const noexcept {
  return f.Pz * speed_m_per_min / 60.0;
}

double CuttingModel::speed_for_life(double life_min, double feed_mm_per_rev, double depth_mm,
                                    double strength_factor) const noexcept {
  if (p_.material.tool_life_ranges == 0 || !(life_min > 0.0)) return 0.0;
  const auto& r = life_range(feed_mm_per_rev);
  return r.Cv * kmv(strength_factor) /
         (std::pow(life_min, r.m) * std::pow(depth_mm, r.xv) * std::pow(feed_mm_per_rev, r.yv));
}

double CuttingModel::roughness_Rz_um(double s) const noexcept {
  return s * s / (8.0 * p_.nose_radius_mm) * 1000.0;
}
double CuttingModel::roughness_Ra_um(double s) const noexcept {
  return s * s / (32.0 * p_.nose_radius_mm) * 1000.0;
}

}  // namespace lathectl::cutting
