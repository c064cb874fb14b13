#pragma once
// Rig E's cutting process written out by hand (issue 45 item 6): the equations of
// cutting::LathePlant::step() — the nose cutting the 0.01 mm grid, the engagement, the 360 angle
// bins and their prefix sums, the last revolution's chip, the runout and random allowance, the
// handbook force law and the dynamometer — in one function on local variables, to measure what
// the rig's cut costs against what its equations cost. The random allowance, the hardness, the
// wear and the sensor's lag and noise are the library's objects (their random streams are the
// plant's); the rest is here. Bit for bit the plant's numbers (tests/bench/hand_loop_e_test.cpp);
// handbook force form and no sensor faults (the rig clears them from the plant) only.

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "lathectl/cutting/disturbances.hpp"
#include "lathectl/cutting/force_parameter.hpp"
#include "lathectl/cutting/lathe_plant.hpp"
#include "lathectl/cutting/stock.hpp"
#include "lathectl/sensors/force_sensor.hpp"

namespace lathectl::bench {

class HandCutE {
 public:
  struct Out {
    double force_measured = 0.0, Pz = 0.0, Py = 0.0, depth = 0.0, feed = 0.0, removed_mm3 = 0.0;
  };

  // As LathePlant::configure(cfg, {}) (cell 0.01 mm, z origin 0, the scenario's nose).
  void configure(const cutting::CuttingProcess& cfg) {
    if (cfg.cutting.form != cutting::ForceForm::Handbook || !cfg.faults.empty())
      throw std::invalid_argument("hand loop E: handbook forces and no faults only");
    cfg_ = cfg;
    edge_valid_ = {false, false};
    rn_ = cfg.cutting.nose_radius_mm;
    const cutting::NoseOffset q = cutting::nose_centre_offset(cfg.tool_orientation);
    ox_ = static_cast<double>(q.x - 1) * rn_;  // the plant's: lowest x less the programmed x
    oz_ = static_cast<double>(q.z) * rn_;      // the centre's machine z less the programmed z
    // The insert's straight edges (the plant's; their geometry is configuration, not the step).
    edges_ = cutting::straight_edges_of(cfg.tool_orientation, rn_, cfg.tool_front_angle_deg,
                                        cfg.tool_back_angle_deg, cutting::kDefaultEdgeLengthMm);
    any_edge_ = edges_[0].on || edges_[1].on;
    const auto& blank = cfg.stock.blank_diameter_mm;
    cutting::Stock stock;
    stock.configure_blank(cfg.stock);
    z0_ = blank.front().at_mm;
    const auto n = static_cast<std::size_t>(
                       std::ceil((blank.back().at_mm - blank.front().at_mm) / kCell)) + 1;
    r_.assign(n, 0.0);
    low_.assign(n, 0.0);
    edge_.assign(static_cast<std::size_t>(std::ceil(2.0 * rn_ / kCell)) + 3, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      r_[i] = 0.5 * stock.blank_diameter_mm(z0_ + static_cast<double>(i) * kCell);
      low_[i] = r_[i] - cfg.stock.eccentricity_mm;
    }
    r_min_ = *std::min_element(r_.begin(), r_.end());
    r_top_ = *std::max_element(r_.begin(), r_.end());
    auto dp = cfg.disturbances;
    dp.depth_steps.clear();
    dp.runout_mm = 0.0;
    dist_.configure(dp);
    sensor_.configure(cfg.force_sensor);
    sensor_.reset(0.0);
    const auto& m = cfg.cutting.material;
    kmp_ = std::pow(m.strength / m.strength_base, m.kmp_exponent);
  }

