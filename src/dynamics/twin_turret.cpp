#include "lathectl/dynamics/twin_turret.hpp"

#include "lathectl/core/parameter_error.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace lathectl::dynamics {

namespace {
constexpr double kPi = std::numbers::pi;
void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("twin-turret cut: " + what);
}
}  // namespace

// configure() in phases, in the order they run.

// What a cut needs of its parameters; throws before anything changes.
void TwinTurretCut::validate(const Params& p, double dt) {
  require(dt > 0.0, "the step must be positive");
  require(p.modes >= 1 && p.modes <= kMaxModes, "modes must be in 1..6");
  const double L_mm = p.part.length_m * 1e3;
  require(p.z_start_mm > 0.0 && p.z_start_mm < L_mm,
          "the material must start between the centres: 0 < z_start < length");
  (void)beam_modes_at(p.part, p.z_start_mm * 1e-3, p.modes);  // validates the part
  require(p.part.damping_ratio < 1.0, "the part's damping ratio must be below 1");
  require(p.rpm_nominal > 0.0 && p.feed_mm_per_rev > 0.0, "rpm and feed must be positive");
  require(p.depth_mm[0] >= 0.0 && p.depth_mm[1] >= 0.0, "depths must be non-negative");
  require(p.chip_law == ChipLaw::Linear ||
              (p.depth_mm[0] > 0.0 && (p.setup == TwinSetup::Single || p.depth_mm[1] > 0.0)),
          "the power chip law needs a positive depth t0 on every tool: F(t0)·(t/t0)^(1−m)");
  require(p.overlap >= 0.0 && p.overlap <= 1.0, "overlap must be in [0, 1]");
  require(p.tool2_lag_mm >= 0.0, "tool2_lag must be non-negative");
  require(p.slowest_feed_fraction > 0.0 && p.slowest_feed_fraction <= 1.0,
          "slowest_feed_fraction must be in (0, 1]");
  const ProcessDamping& pd = p.process_damping;
  require(pd.k_sp_N_per_m3 >= 0.0 && pd.wear_land_mm >= 0.0 && pd.flank_length_mm > 0.0 &&
              pd.clearance_deg > 0.0 && pd.clearance_deg < 45.0,
          "process damping: K_sp, VB ≥ 0, flank length > 0, clearance in (0°, 45°)");
  require(p.tool_modes.size() <= static_cast<std::size_t>(kMaxToolModes),
          "at most " + std::to_string(kMaxToolModes) + " tool modes");
  for (const Mode& m : p.tool_modes)
    require(m.stiffness_N_per_m > 0.0 && m.natural_frequency_Hz > 0.0 && m.damping_ratio > 0.0 &&
                m.damping_ratio < 1.0 && std::isfinite(m.stiffness_N_per_m) &&
                std::isfinite(m.natural_frequency_Hz) && std::isfinite(m.angle_rad),
            "a tool mode needs k > 0, f_n > 0 and 0 < ζ < 1");
}

// The surface memory: cells per revolution at this step, enough revolutions for tool 2's lag
// (and the axial search's slowest pass), one ring per layer cut.
void TwinTurretCut::size_surface_memory(const Params& p, double dt, int lag_revs, bool axial) {
  const double tau = 60.0 / p.rpm_nominal;
  cells_per_rev_ = std::max<std::size_t>(64, static_cast<std::size_t>(std::lround(tau / dt)));
  if (lag_revs > 200)
    throw core::ParameterError("tool2_lag_mm", "tool2_lag_mm is more than 200 revolutions of feed");
  // The axial-position search needs every pass of tool 1 within the lag, at its slowest feed.
  const double mem_revs =
      axial ? std::ceil(p.tool2_lag_mm / (p.feed_mm_per_rev * p.slowest_feed_fraction)) + 3.0
            : lag_revs + 2.0;
  if (!(static_cast<double>(cells_per_rev_) * mem_revs <= 4e6))
    throw core::ParameterError(
        "step",
        "the surface memory (revolutions × steps per revolution) exceeds 4e6 cells: raise the "
        "step, the speed, or shorten tool2_lag_mm");
  ring_cells_ = cells_per_rev_ * static_cast<std::size_t>(mem_revs);
  uncut_reads_ = clipped_reads_ = 0;
  delay_rev_ = 0.0;
  sin_kappa_ = std::sin(p.cutting.approach_angle_deg * kPi / 180.0);
  const std::size_t n_rings = p.setup == TwinSetup::DepthDivision ? 2 : 1;
  rings_.assign(n_rings, Ring{std::vector<double>(ring_cells_, 0.0),
                              std::vector<double>(ring_cells_, p.z_start_mm)});
}

