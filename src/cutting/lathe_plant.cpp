#include "lathectl/cutting/lathe_plant.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <numbers>
#include <stdexcept>
#include <string>

namespace lathectl::cutting {

void LathePlant::configure(const CuttingProcess& cfg, const Params& p) {
  if (!(p.cell_mm > 0.0)) throw std::invalid_argument("lathe plant: cell_mm must be > 0");
  const auto& blank = cfg.stock.blank_diameter_mm;
  if (blank.size() < 2)
    throw std::invalid_argument(
        "lathe plant: the blank needs at least two points (its extent along z)");
  const double r_nose = p.nose_radius_mm < 0.0 ? cfg.cutting.nose_radius_mm : p.nose_radius_mm;
  if (!(r_nose > 0.0) || r_nose > 50.0)
    throw std::invalid_argument("lathe plant: nose radius must be in (0, 50] mm");
  const double r_nose_max = std::max(r_nose, p.max_nose_radius_mm);
  if (!(r_nose_max <= 50.0))
    throw std::invalid_argument("lathe plant: the largest nose radius must be in (0, 50] mm");
  const int q = p.orientation < 0 ? cfg.tool_orientation : p.orientation;
  if (q < 0 || q > 9)
    throw std::invalid_argument("lathe plant: the tool orientation is 0–9 (LinuxCNC's Q)");
  if (!(p.edge_length_mm >= 0.0) || p.edge_length_mm > 1000.0)
    throw std::invalid_argument("lathe plant: edge_length_mm must be in [0, 1000] mm");
  const double length = blank.back().at_mm - blank.front().at_mm;
  const double cells = length / p.cell_mm;
  if (cells > 5e7)
    throw std::invalid_argument("lathe plant: more than 5e7 grid cells (" + std::to_string(cells) +
                                "); raise cell_mm or shorten the stock");
  cut_.configure(cfg.cutting);
  stock_.configure_blank(cfg.stock);  // the program's path cuts it, not the scenario's passes
  auto dp = cfg.disturbances;
  dp.depth_steps.clear();  // allowance variation comes from the blank's shape here
  dp.runout_mm = 0.0;      // and runout from its eccentricity
  dist_.configure(dp);
  sensor_.configure(cfg.force_sensor);
  cfg_ = cfg;
  p_ = p;
  r_nose_ = r_nose;
  r_nose_max_ = r_nose_max;
  front_deg_ = std::isfinite(p.front_angle_deg) ? p.front_angle_deg : cfg.tool_front_angle_deg;
  back_deg_ = std::isfinite(p.back_angle_deg) ? p.back_angle_deg : cfg.tool_back_angle_deg;
  edge_len_ = p.edge_length_mm;
  set_orientation(q);
  z0_ = blank.front().at_mm;
  const auto n = static_cast<std::size_t>(std::ceil(cells)) + 1;
  r_.assign(n, 0.0);
  edge_.assign(static_cast<std::size_t>(std::ceil(2.0 * r_nose_max / p.cell_mm)) + 3, 0.0);
  r_blank_low_.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const double z = z0_ + static_cast<double>(i) * p.cell_mm;
    r_[i] = 0.5 * stock_.blank_diameter_mm(z);
    r_blank_low_[i] = r_[i] - cfg.stock.eccentricity_mm;
  }
  r_blank_min_ = *std::min_element(r_.begin(), r_.end());
  r_top_ = *std::max_element(r_.begin(), r_.end());
  block_max_.assign((n + kBlock - 1) / kBlock, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    block_max_[i / kBlock] = std::max(block_max_[i / kBlock], r_[i]);
  sensor_.reset(0.0);
  faults_.reset(0.0);
  bin_area_.fill(0.0);
  bin_travel_.fill(0.0);
  prefix_area_[0] = prefix_travel_[0] = 0.0;
  dirty_area_ = dirty_travel_ = 0;
  last_nose_ = {};
  last_edge_ = {};
  pending_ = {};
  last_cut_ = {};
  cuts_ = 0;
  leader_ = nullptr;
  leader_cuts_ = 0;
  theta_ = 0.0;
  bin_ = 0;
  has_last_ = false;
  t_cut_ = 0.0;
  t_since_contact_ = -1.0;
  removed_mm3_ = 0.0;
  engaged_ = engaged_area_ = engaged_travel_ = 0.0;
}

void LathePlant::set_orientation(int q) noexcept {
  q_ = q >= 0 && q <= 9 ? q : 0;
  const NoseOffset o = nose_centre_offset(q_);
  ox_ = static_cast<double>(o.x - 1) * r_nose_;
  oz_ = static_cast<double>(o.z) * r_nose_;
  derive_edges();
}

void LathePlant::set_tool(double nose_radius_mm, int q) noexcept {
  const double r = std::clamp(nose_radius_mm, 1e-6, r_nose_max_);
  if (r != r_nose_) {
    r_nose_ = r;
    // The cells the last pass left below its edge (cut_under_nose) were another nose's; a
    // follower's next cut no longer matches this plant's (a tool change counts as a cut), and
    // this plant no longer cuts as its leader.
    last_nose_.valid = false;
    ++cuts_;
    leader_ = nullptr;
  }
  set_orientation(q);
}

double LathePlant::radius_mm(double z) const noexcept {
  const double u = (z - z0_) / p_.cell_mm;
  if (u < 0.0 || u > static_cast<double>(r_.size() - 1)) return 0.0;
  return r_[static_cast<std::size_t>(std::lround(u))];
}

double LathePlant::max_radius_mm(double z_lo, double z_hi) const noexcept {
  const double last = static_cast<double>(r_.size() - 1);
  const double u_lo = std::max((z_lo - z0_) / p_.cell_mm, 0.0);
  const double u_hi = std::min((z_hi - z0_) / p_.cell_mm, last);
  if (!(u_lo <= u_hi)) return 0.0;
  double r = 0.0;
  for (auto i = static_cast<std::size_t>(std::floor(u_lo)); i <= static_cast<std::size_t>(std::ceil(u_hi)) && i < r_.size(); ++i)
    r = std::max(r, r_[i]);
  return r;
}

// The first cell i in [lo, hi) whose centre z0 + i·cell lies above zq (at or above it when
// `or_at`), hi if none; the centres are computed as cut_under_nose() computes them.
std::size_t LathePlant::first_centre_after(double zq, bool or_at, std::size_t lo,
                                           std::size_t hi) const noexcept {
  const double cell = p_.cell_mm;
  const double z0 = z0_;
  auto past = [&](std::size_t i) {
    const double c_i = z0 + static_cast<double>(i) * cell;
    return or_at ? c_i >= zq : c_i > zq;
  };
  if (lo >= hi) return hi;
  const double guess = std::floor((zq - z0) / cell);
  std::size_t i = lo;
  if (guess >= static_cast<double>(hi))
    i = hi;
  else if (guess > static_cast<double>(lo))
    i = static_cast<std::size_t>(guess);
  while (i > lo && past(i - 1)) --i;  // the division rounded up: step back
  while (i < hi && !past(i)) ++i;     // or down: step on
  return i;
}

// e[k] = the nose's edge over cell j0 + k, x + r_n − √(r_n² − dz²) with dz = z0 + i·cell − z,
// for n cells. The SSE2 lanes compute each cell with the same operations as the scalar loop,
// so every edge is the same number either way.
void LathePlant::edges_under_nose(double x, double z, std::size_t j0, std::size_t n,
                                  double* e) const noexcept {
  const double cell = p_.cell_mm;
  const double rn = r_nose_;
  const double z0 = z0_;
  const double top = x + rn;
  const double rn2 = rn * rn;
  std::size_t k = 0;
#if defined(__SSE2__)
  const __m128d v_cell = _mm_set1_pd(cell);
  const __m128d v_z0 = _mm_set1_pd(z0);
  const __m128d v_z = _mm_set1_pd(z);
  const __m128d v_top = _mm_set1_pd(top);
  const __m128d v_rn2 = _mm_set1_pd(rn2);
  const __m128d v_zero = _mm_setzero_pd();
  const __m128d v_two = _mm_set1_pd(2.0);
  const auto i0 = static_cast<double>(j0);
  __m128d v_i = _mm_set_pd(i0 + 1.0, i0);  // whole numbers: exact, as static_cast<double>(i)
  for (; k + 2 <= n; k += 2) {
    const __m128d dz = _mm_sub_pd(_mm_add_pd(v_z0, _mm_mul_pd(v_i, v_cell)), v_z);
    const __m128d under = _mm_max_pd(_mm_sub_pd(v_rn2, _mm_mul_pd(dz, dz)), v_zero);
    _mm_storeu_pd(e + k, _mm_sub_pd(v_top, _mm_sqrt_pd(under)));
    v_i = _mm_add_pd(v_i, v_two);
  }
#endif
  for (; k < n; ++k) {
    const double dz = z0 + static_cast<double>(j0 + k) * cell - z;
    e[k] = top - std::sqrt(std::max(rn2 - dz * dz, 0.0));
  }
}

// The highest surface cut is the blank's own while its cell is still at the blank's radius
// (low + e), which the runout lifts; any other an earlier cut left, at every angle. Decided where
// the nose's front takes a cell its last position did not cover (the material as the pass found
// it); a cell that position covered is one this nose cut a step ago, and the chip's top is still
// where the front last met fresh material. Decided every step instead, a step that took no new
// cell (a step travels less than a cell: 7 µm at 0.5 mm/rev and 1700 rpm on 10 µm cells) read the
// nose's own last cut as an earlier pass's surface and clipped the runout's upper half: an
// eccentric pass's chip came out 1.4-3 % shallower than its geometry, and by how much depended on
// the simulation step (issue 47, e_stepped_life's tool life).
void LathePlant::chip_top(NoseCut& c, const NoseCut& prev, const NosePass& prev_nose,
                          std::size_t top_i, double top, bool top_on_blank) noexcept {
  if (prev_nose.valid && prev.top > 0.0 && top_i >= prev_nose.i0 && top_i <= prev_nose.i1) {
    c.on_blank = prev.on_blank;
    c.top = prev.top;
    c.top_on_blank = prev.top_on_blank;
  } else {
    c.top = top;
    c.top_on_blank = top_on_blank;
  }
}

// A pass within the runout above the blank's mean radius cuts its high side, which the grid (one
// radius a cell) cannot hold: the cells the nose's lowest point passes over are marked as no
// longer the blank's own surface, so a later pass's chip gets no runout above them (2e-9 mm lower,
// nothing counted as removed). Unmarked, a second pass read the full runout there and met a chip
// 15 % deeper than where the first pass had cut the taper before it (generated part 1157). Only
// where the nose is at or above the blank's lowest mean radius (in cut_under_nose's cell loop the
// test cost rig E 2 % of its instructions).
void LathePlant::mark_high_side(double x, std::size_t j0, std::size_t n) noexcept {
  const double ecc = cfg_.stock.eccentricity_mm;
  if (!(ecc > 0.0 && x >= r_blank_min_)) return;
  double* const r = r_.data() + j0;
  const double* const low = r_blank_low_.data() + j0;
  for (std::size_t k = 0; k < n; ++k) {
    const double ri = r[k];
    if (x >= ri && x < ri + ecc && ri > low[k] + (ecc - 1e-9)) r[k] = ri - 2e-9;
  }
}

// The cells of [j0, j_end) the nose cannot cut, taken off its ends: those its last pass left at
// or below its edge, where the edge has not come down since — the nose no lower (x ≥ x_prev)
// and the cell no nearer its centre (|dz| ≥ |dz_prev|: behind the last position along the move).
// Every rounded step of edge(x, dz) is monotone (the straight edges' too: they rise away from
// the nose), so this holds for the computed edges and skipping them changes no number. Turning
// skips the trailing half of the nose; a dwell skips all of it.
void LathePlant::nose_window(double x, double z, std::size_t& j0,
                             std::size_t& j_end) const noexcept {
  const NosePass& lp = last_nose_;
  if (lp.valid && x >= lp.x && lp.x > 0.01) {  // x > 0: the last pass left r = edge, not 0
    // The skipped cells are a run at each end of [i0, i1]: the cell centres rise with i, so
    // "c_i ≤ z_prev" holds up to one index and "c_i ≥ z_prev" from one on. Found by division
    // and confirmed on the same computed centres (a walk cell by cell was a fifth of rig E's
    // time, 120 cells a step).
    // The trailing end: cells of the last pass at or behind z_prev.
    if (z >= lp.z && j0 >= lp.i0 && j0 <= lp.i1)
      j0 = std::min({first_centre_after(lp.z, false, j0, j_end), lp.i1 + 1, j_end});
    // Moving toward −z: the cells of the last pass at or ahead of z_prev.
    if (z <= lp.z && j_end - 1 >= lp.i0 && j_end - 1 <= lp.i1)
      j_end = std::max({first_centre_after(lp.z, true, j0, j_end), lp.i0, j0});
  }
}

// The nose's pass over the grid at (x, z): each cell under its circle comes down to its edge.
// Members are read into locals and removed_mm3_ summed in one: a store into r_ may alias any
// double of *this, so the compiler reloaded them and stored removed_mm3_ on every cell (rig E:
// 240 cells a step, most of its time). The sums run in the same order: the same numbers.
LathePlant::NoseCut LathePlant::cut_under_nose(double x, double z, bool edges) noexcept {
  NoseCut c;
  const double cell = p_.cell_mm;
  const double rn = r_nose_;
  const double z0 = z0_;
  const double u_lo = (z - rn - z0) / cell;
  const double u_hi = (z + rn - z0) / cell;
  const double last = static_cast<double>(r_.size() - 1);
  const NoseCut prev = last_cut_.result;  // the last step's cut, for the chip's top below
  const NosePass prev_nose = last_nose_;
  last_cut_ = {x, z, 0, 0, c, edges};
  if (!(std::isfinite(x) && std::isfinite(z))) {
    last_nose_.valid = false;
    last_edge_ = {};
    return c;
  }
  std::size_t lo = r_.size();  // the cells the straight edges changed: [lo, hi)
  std::size_t hi = 0;
  if (!(u_hi >= 0.0 && u_lo <= last)) {  // the nose off the grid; its edges may reach it
    last_nose_.valid = false;
    if (any_edge_) cut_beyond_nose(x, z, edges, std::ceil(u_lo), std::floor(u_hi), c, lo, hi);
    if (lo < hi) last_cut_ = {x, z, lo, hi, c, edges};
    return c;
  }
  const auto i0 = static_cast<std::size_t>(std::ceil(std::max(u_lo, 0.0)));
  const auto i1 = static_cast<std::size_t>(std::floor(std::min(u_hi, last)));
  std::size_t j0 = i0;
  std::size_t j_end = i1 + 1;
  nose_window(x, z, j0, j_end);
  last_nose_ = {true, x, z, i0, i1};
  if (j_end <= j0) {
    if (any_edge_) cut_beyond_nose(x, z, edges, std::ceil(u_lo), std::floor(u_hi), c, lo, hi);
    if (lo < hi) last_cut_ = {x, z, lo, hi, c, edges};
    return c;
  }
  // The edge under each cell first (the cells are independent: two at a time where the CPU has
  // SSE2, whose sqrtpd rounds as sqrtsd does), then the cells and the sums, in index order.
  const std::size_t n = j_end - j0;
  double* const e = edge_.data();
  edges_under_nose(x, z, j0, n, e);
  if (edges && any_edge_) edges_within_nose(x, z, j0, n, e);
  double* const r = r_.data() + j0;
  const double* const low = r_blank_low_.data() + j0;
  double removed = 0.0;
  double removed_mm3 = removed_mm3_;
  bool on_blank = false;
  double top = 0.0;  // the highest surface cut, at cell top_k
  std::size_t top_k = n;
  for (std::size_t k = 0; k < n; ++k) {
    const double ri = r[k];
    const double edge = e[k];
    if (edge < ri) {
      on_blank |= ri > low[k];
      if (ri > top) {
        top = ri;
        top_k = k;
      }
      const double r_new = std::max(edge, 0.0);
      removed += (ri - r_new) * cell;
      removed_mm3 += std::numbers::pi * (ri * ri - r_new * r_new) * cell;
      r[k] = r_new;
    }
  }
  mark_high_side(x, j0, n);
  c.removed = removed;
  c.on_blank = on_blank;
  if (top_k < n)
    chip_top(c, prev, prev_nose, j0 + top_k, top,
             top > low[top_k] + (cfg_.stock.eccentricity_mm - 1e-9));
  removed_mm3_ = removed_mm3;
  if (any_edge_) cut_beyond_nose(x, z, edges, std::ceil(u_lo), std::floor(u_hi), c, lo, hi);
  last_cut_ = {x, z, std::min(j0, lo), std::max(j_end, hi), c, edges};
  return c;
}

namespace {
template <class Passes>
bool same_edge_passes(const Passes& a, const Passes& b) {
  for (std::size_t k = 0; k < a.size(); ++k)
    if (a[k].valid != b[k].valid || a[k].x != b[k].x || a[k].z != b[k].z) return false;
  return true;
}
}  // namespace

void LathePlant::follow(const LathePlant* leader) {
  leader_ = nullptr;
  if (leader == nullptr) return;
  const auto& l = *leader;
  if (!(l.r_ == r_ && l.r_blank_low_ == r_blank_low_ && l.z0_ == z0_ &&
        l.p_.cell_mm == p_.cell_mm && l.r_nose_ == r_nose_ && l.q_ == q_ &&
        l.front_deg_ == front_deg_ && l.back_deg_ == back_deg_ && l.edge_len_ == edge_len_ &&
        same_edge_passes(l.last_edge_, last_edge_) &&
        l.removed_mm3_ == removed_mm3_ &&
        l.last_nose_.valid == last_nose_.valid && l.last_nose_.x == last_nose_.x &&
        l.last_nose_.z == last_nose_.z && l.last_nose_.i0 == last_nose_.i0 &&
        l.last_nose_.i1 == last_nose_.i1))
    throw std::invalid_argument("lathe plant: follows a plant whose workpiece differs");
  leader_ = leader;
  leader_cuts_ = l.cuts_;
}

LathePlant::NoseCut LathePlant::nose_cut(double x, double z, bool edges) noexcept {
  ++cuts_;
  if (leader_ != nullptr) {
    const LathePlant& l = *leader_;
    const LastCut& lc = l.last_cut_;
    auto same = [](double a, double b) {
      return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
    };
    if (l.cuts_ == leader_cuts_ + 1 && same(lc.x, x) && same(lc.z, z) && lc.edges == edges) {
      // Both grids were equal before the leader's cut, which was at this position: after it
      // they are equal again (the cells outside [j0, j_end) it did not touch).
      std::copy(l.r_.begin() + static_cast<std::ptrdiff_t>(lc.j0),
                l.r_.begin() + static_cast<std::ptrdiff_t>(lc.j_end),
                r_.begin() + static_cast<std::ptrdiff_t>(lc.j0));
      last_nose_ = l.last_nose_;
      last_edge_ = l.last_edge_;
      removed_mm3_ = l.removed_mm3_;
      last_cut_ = lc;
      leader_cuts_ = l.cuts_;
      return lc.result;
    }
    leader_ = nullptr;  // out of step: its own grid from now on
  }
  return cut_under_nose(x, z, edges);
}

// Spreads this step's chip and travel over the spindle-angle bins it swept, [a0, a1), opening
// (emptying) each bin it enters: putting a whole step into one bin made the window one
// revolution plus about half a step long — s came out 1 % high at 1200 rpm and 1 ms, 2.5 % at
// 3000 rpm. Marks the first bin written for revolution_sums().
void LathePlant::spread_over_bins(double a0, double a1, double removed, double travel) noexcept {
  if (a1 - a0 >= static_cast<double>(kBins)) {  // a revolution or more per step
    bin_area_.fill(removed / (a1 - a0));
    bin_travel_.fill(travel / (a1 - a0));
    dirty_area_ = dirty_travel_ = 0;
  } else if (a1 > a0) {
    dirty_area_ = std::min(dirty_area_, bin_);
    dirty_travel_ = std::min(dirty_travel_, bin_);
    double pos = a0;
    while (pos < a1) {
      const double edge = std::floor(pos) + 1.0;
      const double end = std::min(edge, a1);
      const double w = (end - pos) / (a1 - a0);
      bin_area_[bin_] += removed * w;
      bin_travel_[bin_] += travel * w;
      if (end == edge) {
        bin_ = (bin_ + 1) % kBins;
        if (bin_ == 0) dirty_area_ = dirty_travel_ = 0;
        bin_area_[bin_] = 0.0;
        bin_travel_[bin_] = 0.0;
      }
      pos = end;
    }
  } else {  // spindle stopped: the chip accumulates
    dirty_area_ = std::min(dirty_area_, bin_);
    dirty_travel_ = std::min(dirty_travel_, bin_);
    bin_area_[bin_] += removed;
    bin_travel_[bin_] += travel;
  }
}

// Σ bins from bin 0 up, as prefix sums: only those from the first bin written since the last
// call are summed again (the same additions in the same order as summing all 360 each step,
// which cost rig E a fifth of its time). The area is summed only when asked (it is read only
// on a step that removed material).
void LathePlant::revolution_sums(bool area, double& area_rev, double& travel_rev) noexcept {
  if (area) {  // both chains in one loop, from the first bin either lacks: they overlap in time
    const std::size_t k0 = std::min(dirty_area_, dirty_travel_);
    for (std::size_t k = k0; k < kBins; ++k) {
      prefix_travel_[k + 1] = prefix_travel_[k] + bin_travel_[k];
      prefix_area_[k + 1] = prefix_area_[k] + bin_area_[k];
    }
    dirty_area_ = kBins;
    area_rev = prefix_area_[kBins];
  } else {
    for (std::size_t k = dirty_travel_; k < kBins; ++k)
      prefix_travel_[k + 1] = prefix_travel_[k] + bin_travel_[k];
  }
  dirty_travel_ = kBins;
  travel_rev = prefix_travel_[kBins];
}

void LathePlant::cut(const Input& in, double dt, Output& out) noexcept {
  cut_geometry(in, dt, out);
  chip(out);
}

// The plant cuts at the nose's lowest point (x) under its centre (stock z): the programmed
// point moved by the orientation's offset (nose_low_x_mm, nose_centre_stock_z_mm).
void LathePlant::cut_geometry(const Input& in, double dt, Output& out) noexcept {
  const double x = nose_low_x_mm(in.x_mm);
  const double z = nose_centre_stock_z_mm(in.z_mm);
  const double rpm = std::abs(in.rpm);

  // Spindle angle of this step, in bins: [a0, a1).
  const double turns = rpm / 60.0 * dt;
  const double a0 = theta_ * static_cast<double>(kBins);
  theta_ += turns;
  const double a1 = theta_ * static_cast<double>(kBins);

  // Material the nose removes this step.
  // A grooving or parting insert's sides are its width's, not a turning insert's edges.
  const NoseCut nc = nose_cut(x, z, !(in.insert_width_mm > 0.0));
  const double removed = nc.removed;
  double travel = 0.0;
  if (std::isfinite(x) && std::isfinite(z)) {
    if (has_last_) travel = std::hypot(x - last_x_, z - last_z_);
    last_x_ = x;
    last_z_ = z;
    has_last_ = true;
  } else {
    has_last_ = false;  // no position: the path restarts where the next one is
  }
  // The engagement: removed cross-section over path travelled, both forgotten over 3 cells of
  // travel. Per step it would be the grid's, not the cut's: at an entry feed of 0.05 mm/rev a
  // step travels 1/15 of a cell, and a cell entering the nose is cut at once (3.1 mm read for a
  // 1.5 mm cut).
  const double forget = std::exp(-travel / (3.0 * p_.cell_mm));
  engaged_area_ = engaged_area_ * forget + removed;
  engaged_travel_ = engaged_travel_ * forget + travel;
  if (!has_last_) engaged_area_ = engaged_travel_ = 0.0;
  engaged_ = engaged_travel_ > 1e-12 ? engaged_area_ / engaged_travel_ : 0.0;
  spread_over_bins(a0, a1, removed, travel);
  if (theta_ > 1e6) theta_ -= 1e6;  // keep the angle's fraction precise (1e6·kBins bins: whole)
  // The bins hold the last kBins − 1 bins and the filled part of the current one.
  pending_ = {removed > 0.0, a1 > a0 && a1 - a0 < static_cast<double>(kBins),
              (static_cast<double>(kBins) - 1.0 + (a1 - std::floor(a1))) /
                  static_cast<double>(kBins)};
  out.removed_mm3 = removed_mm3_;
  out.engaged_depth_mm = engaged_;
  out.on_blank = nc.on_blank;
  out.cut_surface_depth_mm =
      nc.on_blank && !nc.top_on_blank ? std::max(nc.top - x, 0.0) : 0.0;
}

// Chip of the last revolution.
void LathePlant::chip(Output& out) noexcept {
  double area_rev = 0.0;
  double travel_rev = 0.0;
  revolution_sums(pending_.removed, area_rev, travel_rev);
  if (pending_.scale) {
    area_rev /= pending_.covered;
    travel_rev /= pending_.covered;
  }
  const double s = travel_rev;
  out.chip_depth_mm = s > 1e-4 && pending_.removed ? area_rev / s : 0.0;
  out.feed_per_rev_mm = s;
}

void LathePlant::step(const Input& in, double dt, Output& out) noexcept {
  cut(in, dt, out);
  const double x = nose_low_x_mm(in.x_mm);
  const double z = nose_centre_stock_z_mm(in.z_mm);
  const double rpm = std::abs(in.rpm);
  const double s = out.feed_per_rev_mm;
  double t = out.chip_depth_mm;
  const double phi = 2.0 * std::numbers::pi * (theta_ - std::floor(theta_));
  if (t > 0.0) {
    if (out.on_blank) {
      // The runout of the eccentric blank's surface, t + e·sin φ — but where the nose meets the
      // blank below a surface an earlier pass left (running off onto a forged neck's taper),
      // that pass cut the blank down to its surface at every angle: the chip is no deeper.
      const double runout = t + cfg_.stock.eccentricity_mm * std::sin(phi);
      const double cap = out.cut_surface_depth_mm;
      t = cap > 0.0 ? std::min(runout, std::max(t, cap)) : runout;
    }
    t = std::max(t + dist_.random_allowance_mm(z), 0.0);
  }
  // No position (not homed): no cutting speed either — a NaN here made the cutting power, and
  // the LinuxCNC plant's drive-power pin, NaN until homing: a sensor_not_finite alarm at start.
  const double v = std::isfinite(x) ? std::numbers::pi * 2.0 * (x + t) * rpm / 1000.0 : 0.0;
  const double strength = dist_.strength_factor(z);
  Forces f{};
  if (t > 0.0 && s > 0.0 && v > 0.0) {
    const double b = in.insert_width_mm > 0.0 ? in.insert_width_mm : t;  // a plunge: its width
    f = cut_.forces_pz_py({b, s, v, strength, dist_.wear_factor(t_cut_)});  // no Px here
    t_cut_ += dt;
    if (t_since_contact_ < 0.0) t_since_contact_ = 0.0;
  }
  if (t_since_contact_ >= 0.0) t_since_contact_ += dt;
  const double power = cut_.power_W(f, v);
  const double param = cutting::force_parameter(cfg_.force_parameter, f, power);
  sensor_.step(dt, param);
  const double sample = sensor_.sample();
  out.force_measured = t_since_contact_ >= 0.0
                           ? faults_.apply(cfg_.faults, t_since_contact_, sample,
                                           cfg_.force_sensor.range * 2.0 + 1.0)
                           : sample;
  out.force_parameter = param;
  out.Pz_N = f.Pz;
  out.Py_N = f.Py;
  out.cut_power_W = power;
  out.depth_mm = t;
  out.speed_m_per_min = v;
  out.strength_factor = strength;
  out.in_contact = t > 0.0;
  out.time_in_cut_s = t_cut_;
}

}  // namespace lathectl::cutting