  // (x, z_machine): the programmed point, the tool tip of the scenario's orientation; the nose
  // cuts at its lowest point under its centre, as the plant's.
  void step(double x_prog, double z_machine, double rpm_signed, double dt, Out& out) noexcept {
    const double x = x_prog + ox_;
    const double z = (0.0 - z_machine) - oz_;
    const double rpm = std::abs(rpm_signed);
    const double a0 = theta_ * 360.0;
    theta_ += rpm / 60.0 * dt;
    const double a1 = theta_ * 360.0;
    const auto [removed, on_blank, cap] = cut_cells(x, z);
    const auto [area_rev, s] = revolution(x, z, a0, a1, removed);
    // The chip with the blank's runout and the random allowance, the forces, the sensor.
    double t = s > 1e-4 && removed > 0.0 ? area_rev / s : 0.0;
    const double phi = 2.0 * std::numbers::pi * (theta_ - std::floor(theta_));
    if (t > 0.0) {
      if (on_blank) {  // the runout, no deeper than a surface an earlier pass left (the plant's)
        const double runout = t + cfg_.stock.eccentricity_mm * std::sin(phi);
        t = cap > 0.0 ? std::min(runout, std::max(t, cap)) : runout;
      }
      t = std::max(t + dist_.random_allowance_mm(z), 0.0);
    }
    const double v = std::isfinite(x) ? std::numbers::pi * 2.0 * (x + t) * rpm / 1000.0 : 0.0;
    const double strength = dist_.strength_factor(z);
    cutting::Forces f{};
    if (t > 0.0 && s > 0.0 && v > 0.0) {
      const auto& m = cfg_.cutting.material;
      const double k = kmp_ * (strength == 1.0 ? 1.0 : std::pow(strength, m.kmp_exponent)) *
                       dist_.wear_factor(t_cut_);
      const double vv = std::max(v, 1.0);
      f.Pz = 10.0 * m.Pz.Cp * std::pow(t, m.Pz.x) * std::pow(s, m.Pz.y) * std::pow(vv, m.Pz.n) * k;
      f.Py = 10.0 * m.Py.Cp * std::pow(t, m.Py.x) * std::pow(s, m.Py.y) * std::pow(vv, m.Py.n) * k;
      t_cut_ += dt;
    }
    const double power = f.Pz * v / 60.0;
    sensor_.step(dt, cutting::force_parameter(cfg_.force_parameter, f, power));
    out = {sensor_.sample(), f.Pz, f.Py, t, s, removed_mm3_};
  }