// The two edges: which side, which ring each writes and reads, how far back, and the flank's
// history for process damping.
void TwinTurretCut::place_edges(const Params& p, double dt, int lag_revs, bool axial) {
  const ProcessDamping& pd = p.process_damping;
  n_tools_ = p.setup == TwinSetup::Single ? 1 : 2;
  for (int i = 0; i < 2; ++i) {
    Edge& e = edges_[i];
    e = Edge{};
    e.sigma = i == 0 ? 1.0 : -1.0;
    e.alpha = i == 0 ? 0.0 : kPi;
    e.t0_mm = p.depth_mm[i];
    e.d_weight = p.overlap;
    if (pd.on()) {
      // One sample per step over the flank at half the nominal speed (the spindle may sag).
      const double v_low = 0.5 * kPi * p.part.diameter_m * p.rpm_nominal / 60.0;
      const auto n = static_cast<std::size_t>(std::ceil(pd.flank_length_mm * 1e-3 / (v_low * dt)));
      require(n <= 100000, "process damping: the flank spans more than 1e5 steps");
      e.hist.assign(n + 2, 0.0);
    }
  }
  if (p.setup == TwinSetup::FeedDivision) {
    // One shared layer. In cumulative material-angle cells tool 2 (at π) finds tool 1's pass
    // of half a turn ago in the cell it is at (lag 0); tool 1 finds tool 2's one turn of cells
    // back (lag 1).
    edges_[1].d_lag_rev = 0.0;
    edges_[1].z_lag_rev = 0.0;
  }
  if (p.setup == TwinSetup::DepthDivision) {
    Edge& e2 = edges_[1];
    e2.write_ring = 1;
    e2.d_ring = 0;
    e2.d_lag_rev = lag_revs;
    e2.d_weight = 1.0;
    e2.axial = axial;
    e2.pass_hint = lag_revs;
  }
  for (Edge& e : edges_)
    e.last_cell = static_cast<long long>(
        std::floor(-e.alpha / (2.0 * kPi) * static_cast<double>(cells_per_rev_)));
}

// The tool's modes along the radial line, discretised exactly over one step.
void TwinTurretCut::discretise_tool_modes(const Params& p) {
  // The tool's modes along the radial line: k/cos²θ (a mode across it is not coupled).
  n_tool_modes_ = static_cast<int>(p.tool_modes.size());
  for (int j = 0; j < n_tool_modes_; ++j) {
    const Mode& m = p.tool_modes[static_cast<std::size_t>(j)];
    const double c2 = std::cos(m.angle_rad) * std::cos(m.angle_rad);
    const double wn = 2.0 * kPi * m.natural_frequency_Hz, z = m.damping_ratio;
    const double wd = wn * std::sqrt(1.0 - z * z), s = z * wn;
    const double e = std::exp(-s * dt_), c = std::cos(wd * dt_), sn = std::sin(wd * dt_);
    tphi11_[j] = e * (c + s / wd * sn);
    tphi12_[j] = e * sn / wd;
    tphi21_[j] = -wn * wn * tphi12_[j];
    tphi22_[j] = e * (c - s / wd * sn);
    // Force F along the line: q̈ + 2ζω q̇ + ω² q = ω²·F·cos²θ/k, so the gains of the part's modes
    // with 1/k and 1/m scaled by cos²θ.
    const double compliance = c2 > 1e-12 ? c2 / m.stiffness_N_per_m : 0.0;
    tg1_[j] = (1.0 - tphi11_[j]) * compliance;
    tg2_[j] = tphi12_[j] * wn * wn * compliance;
  }
}

void TwinTurretCut::configure(const Params& p, double dt) {
  validate(p, dt);
  p_ = p;
  p_.cutting.form = cutting::ForceForm::Kienzle;
  cut_.configure(p_.cutting);
  dt_ = dt;
  sound_ = true;
  const bool depth = p.setup == TwinSetup::DepthDivision;
  const bool axial = depth && p.inter_tool_delay == InterToolDelay::AxialPositions;
  const int lag_revs =
      depth ? static_cast<int>(std::lround(p.tool2_lag_mm / p.feed_mm_per_rev)) : 0;
  size_surface_memory(p, dt, lag_revs, axial);
  place_edges(p, dt, lag_revs, axial);
  discretise_tool_modes(p);
  for (int j = 0; j < kMaxModes; ++j) q_[j] = qd_[j] = shape_[j] = 0.0;
  modes_at_mm_ = -1e9;
  update_modes(p.z_start_mm);
  seed_pending_ = p.initial_disturbance_um != 0.0;
  y_ = 0.0;
}

