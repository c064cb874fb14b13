#include "lathectl/cutting/stock.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace lathectl::cutting {

void Stock::configure(const StockParams& p) {
  configure_blank(p);
  if (p.passes.empty()) throw std::invalid_argument("stock: at least one pass");
  for (const auto& k : p.passes)
    if (!(k.z_end_mm > k.z_start_mm) || !(k.diameter_mm > 0.0))
      throw std::invalid_argument("stock: each pass needs z_end > z_start and a diameter > 0");
}

void Stock::configure_blank(const StockParams& p) {
  if (p.blank_diameter_mm.empty()) throw std::invalid_argument("stock: blank profile is empty");
  for (std::size_t i = 0; i < p.blank_diameter_mm.size(); ++i) {
    if (!(p.blank_diameter_mm[i].value > 0.0))
      throw std::invalid_argument("stock: blank diameter must be > 0");
    if (i > 0 && !(p.blank_diameter_mm[i].at_mm > p.blank_diameter_mm[i - 1].at_mm))
      throw std::invalid_argument("stock: blank profile positions must ascend");
  }
  if (p.eccentricity_mm < 0.0) throw std::invalid_argument("stock: eccentricity must be ≥ 0");
  p_ = p;
}

double Stock::blank_diameter_mm(double z) const noexcept {
  const auto& b = p_.blank_diameter_mm;
  if (z <= b.front().at_mm) return b.front().value;
  if (z >= b.back().at_mm) return b.back().value;
  const auto it = std::upper_bound(b.begin(), b.end(), z,
                                   [](double v, const ProfilePoint& q) { return v < q.at_mm; });
  const auto& hi = *it;
  const auto& lo = *(it - 1);
  return lo.value + (hi.value - lo.value) * (z - lo.at_mm) / (hi.at_mm - lo.at_mm);
}

bool Stock::blank_surface(std::size_t pass, double z) const noexcept {
  // The blank's eccentric surface survives wherever no earlier pass reached below its lowest
  // point (a pass that cut only air, or only the high side, leaves it).
  const double lowest = blank_diameter_mm(z) - 2.0 * p_.eccentricity_mm;
  for (std::size_t j = 0; j < pass && j < p_.passes.size(); ++j)
    if (z >= p_.passes[j].z_start_mm && z <= p_.passes[j].z_end_mm &&
        p_.passes[j].diameter_mm < lowest)
      return false;
  return true;
}

double Stock::surface_diameter_mm(std::size_t pass, double z) const noexcept {
  double d = blank_diameter_mm(z);
  for (std::size_t j = 0; j < pass && j < p_.passes.size(); ++j)
    if (z >= p_.passes[j].z_start_mm && z <= p_.passes[j].z_end_mm)
      d = std::min(d, p_.passes[j].diameter_mm);
  return d;
}

// Radius of the surface in front of pass k at angle φ: the eccentric blank, cut down to each
// earlier pass's radius where that pass reached (exact for partly cut, interrupted surfaces).
double Stock::depth_mm(std::size_t pass, double z, double phi) const noexcept {
  if (pass >= p_.passes.size()) return 0.0;
  const auto& k = p_.passes[pass];
  if (z < k.z_start_mm || z > k.z_end_mm) return 0.0;
  double r = 0.5 * blank_diameter_mm(z) + p_.eccentricity_mm * std::sin(phi);
  for (std::size_t j = 0; j < pass; ++j)
    if (z >= p_.passes[j].z_start_mm && z <= p_.passes[j].z_end_mm)
      r = std::min(r, 0.5 * p_.passes[j].diameter_mm);
  return std::max(r - 0.5 * k.diameter_mm, 0.0);
}

double Stock::max_depth_mm() const noexcept {
  double m = 0.0;
  for (std::size_t k = 0; k < p_.passes.size(); ++k) {
    const auto& q = p_.passes[k];
    for (int i = 0; i <= 400; ++i) {
      const double z = q.z_start_mm + (q.z_end_mm - q.z_start_mm) * i / 400.0;
      m = std::max(m, depth_mm(k, z, 0.5 * std::numbers::pi));  // the blank's high side
    }
  }
  return m;
}

double Stock::volume_to_remove_cm3() const noexcept {
  double v = 0.0;  // mm³
  for (std::size_t k = 0; k < p_.passes.size(); ++k) {
    const auto& q = p_.passes[k];
    const int n = 2000;
    const double dz = (q.z_end_mm - q.z_start_mm) / n;
    for (int i = 0; i < n; ++i) {
      const double z = q.z_start_mm + (i + 0.5) * dz;
      const double d0 = surface_diameter_mm(k, z);
      if (d0 > q.diameter_mm)
        v += std::numbers::pi / 4.0 * (d0 * d0 - q.diameter_mm * q.diameter_mm) * dz;
    }
  }
  return v / 1000.0;
}

}  // namespace lathectl::cutting
