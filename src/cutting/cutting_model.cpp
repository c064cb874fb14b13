#include "lathectl/cutting/cutting_model.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "lathectl/cutting/feed_range.hpp"

namespace lathectl::cutting {

namespace {
double power_law(const PowerLaw& law, const CutState& c, double kp) noexcept {
  return 10.0 * law.Cp * std::pow(c.depth_mm, law.x) * std::pow(c.feed_mm_per_rev, law.y) *
         std::pow(c.speed_m_per_min, law.n) * kp;
}
double kienzle(const KienzleLaw& law, double b_mm, double h_mm) noexcept {
  return law.k11_N_per_mm2 * b_mm * std::pow(h_mm, 1.0 - law.m);
}
}  // namespace

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

Forces CuttingModel::forces(const CutState& c) const noexcept { return forces_of(c, true); }

Forces CuttingModel::forces_pz_py(const CutState& c) const noexcept { return forces_of(c, false); }

Forces CuttingModel::forces_of(const CutState& c, bool with_px) const noexcept {
  if (!(c.depth_mm > 0.0) || !(c.feed_mm_per_rev > 0.0)) return {};
  const double k = kmp_ * hardness_kp(p_.material.kmp_exponent, c.strength_factor) * c.wear_factor;
  if (p_.form == ForceForm::Handbook) {
    const double v = std::max(c.speed_m_per_min, 1.0);  // the power law has no meaning at V→0
    const CutState cv{c.depth_mm, c.feed_mm_per_rev, v, 1.0, 1.0};
    return {power_law(p_.material.Pz, cv, k), power_law(p_.material.Py, cv, k),
            with_px ? power_law(p_.material.Px, cv, k) : 0.0};
  }
  // The Kienzle constants are the material's own (data/materials.toml gives them per grade):
  // Kmp, the handbook's strength correction to its reference grade, does not apply; the local
  // hardness and wear factors do.
  const double kk = k / kmp_;
  const double b = c.depth_mm / sin_kappa_;
  const double h = c.feed_mm_per_rev * sin_kappa_;
  return {kienzle(p_.material.Fc, b, h) * kk, kienzle(p_.material.Fp, b, h) * kk,
          with_px ? kienzle(p_.material.Ff, b, h) * kk : 0.0};
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