 private:
  // The nose over the grid: the cells under it come down to its edge, less those its last
  // position left at or below it (behind it along the move, the nose no lower). The removed
  // cross-section [mm²], and whether it cut the blank's own surface.
  // (By value, on locals: through references the sums were stored at every cell, as a store
  // into r_ may alias them.)
  struct Cells {
    double removed = 0.0;
    bool on_blank = false;
    double cap = 0.0;  // below a surface an earlier cut left [mm] (LathePlant's cut_surface_depth_mm)
  };
  Cells cut_cells(double x, double z) noexcept {
    double removed = 0.0;
    bool on_blank = false;
    double cap = 0.0;
    const double u_lo = (z - rn_ - z0_) / kCell, u_hi = (z + rn_ - z0_) / kCell;
    const double last = static_cast<double>(r_.size() - 1);
    const Top prev = top_;  // the last step's chip top (the plant's held decision)
    const bool prev_valid = nose_valid_;
    const std::size_t prev_i0 = nose_i0_, prev_i1 = nose_i1_;
    top_ = {};
    const double ecc = cfg_.stock.eccentricity_mm;
    double highest = 0.0;  // the chip's top: the nose's (held, or the highest surface it cut)
    bool top_on_blank = false;  // the blank's own surface
    if (!(std::isfinite(x) && std::isfinite(z))) {
      nose_valid_ = false;
      edge_valid_ = {false, false};
      return {removed, on_blank, cap};
    }
    if (u_hi >= 0.0 && u_lo <= last) {
      const auto i0 = static_cast<std::size_t>(std::ceil(std::max(u_lo, 0.0)));
      const auto i1 = static_cast<std::size_t>(std::floor(std::min(u_hi, last)));
      std::size_t j0 = i0, j1 = i1 + 1;
      auto centre = [&](std::size_t i) { return z0_ + static_cast<double>(i) * kCell; };
      // The first cell in [lo, hi) whose centre is above zq (or at it): a guess by division,
      // confirmed on the centres.
      auto first_after = [&](double zq, bool or_at, std::size_t lo, std::size_t hi) {
        auto past = [&](std::size_t i) { return or_at ? centre(i) >= zq : centre(i) > zq; };
        const double g = std::floor((zq - z0_) / kCell);
        std::size_t i = g >= static_cast<double>(hi)  ? hi
                        : g > static_cast<double>(lo) ? static_cast<std::size_t>(g)
                                                      : lo;
        while (i > lo && past(i - 1)) --i;
        while (i < hi && !past(i)) ++i;
        return i;
      };
      if (nose_valid_ && x >= nose_x_ && nose_x_ > 0.01) {
        if (z >= nose_z_ && j0 >= nose_i0_ && j0 <= nose_i1_)
          j0 = std::min({first_after(nose_z_, false, j0, j1), nose_i1_ + 1, j1});
        if (z <= nose_z_ && j1 - 1 >= nose_i0_ && j1 - 1 <= nose_i1_)
          j1 = std::max({first_after(nose_z_, true, j0, j1), nose_i0_, j0});
      }
      nose_valid_ = true;
      nose_x_ = x;
      nose_z_ = z;
      nose_i0_ = i0;
      nose_i1_ = i1;
      // The edges first, two cells at a time (sqrtpd rounds as sqrtsd), then the cells and the
      // sums in index order on locals (a store into r_ may alias any double of *this).
      const double top = x + rn_, rn2 = rn_ * rn_, z0 = z0_;
      const std::size_t n = j1 > j0 ? j1 - j0 : 0;
      double* const e = edge_.data();
      std::size_t k = 0;
  #if defined(__SSE2__)
      const __m128d v_cell = _mm_set1_pd(kCell), v_z0 = _mm_set1_pd(z0), v_z = _mm_set1_pd(z),
                    v_top = _mm_set1_pd(top), v_rn2 = _mm_set1_pd(rn2);
      __m128d v_i = _mm_set_pd(static_cast<double>(j0) + 1.0, static_cast<double>(j0));
      for (; k + 2 <= n; k += 2) {
        const __m128d dz = _mm_sub_pd(_mm_add_pd(v_z0, _mm_mul_pd(v_i, v_cell)), v_z);
        const __m128d under =
            _mm_max_pd(_mm_sub_pd(v_rn2, _mm_mul_pd(dz, dz)), _mm_setzero_pd());
        _mm_storeu_pd(e + k, _mm_sub_pd(v_top, _mm_sqrt_pd(under)));
        v_i = _mm_add_pd(v_i, _mm_set1_pd(2.0));
      }
  #endif
      for (; k < n; ++k) {
        const double dz = z0 + static_cast<double>(j0 + k) * kCell - z;
        e[k] = top - std::sqrt(std::max(rn2 - dz * dz, 0.0));
      }
      // The straight edges where they run under the nose: x_t + side·(c − z_t)·tan β.
      for (const auto& g : edges_) {
        if (!any_edge_ || !g.on) continue;
        const double xt = x + g.hx, zt = z + g.hz, side = static_cast<double>(g.side);
        const std::size_t k0 = g.side < 0 ? 0 : first_after(zt, true, j0, j0 + n) - j0;
        const std::size_t k1 = g.side < 0 ? first_after(zt, false, j0, j0 + n) - j0 : n;
        for (k = k0; k < k1; ++k)
          e[k] = std::min(e[k], xt + side * (centre(j0 + k) - zt) * g.slope);
      }
      double* const r = r_.data() + j0;
      const double* const low = low_.data() + j0;
      double mm3 = removed_mm3_;
      std::size_t top_k = n;  // the cell of the highest surface cut
      for (k = 0; k < n; ++k) {
        const double ri = r[k], edge = e[k];
        if (edge < ri) {
          on_blank = on_blank || ri > low[k];
          if (ri > highest) {
            highest = ri;
            top_k = k;
          }
          const double r_new = std::max(edge, 0.0);
          removed += (ri - r_new) * kCell;
          mm3 += std::numbers::pi * (ri * ri - r_new * r_new) * kCell;
          r[k] = r_new;
        }
      }
      if (ecc > 0.0 && x >= r_min_)  // the blank's high side cut (the plant's mark)
        for (k = 0; k < n; ++k) {
          const double ri = r[k];
          if (x >= ri && x < ri + ecc && ri > low[k] + (ecc - 1e-9)) r[k] = ri - 2e-9;
        }
      removed_mm3_ = mm3;
      if (top_k < n) {  // decided where the front takes a cell the last position did not cover
        const std::size_t top_i = j0 + top_k;
        if (prev_valid && prev.highest > 0.0 && top_i >= prev_i0 && top_i <= prev_i1) {
          on_blank = prev.on_blank;
          highest = prev.highest;
          top_on_blank = prev.on_blank_surface;
        } else {
          top_on_blank = highest > low[top_k] + (ecc - 1e-9);
        }
      }
    } else {
      nose_valid_ = false;
    }
    // The straight edges beyond the nose, from it outward until they rise past the blank's
    // largest radius; skipped where an edge has not come down since the last step.
    const double i0f = std::ceil(u_lo), i1f = std::floor(u_hi);
    double mm3 = removed_mm3_;
    double low_top = 0.0;  // the blank's lowest under the highest cell an edge cut above the top
    bool edge_top = false;
    for (std::size_t g_k = 0; any_edge_ && g_k < 2; ++g_k) {
      const auto& g = edges_[g_k];
      if (!g.on) continue;
      const double xt = x + g.hx, zt = z + g.hz, side = static_cast<double>(g.side);
      const double near = z + side * rn_;
      const bool kept = edge_valid_[g_k] && xt >= edge_x_[g_k] && side * (zt - edge_z_[g_k]) <= 0.0 &&
                        side * (near - edge_z_[g_k]) > 1e-9;
      edge_valid_[g_k] = true;
      edge_x_[g_k] = xt;
      edge_z_[g_k] = zt;
      if (kept) continue;
      const double a = g.side < 0 ? std::min(i0f - 1.0, last) : std::max(i1f + 1.0, 0.0);
      const double b = g.side < 0 ? std::max(std::ceil((zt - g.reach - z0_) / kCell), 0.0)
                                  : std::min(std::floor((zt + g.reach - z0_) / kCell), last);
      if (g.side < 0 ? a < b : a > b) continue;
      for (auto i = static_cast<std::ptrdiff_t>(a);; i += g.side) {
        const auto u = static_cast<std::size_t>(i);
        const double edge = xt + side * ((z0_ + static_cast<double>(u) * kCell) - zt) * g.slope;
        if (edge >= r_top_) break;
        const double ri = r_[u];
        if (edge < ri) {
          on_blank = on_blank || ri > low_[u];
          if (ri > highest) {
            highest = ri;
            low_top = low_[u];
            edge_top = true;
          }
          const double r_new = std::max(edge, 0.0);
          removed += (ri - r_new) * kCell;
          mm3 += std::numbers::pi * (ri * ri - r_new * r_new) * kCell;
          r_[u] = r_new;
        }
        if (i == static_cast<std::ptrdiff_t>(b)) break;
      }
    }
    removed_mm3_ = mm3;
    if (edge_top) top_on_blank = highest > low_top + (ecc - 1e-9);
    top_ = {on_blank, highest, top_on_blank};
    if (on_blank && !top_on_blank) cap = std::max(highest - x, 0.0);
    return {removed, on_blank, cap};
  }