void TwinTurretCut::update_modes(double x) noexcept {
  const double L = p_.part.length_m * 1e3;
  const double x_mm = std::clamp(p_.modes_follow_tool ? x : p_.z_start_mm, 1.0, L - 1.0);
  if (std::abs(x_mm - modes_at_mm_) < 0.5) return;
  modes_at_mm_ = x_mm;
  for (int j = 0; j < p_.modes; ++j) {
    const BeamModeAt bm = beam_mode_at(p_.part, x_mm * 1e-3, j + 1);
    // Keep the physical modal amplitude: q = η·φ(x_c).
    if (shape_[j] != 0.0) {
      const double r = bm.shape / shape_[j];
      q_[j] *= r;
      qd_[j] *= r;
    }
    shape_[j] = bm.shape;
    const double wn = 2.0 * kPi * bm.mode.natural_frequency_Hz;
    const double z = bm.mode.damping_ratio;
    const double wd = wn * std::sqrt(1.0 - z * z);
    const double s = z * wn;
    const double e = std::exp(-s * dt_), c = std::cos(wd * dt_), sn = std::sin(wd * dt_);
    phi11_[j] = e * (c + s / wd * sn);
    phi12_[j] = e * sn / wd;
    phi21_[j] = -wn * wn * phi12_[j];
    phi22_[j] = e * (c - s / wd * sn);
    g1_[j] = (1.0 - phi11_[j]) / bm.mode.stiffness_N_per_m;
    g2_[j] = phi12_[j] / bm.mass_kg;
  }
}

namespace {
// c mod m in [0, m) with one 64-bit division (a step reads the rings four times and writes them
// once: ((c % m) + m) % m and (i + 1) % m took three divisions a read).
std::size_t wrap(long long c, long long m) noexcept {
  const long long i = c % m;
  return static_cast<std::size_t>(i < 0 ? i + m : i);
}
}  // namespace

inline double TwinTurretCut::read(const std::vector<double>& v, double cell) const noexcept {
  const double fl = std::floor(cell);
  const std::size_t i = wrap(static_cast<long long>(fl), static_cast<long long>(ring_cells_));
  const double f = cell - fl;
  return v[i] * (1.0 - f) + v[i + 1 == ring_cells_ ? 0 : i + 1] * f;
}

double TwinTurretCut::surface_over(Edge& e, double cell, double z_lo, double z_hi) noexcept {
  // Tool 1's passes at this material angle, newest first: Z_j = z(cell − j·N), non-increasing
  // in j (tool 1 only advances; where it did not cut, the older pass was carried forward).
  const std::vector<double>& zr = rings_[0].z;
  const std::vector<double>& dr = rings_[0].d;
  const double n_rev = static_cast<double>(cells_per_rev_);
  const long long last = static_cast<long long>(ring_cells_ / cells_per_rev_) - 1;
  auto Z = [&](long long j) { return read(zr, cell - static_cast<double>(j) * n_rev); };
  // The pass that cut z_hi: the oldest j with Z_j ≥ z_hi (then Z_{j+1} < z_hi).
  long long j = std::clamp(e.pass_hint, 0LL, last);
  while (j > 0 && Z(j) < z_hi) --j;
  while (j < last && Z(j + 1) >= z_hi) ++j;
  e.pass_hint = j;
  const double t0_outer = p_.depth_mm[0] * 1e-3;  // the uncut layer above tool 1's surface
  double zj = Z(j);
  if (z_hi <= z_lo) {  // no chip: the surface at the edge
    delay_rev_ = static_cast<double>(j) + 0.5;
    if (zj < z_hi) {
      ++uncut_reads_;
      return t0_outer;
    }
    return read(dr, cell - static_cast<double>(j) * n_rev);
  }
  double sum = 0.0, weight_j = 0.0;
  if (zj < z_hi) {  // only possible at j = 0: tool 2 is ahead of tool 1's last pass
    ++uncut_reads_;
    sum += (z_hi - std::max(zj, z_lo)) * t0_outer;
  }
  for (;; ++j) {
    const bool oldest = j == last;
    const double below = oldest ? z_lo : Z(j + 1);
    if (oldest && zj > z_lo) ++clipped_reads_;
    const double w = std::min(zj, z_hi) - std::max(below, z_lo);
    if (w > 0.0) {
      sum += w * read(dr, cell - static_cast<double>(j) * n_rev);
      weight_j += w * static_cast<double>(j);
    }
    if (oldest || below <= z_lo) break;
    zj = below;
  }
  delay_rev_ = weight_j / (z_hi - z_lo) + 0.5;
  return sum / (z_hi - z_lo);
}

