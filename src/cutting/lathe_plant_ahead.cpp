// LathePlant's look-ahead (the geometry in lathe_plant.hpp): how much material stands ahead of
// the tool along a move, for the controller's feed-forward (control::AdaptiveMachine).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "lathectl/cutting/lathe_plant.hpp"

namespace lathectl::cutting {

double LathePlant::depth_ahead_mm(double x_prog, double z_machine, double dx, double dz,
                                  double distance) const noexcept {
  const double len = std::hypot(dx, dz);
  if (!std::isfinite(x_prog) || !std::isfinite(z_machine) || !(len > 0.0) || !std::isfinite(len) ||
      !(distance >= 0.0) || r_.empty())
    return 0.0;
  const double ux = dx / len;
  const double uz_stock = -dz / len;  // the stock runs toward −z
  const double x = nose_low_x_mm(x_prog);  // the nose's lowest point, as the plant cuts
  const double z = nose_centre_stock_z_mm(z_machine);
  const double x_end = x + ux * distance;
  const double z_end = z + uz_stock * distance;
  if (std::abs(uz_stock) >= std::abs(ux)) {
    // The nose's reach ahead, or a straight edge's where one leads.
    double ahead = r_nose_;
    for (const StraightEdge& g : edges_)
      if (g.on && (g.side > 0) == (uz_stock >= 0.0))
        ahead = std::max(ahead, static_cast<double>(g.side) * g.hz + g.reach);
    const double reach = uz_stock >= 0.0 ? ahead : -ahead;
    const double r_max = max_radius_mm(std::min(z, z_end + reach), std::max(z, z_end + reach));
    return std::max(r_max - std::min(x, x_end), 0.0);
  }
  // The tool at the path's end: the cells whose material stands above its edge — under the
  // nose's circle (the arc, or a straight edge where it is lower), then along the straight
  // edges beyond it.
  const double last = static_cast<double>(r_.size() - 1);
  const double f_lo = (z_end - r_nose_ - z0_) / p_.cell_mm;
  const double f_hi = (z_end + r_nose_ - z0_) / p_.cell_mm;
  const double u_lo = std::max(f_lo, 0.0);
  const double u_hi = std::min(f_hi, last);
  double width = 0.0;
  auto along_edges = [&](double c, double edge) {
    for (const StraightEdge& g : edges_) {
      const double d = static_cast<double>(g.side) * (c - (z_end + g.hz));
      if (g.on && d >= 0.0 && d <= g.reach) edge = std::min(edge, x_end + g.hx + d * g.slope);
    }
    return edge;
  };
  if (u_lo <= u_hi) {
    for (auto i = static_cast<std::size_t>(std::ceil(u_lo));
         i <= static_cast<std::size_t>(std::floor(u_hi)) && i < r_.size(); ++i) {
      const double c = z0_ + static_cast<double>(i) * p_.cell_mm;
      const double dzc = c - z_end;
      double edge = x_end + r_nose_ - std::sqrt(std::max(r_nose_ * r_nose_ - dzc * dzc, 0.0));
      if (any_edge_) edge = along_edges(c, edge);
      if (r_[i] > edge) width += p_.cell_mm;
    }
  }
  for (const StraightEdge& g : edges_) {
    if (!g.on) continue;
    const double a = g.side < 0 ? std::min(std::ceil(f_lo) - 1.0, last)
                                : std::max(std::floor(f_hi) + 1.0, 0.0);
    const double far = (z_end + g.hz + static_cast<double>(g.side) * g.reach - z0_) / p_.cell_mm;
    const double b = g.side < 0 ? std::max(std::ceil(far), 0.0) : std::min(std::floor(far), last);
    if (g.side < 0 ? a < b : a > b) continue;
    for (auto i = static_cast<std::ptrdiff_t>(a);; i += g.side) {
      const double c = z0_ + static_cast<double>(i) * p_.cell_mm;
      if (r_[static_cast<std::size_t>(i)] > along_edges(c, std::numeric_limits<double>::infinity())) width += p_.cell_mm;
      if (i == static_cast<std::ptrdiff_t>(b)) break;
    }
  }
  return width;
}

}  // namespace lathectl::cutting