  // The path travelled, the bins, and the last revolution's chip area and feed.
  struct Chip {
    double area_rev = 0.0;  // [mm²]
    double s = 0.0;         // [mm]
  };
  Chip revolution(double x, double z, double a0, double a1, double removed) noexcept {
    // The bins of the angle swept: each one entered is emptied first.
    double travel = 0.0;
    if (std::isfinite(x) && std::isfinite(z)) {
      if (has_last_) travel = std::hypot(x - last_x_, z - last_z_);
      last_x_ = x;
      last_z_ = z;
      has_last_ = true;
    } else {
      has_last_ = false;
    }
    const double forget = std::exp(-travel / (3.0 * kCell));  // the engagement (unused here)
    engaged_area_ = engaged_area_ * forget + removed;
    engaged_travel_ = engaged_travel_ * forget + travel;
    if (a1 - a0 >= 360.0) {
      area_.fill(removed / (a1 - a0));
      trav_.fill(travel / (a1 - a0));
      dirty_a_ = dirty_t_ = 0;
    } else if (a1 > a0) {
      dirty_a_ = std::min(dirty_a_, bin_);
      dirty_t_ = std::min(dirty_t_, bin_);
      for (double pos = a0; pos < a1;) {
        const double edge = std::floor(pos) + 1.0;
        const double end = std::min(edge, a1);
        const double w = (end - pos) / (a1 - a0);
        area_[bin_] += removed * w;
        trav_[bin_] += travel * w;
        if (end == edge) {
          bin_ = (bin_ + 1) % 360;
          if (bin_ == 0) dirty_a_ = dirty_t_ = 0;
          area_[bin_] = trav_[bin_] = 0.0;
        }
        pos = end;
      }
    } else {
      dirty_a_ = std::min(dirty_a_, bin_);
      dirty_t_ = std::min(dirty_t_, bin_);
      area_[bin_] += removed;
      trav_[bin_] += travel;
    }
    if (theta_ > 1e6) theta_ -= 1e6;
    // The last revolution's sums, from the first bin changed since they were taken.
    if (removed > 0.0) {
      for (std::size_t k = std::min(dirty_a_, dirty_t_); k < 360; ++k) {
        pre_t_[k + 1] = pre_t_[k] + trav_[k];
        pre_a_[k + 1] = pre_a_[k] + area_[k];
      }
      dirty_a_ = 360;
    } else {
      for (std::size_t k = dirty_t_; k < 360; ++k) pre_t_[k + 1] = pre_t_[k] + trav_[k];
    }
    dirty_t_ = 360;
    double area_rev = removed > 0.0 ? pre_a_[360] : 0.0;
    double s = pre_t_[360];
    if (a1 > a0 && a1 - a0 < 360.0) {
      const double covered = (359.0 + (a1 - std::floor(a1))) / 360.0;
      area_rev /= covered;
      s /= covered;
    }
    return {area_rev, s};
  }