double TwinTurretCut::ploughing(Edge& e, double p, double v) const noexcept {
  // History: p at this step and the ones before it, one sample per step.
  const std::size_t n = e.hist.size();
  e.hist_at = (e.hist_at + n - 1) % n;
  e.hist[e.hist_at] = p;
  if (!(v > 0.0)) return 0.0;
  const ProcessDamping& pd = p_.process_damping;
  const double dx = v * dt_;  // m per step behind the edge
  const double land = pd.wear_land_mm * 1e-3, tan_g = std::tan(pd.clearance_deg * kPi / 180.0);
  const double flank = pd.flank_length_mm * 1e-3;
  // The surface is linear between samples and the flank is linear on each side of the land's
  // end: integrate the positive part of the interference exactly on each linear piece (a
  // sampled trapezoid would lose the land's end, where the clearance face drops by dx·tan γ
  // within one sample, far more than a small vibration's interference).
  auto positive = [](double f0, double f1, double len) {
    if (f0 >= 0.0 && f1 >= 0.0) return 0.5 * (f0 + f1) * len;
    if (f0 <= 0.0 && f1 <= 0.0) return 0.0;
    const double fp = std::max(f0, f1);
    return 0.5 * fp * fp / std::abs(f1 - f0) * len;
  };
  auto clearance = [&](double x) { return x > land ? (x - land) * tan_g : 0.0; };
  double area = 0.0, x0 = 0.0, s0 = p;  // at the edge the surface is where the tool is
  for (std::size_t k = 1; k < n && x0 < flank; ++k) {
    double x1 = static_cast<double>(k) * dx, s1 = e.hist[(e.hist_at + k) % n];
    if (x1 > flank) {  // the flank ends inside this sample
      s1 = s0 + (s1 - s0) * (flank - x0) / (x1 - x0);
      x1 = flank;
    }
    if (x0 < land && x1 > land) {  // split at the land's end
      const double sl = s0 + (s1 - s0) * (land - x0) / (x1 - x0);
      area += positive(p - s0, p - sl, land - x0);
      area += positive(p - sl, p - clearance(x1) - s1, x1 - land);
    } else {
      area += positive(p - clearance(x0) - s0, p - clearance(x1) - s1, x1 - x0);
    }
    x0 = x1;
    s0 = s1;
  }
  const double width = e.b_mm * 1e-3 / sin_kappa_;
  return pd.k_sp_N_per_m3 * width * area;
}

