// The insert's straight edges in LathePlant (the geometry in lathe_plant.hpp): their derivation
// from LinuxCNC's I, J and Q, and the cells they cut under and beyond the nose.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>

#include "lathectl/cutting/lathe_plant.hpp"

namespace lathectl::cutting {

std::array<StraightEdge, 2> straight_edges_of(int q, double r_n, double front_deg,
                                              double back_deg, double edge_length_mm) noexcept {
  std::array<StraightEdge, 2> out{};
  if (q < 1 || q > 8 || !(r_n > 0.0) || !(edge_length_mm > 0.0)) return out;
  if (front_deg == 0.0 && back_deg == 0.0) return out;  // none given: the nose alone
  const double deg = std::numbers::pi / 180.0;
  const double lo = std::min(front_deg, back_deg) * deg;
  const double hi = std::max(front_deg, back_deg) * deg;
  if (!(hi - lo > 0.0 && hi - lo < std::numbers::pi)) return out;
  // AXIS's lathe tool: the edge at angle a runs along machine (x, z) = (sin a, cos a) from the
  // nose's point centre + r·n, n = (−cos a, sin a) for the smaller angle, (cos a, −sin a) for
  // the larger; stock z runs the other way.
  for (int k = 0; k < 2; ++k) {
    const double a = k == 0 ? lo : hi;
    const double sign = k == 0 ? -1.0 : 1.0;
    const double nx = sign * std::cos(a);
    const double nz_stock = sign * std::sin(a);  // machine n_z = −sign·sin a
    const double dx = std::sin(a);
    const double dz_stock = -std::cos(a);
    // On the lower side (the tangent point below the centre), rising, and not vertical.
    if (!(nx < -1e-9 && dx > 1e-9 && std::abs(dz_stock) > 1e-9)) continue;
    StraightEdge& e = out[static_cast<std::size_t>(k)];
    e.on = true;
    e.side = dz_stock > 0.0 ? 1 : -1;
    e.slope = dx / std::abs(dz_stock);
    e.hx = r_n * (1.0 + nx);
    e.hz = r_n * nz_stock;
    e.reach = edge_length_mm * std::abs(dz_stock);
  }
  return out;
}

void LathePlant::set_edges(double front_deg, double back_deg) noexcept {
  front_deg_ = std::isfinite(front_deg) ? front_deg : 0.0;
  back_deg_ = std::isfinite(back_deg) ? back_deg : 0.0;
  derive_edges();
}

// The edges of the tool as it is now (its orientation, nose and angles); what the last cut left
// along them is not known for the new ones.
void LathePlant::derive_edges() noexcept {
  edges_ = straight_edges_of(q_, r_nose_, front_deg_, back_deg_, edge_len_);
  any_edge_ = edges_[0].on || edges_[1].on;
  last_edge_ = {};
}

// e[k] = min(e[k], the straight edges) over the cells j0 + k under the nose that lie along an
// edge (beyond its tangent point): x_t + side·(c − z_t)·tan β, as cut_beyond_nose() computes it.
void LathePlant::edges_within_nose(double x, double z, std::size_t j0, std::size_t n,
                                   double* e) const noexcept {
  const double cell = p_.cell_mm;
  const double z0 = z0_;
  for (const StraightEdge& g : edges_) {
    if (!g.on) continue;
    const double xt = x + g.hx;
    const double zt = z + g.hz;
    const double side = static_cast<double>(g.side);
    const std::size_t k0 = g.side < 0 ? 0 : first_centre_after(zt, true, j0, j0 + n) - j0;
    const std::size_t k1 = g.side < 0 ? first_centre_after(zt, false, j0, j0 + n) - j0 : n;
    for (std::size_t k = k0; k < k1; ++k) {
      const double c = z0 + static_cast<double>(j0 + k) * cell;
      e[k] = std::min(e[k], xt + side * (c - zt) * g.slope);
    }
  }
}

// The straight edges beyond the nose's cells [i0f, i1f] (its circle's, not clipped to the grid),
// each from the nose outward along its length, until it rises past the blank's largest radius.
// An edge that has not come down since the last cut (its tangent point no lower and no further
// out along it) meets only cells the last cut left at or below it — those beyond the nose now
// were along it then — and is skipped: turning toward the nose's side leaves its trailing edge
// above the surface, and costs nothing here.
void LathePlant::cut_beyond_nose(double x, double z, bool edges, double i0f, double i1f,
                                 NoseCut& c, std::size_t& lo, std::size_t& hi) noexcept {
  if (!edges) {  // not kept along the edges this step: not known at the next
    last_edge_ = {};
    return;
  }
  const double cell = p_.cell_mm;
  const double z0 = z0_;
  const double last = static_cast<double>(r_.size() - 1);
  EdgeCut sums{c.removed, removed_mm3_, c.top, c.on_blank, r_.size(), lo, hi};
  for (std::size_t k = 0; k < edges_.size(); ++k) {
    const StraightEdge& g = edges_[k];
    if (!g.on) continue;
    const double xt = x + g.hx;
    const double zt = z + g.hz;
    const double side = static_cast<double>(g.side);
    const double near = z + side * r_nose_;  // the nose's last z on this side
    EdgePass& lp = last_edge_[k];
    const bool kept = lp.valid && xt >= lp.x && side * (zt - lp.z) <= 0.0 &&
                      side * (near - lp.z) > 1e-9;
    lp = {true, xt, zt};
    if (kept) continue;
    // Cell indices from the nose outward, a (nearest) to b (farthest), inclusive.
    const double a = g.side < 0 ? std::min(i0f - 1.0, last) : std::max(i1f + 1.0, 0.0);
    const double b = g.side < 0 ? std::max(std::ceil((zt - g.reach - z0) / cell), 0.0)
                                : std::min(std::floor((zt + g.reach - z0) / cell), last);
    if (g.side < 0 ? a < b : a > b) continue;
    cut_along_edge(g, xt, zt, static_cast<std::ptrdiff_t>(a), static_cast<std::ptrdiff_t>(b),
                   sums);
  }
  c.removed = sums.removed;
  c.on_blank = sums.on_blank;
  if (sums.top_i < r_.size()) {
    c.top = sums.top;
    c.top_on_blank = sums.top > r_blank_low_[sums.top_i] + (cfg_.stock.eccentricity_mm - 1e-9);
  }
  removed_mm3_ = sums.mm3;
  lo = sums.lo;
  hi = sums.hi;
}

// One straight edge over the cells a to b (from the nose outward), at tangent point (xt, zt):
// each cell above it comes down to it, until it rises past the blank's largest radius. Whole
// blocks of kBlock cells whose highest cell is at or below the edge where it enters them (it
// rises outward) are skipped; a block scanned whole gets its highest cell anew.
void LathePlant::cut_along_edge(const StraightEdge& g, double xt, double zt, std::ptrdiff_t ia,
                                std::ptrdiff_t ib, EdgeCut& sums) noexcept {
  const double cell = p_.cell_mm;
  const double z0 = z0_;
  const double side = static_cast<double>(g.side);
  const std::ptrdiff_t step = g.side;
  const double r_top = r_top_;
  double* const r = r_.data();
  const double* const low = r_blank_low_.data();
  EdgeCut s = sums;  // on a local: a store into r_ may alias any double of *this
  double* const bmax = block_max_.data();
  const auto blk_first = [&](std::size_t u) {
    return g.side > 0 ? u % kBlock == 0 : u % kBlock == kBlock - 1;
  };
  bool whole = false;  // the block being scanned was entered at its first cell
  double run = 0.0;    // its highest cell so far
  for (std::ptrdiff_t i = ia;; i += step) {
    const auto u = static_cast<std::size_t>(i);
    const std::size_t blk = u / kBlock;
    const double ci = z0 + static_cast<double>(u) * cell;
    const double edge = xt + side * (ci - zt) * g.slope;
    if (edge >= r_top) break;
    if (blk_first(u)) {
      if (edge >= bmax[blk]) {  // the block lies at or below the edge: to its last cell
        const auto far = static_cast<std::ptrdiff_t>(g.side > 0 ? blk * kBlock + kBlock - 1
                                                                : blk * kBlock);
        if (g.side > 0 ? far >= ib : far <= ib) break;
        i = far;
        whole = false;
        continue;
      }
      whole = true;
      run = 0.0;
    }
    const double ri = r[u];
    double r_now = ri;
    if (edge < ri) {
      s.on_blank = s.on_blank || ri > low[u];
      if (ri > s.top) {
        s.top = ri;
        s.top_i = u;
      }
      const double r_new = std::max(edge, 0.0);
      s.removed += (ri - r_new) * cell;
      s.mm3 += std::numbers::pi * (ri * ri - r_new * r_new) * cell;
      r[u] = r_new;
      r_now = r_new;
      s.lo = std::min(s.lo, u);
      s.hi = std::max(s.hi, u + 1);
    }
    run = std::max(run, r_now);
    const bool blk_last = g.side > 0 ? u % kBlock == kBlock - 1 || u + 1 == r_.size()
                                     : u % kBlock == 0;
    if (whole && blk_last) bmax[blk] = run;
    if (i == ib) break;
  }
  sums = s;
}

}  // namespace lathectl::cutting