  static constexpr double kCell = 0.01;
  cutting::CuttingProcess cfg_{};
  double rn_ = 0.8, z0_ = 0.0, kmp_ = 1.0;
  std::vector<double> r_, low_, edge_;
  double r_min_ = 0.0;  // the blank's smallest mean radius
  cutting::Disturbances dist_;
  sensors::LaggedNoisySensor sensor_;
  double ox_ = 0.0, oz_ = 0.0;
  bool nose_valid_ = false;
  struct Top {
    bool on_blank = false;
    double highest = 0.0;
    bool on_blank_surface = false;
  };
  Top top_{};  // the chip's top: decided where the nose's front met fresh material
  double nose_x_ = 0.0, nose_z_ = 0.0;
  std::size_t nose_i0_ = 0, nose_i1_ = 0;
  std::array<cutting::StraightEdge, 2> edges_{};
  bool any_edge_ = false;
  std::array<bool, 2> edge_valid_{};
  std::array<double, 2> edge_x_{}, edge_z_{};
  double r_top_ = 0.0;
  double theta_ = 0.0, last_x_ = 0.0, last_z_ = 0.0, removed_mm3_ = 0.0, t_cut_ = 0.0;
  double engaged_area_ = 0.0, engaged_travel_ = 0.0;
  bool has_last_ = false;
  std::array<double, 360> area_{}, trav_{};
  std::array<double, 361> pre_a_{}, pre_t_{};
  std::size_t bin_ = 0, dirty_a_ = 0, dirty_t_ = 0;
};

}  // namespace lathectl::bench