void TwinTurretCut::cut(Edge& e, double theta, double rpm, double z_mm) noexcept {
  const double n_rev = static_cast<double>(cells_per_rev_);
  const double cell = (theta - e.alpha) / (2.0 * kPi) * n_rev;
  // A lag of 0 revolutions reads what was written half a turn ago at this material angle (the
  // other turret's pass): read one cell ahead, past what this tool itself wrote last step.
  auto at = [&](double lag_rev) { return cell - lag_rev * n_rev + (lag_rev == 0.0 ? 1.0 : 0.0); };
  Ring& w = rings_[e.write_ring];
  double z_read = 0.0, d_read = 0.0;
  if (!e.axial && e.d_lag_rev == e.z_lag_rev) {  // both at one position: one index, as read()
    const double pos = at(e.z_lag_rev);
    const double fl = std::floor(pos);
    const std::size_t i = wrap(static_cast<long long>(fl), static_cast<long long>(ring_cells_));
    const std::size_t i1 = i + 1 == ring_cells_ ? 0 : i + 1;
    const double f = pos - fl;
    const auto& d = rings_[e.d_ring].d;
    z_read = w.z[i] * (1.0 - f) + w.z[i1] * f;
    d_read = d[i] * (1.0 - f) + d[i1] * f;
    e.s_mm = z_mm - z_read;
  } else {
    z_read = read(w.z, at(e.z_lag_rev));
    e.s_mm = z_mm - z_read;
    d_read = e.axial ? surface_over(e, cell, std::min(z_read, z_mm), z_mm)
                     : read(rings_[e.d_ring].d, at(e.d_lag_rev));
  }
  const double pen = e.sigma * y_ - e.u;  // the tool's penetration into the part
  e.b_mm = e.t0_mm + (pen + e.d_weight * d_read) * 1e3;
  e.cutting = e.b_mm > 0.0 && e.s_mm > 0.0;
  if (e.cutting) {
    const double v = kPi * p_.part.diameter_m * rpm;  // m/min
    const cutting::Forces f = cut_.forces_pz_py({e.b_mm, e.s_mm, v, 1.0, 1.0});
    e.fc = f.Pz;
    e.fp = f.Py;
    if (p_.chip_law == ChipLaw::Power) {  // F_linear(t0)·(t/t0)^(1−m) = F_linear(t)·(t/t0)^−m
      const double r = e.b_mm / e.t0_mm;
      e.fc *= std::pow(r, -p_.cutting.material.Fc.m);
      e.fp *= std::pow(r, -p_.cutting.material.Fp.m);
    }
  } else {
    e.fc = e.fp = 0.0;
  }
  e.fd = 0.0;
  if (!e.hist.empty()) {
    const double pd = ploughing(e, pen, kPi * p_.part.diameter_m * rpm / 60.0);
    if (e.cutting) e.fd = pd;
  }
  // Write the cells swept since the last step: the new surface where the tool cut; where it did
  // not, the surface it met is carried forward (from the cell it reads its chip from; with a lag
  // of 0 that is this cell, which keeps the other turret's surface).
  const auto m = static_cast<long long>(ring_cells_);
  const auto back = static_cast<long long>(e.z_lag_rev) * static_cast<long long>(cells_per_rev_);
  const auto now = static_cast<long long>(std::floor(cell));
  // A stopped or reversed spindle writes nothing; a jump of more than a revolution is clipped.
  const long long from = std::max(e.last_cell + 1, now - m + 1);
  double* const wd = w.d.data();  // the rings' storage, loaded once (stores do not reload it)
  double* const wz = w.z.data();
  for (long long c = from; c <= now; ++c) {
    const std::size_t i = wrap(c, m);
    if (e.cutting) {
      wd[i] = -pen;
      wz[i] = z_mm;
    } else if (back > 0) {
      const std::size_t q = wrap(c - back, m);
      wd[i] = wd[q];
      wz[i] = wz[q];
    }
  }
  if (now > e.last_cell) e.last_cell = now;
}

[[gnu::flatten]] void TwinTurretCut::step(double theta, double rpm, const double z_mm[2]) noexcept {
  update_modes(z_mm[0]);
  if (seed_pending_ && (z_mm[0] > p_.z_start_mm || z_mm[n_tools_ - 1] > p_.z_start_mm)) {
    seed_pending_ = false;  // the first tool meets the material: the part displaced by then
    q_[0] += p_.initial_disturbance_um * 1e-6;
    y_ += p_.initial_disturbance_um * 1e-6;
  }
  double fy = 0.0;
  for (int i = 0; i < n_tools_; ++i) {
    cut(edges_[i], theta, rpm, z_mm[i]);
    fy -= edges_[i].sigma * (edges_[i].fp + edges_[i].fd);
  }
  y_ = 0.0;
  for (int j = 0; j < p_.modes; ++j) {
    const double q = phi11_[j] * q_[j] + phi12_[j] * qd_[j] + g1_[j] * fy;
    const double qd = phi21_[j] * q_[j] + phi22_[j] * qd_[j] + g2_[j] * fy;
    q_[j] = q;
    qd_[j] = qd;
    y_ += q;
  }
  for (int i = 0; i < n_tools_ && n_tool_modes_ == 0; ++i) edges_[i].u = 0.0;  // rigid tools
  for (int i = 0; i < n_tools_ && n_tool_modes_ > 0; ++i) {  // each tool under its own force,
    Edge& e = edges_[i];                                      // pushed off the part
    const double f = e.fp + e.fd;
    e.u = 0.0;
    for (int j = 0; j < n_tool_modes_; ++j) {
      const double q = tphi11_[j] * e.tq[j] + tphi12_[j] * e.tqd[j] + tg1_[j] * f;
      const double qd = tphi21_[j] * e.tq[j] + tphi22_[j] * e.tqd[j] + tg2_[j] * f;
      e.tq[j] = q;
      e.tqd[j] = qd;
      e.u += q;
    }
    if (!std::isfinite(e.u) || std::abs(e.u) > 0.05) sound_ = false;
  }
  if (!std::isfinite(y_) || std::abs(y_) > 0.05) sound_ = false;
}

double TwinTurretCut::power_W(double rpm) const noexcept {
  const double v = kPi * p_.part.diameter_m * rpm / 60.0;  // m/s
  double p = 0.0;
  for (int i = 0; i < n_tools_; ++i) p += edges_[i].fc * v;
  return p;
}

}  // namespace lathectl::dynamics
