#include "systems/b_chatter/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include "lathectl/dynamics/beam.hpp"
#include "lathectl/dynamics/delayed_coupling.hpp"

namespace lathectl::systems::b_chatter {
namespace {

// The frequency of a signal's crossings of ±h (hysteresis): each change of side past ±h is a
// crossing, and (crossings − 1) half periods lie between the first and the last.
class Crossings {
 public:
  explicit Crossings(double h) : h_(h) {}
  void operator()(double t, double v) noexcept {
    const int s = v > h_ ? 1 : (v < -h_ ? -1 : 0);
    if (s != 0 && s != sign_) {
      if (sign_ != 0) {
        ++crossings_;
        if (std::isnan(tc0_)) tc0_ = t;
        tc1_ = t;
      }
      sign_ = s;
    }
  }
  [[nodiscard]] int count() const noexcept { return crossings_; }
  [[nodiscard]] double frequency_Hz() const noexcept {
    return (crossings_ - 1) / (2.0 * (tc1_ - tc0_));
  }

 private:
  double h_;
  int sign_ = 0, crossings_ = 0;
  double tc0_ = kNaN, tc1_ = kNaN;
};

}  // namespace

Measure::Measure(const Rig& rig, bool twin, io::OutputStage* stage, std::size_t spill_block_rows)
    : rig_(&rig), twin_(twin) {
  const std::pair<std::size_t*, const char*> read[] = {{&t_, "time_s"},
                                                       {&y_, "y_um"},
                                                       {&yh_, "y_highpass_um"},
                                                       {&c1_, "chip1_mm"},
                                                       {&c2_, "chip2_mm"},
                                                       {&pw_, "cut_power_W"},
                                                       {&pwm_, "cut_power_measured_W"},
                                                       {&dl_, "inter_tool_delay_rev"},
                                                       {&z1_, "z1_mm"},
                                                       {&z2_, "z2_mm"},
                                                       {&v1_, "feed1_mm_per_min"},
                                                       {&v2_, "feed2_mm_per_min"},
                                                       {&rpm_, "spindle_rpm"},
                                                       {&d1_, "depth1_mm"}};
  for (const auto& [index, name] : read) *index = rig.recorder().index(name);
  nose_mm_ = rig.config().cutting.nose_radius_mm;
  spill_ = std::make_unique<io::RowSpill>(stage, "the steady window's rows", kWidth,
                                          rig.max_record_rows(), spill_block_rows);
}

void Measure::row(std::span<const double> v) noexcept {
  const double tz[3] = {v[t_], v[z1_], v[z2_]};
  if (n_ == 0) std::copy_n(tz, 3, first_);
  std::copy_n(tz, 3, last_);
  // The cut's start is set (by the step that records this row at the latest) before its rows.
  const double start = rig_->cut_start_s();
  if (!k0_seen_ && start >= 0.0 && v[t_] >= start) {
    k0_seen_ = true;
    k0_ = n_;
    std::copy_n(tz, 3, k0_row_);
  }
  ++n_;
  marks(v);
  const bool one_out = twin_ && ((v[c1_] == 0.0) != (v[c2_] == 0.0));
  const double w[kWidth] = {v[t_],  v[y_],  v[yh_], v[pw_], v[pwm_], v[dl_], one_out ? 1.0 : 0.0,
                            v[d1_]};
  spill_->push(w);
}

void Measure::marks(std::span<const double> v) noexcept {
  const double start = rig_->cut_start_s();
  const double n = v[rpm_];
  const bool cut1 = v[c1_] > 0.0, cut2 = twin_ && v[c2_] > 0.0;
  if (start < 0.0 || v[t_] < start || !(n > 0.0) || !(cut1 || cut2)) return;
  const TwinSetup setup = rig_->config().setup;
  // The finishing tool's position (the path the surface is measured along), and the cusps.
  double z = v[z1_], p = 0.0, ra = 0.0;
  if (setup == TwinSetup::FeedDivision && cut1 && cut2) {
    const double s = 0.5 * (v[v1_] + v[v2_]) / n;
    if (!(s > 0.0)) return;
    const double d = std::fmod(std::fmod(v[z1_] - v[z2_] + 0.5 * s, s) + s, s);
    p = std::max(d, s - d);
    ra = (d * d * d + (s - d) * (s - d) * (s - d)) / (32.0 * nose_mm_ * s);
  } else {
    const bool second = setup == TwinSetup::DepthDivision ? cut2 : !cut1;
    if (setup == TwinSetup::DepthDivision && !cut2) return;  // tool 2 leaves the surface
    z = second ? v[z2_] : v[z1_];
    p = (second ? v[v2_] : v[v1_]) / n;
    ra = p * p / (32.0 * nose_mm_);
  }
  if (!marks_started_) {
    marks_started_ = true;
    z_marks_ = z;
    rz_min_ = rz_max_ = p * p / (8.0 * nose_mm_);
    return;
  }
  const double ds = std::abs(z - z_marks_);
  z_marks_ = z;
  const double rz = p * p / (8.0 * nose_mm_);
  path_ += ds;
  rz_path_ += rz * ds;
  ra_path_ += ra * ds;
  rz_min_ = std::min(rz_min_, rz);
  rz_max_ = std::max(rz_max_, rz);
}

// result() in phases: the window's first row, the window's statistics (in result()), the mean
// feeds over the cut, the surface.

// The first spilled row at t ≥ t0 (time grows row by row).
std::size_t Measure::first_row_at(double t0) const {
  const io::RowSpill& sp = *spill_;
  const std::size_t rows = sp.rows();
  double one[kWidth];
  const auto time_of = [&](std::size_t i) {
    sp.read(i, one);
    return one[kT];
  };
  std::size_t lo_i = 0, hi_i = rows;
  while (lo_i < hi_i) {
    const std::size_t mid = lo_i + (hi_i - lo_i) / 2;
    if (time_of(mid) < t0)
      lo_i = mid + 1;
    else
      hi_i = mid;
  }
  return lo_i;
}

// The mean feeds over the cut: from its first row (every row when it never started) to the
// last.
void Measure::mean_feeds(Run& r, double start) const noexcept {
  const bool from_first = start < 0.0 || !k0_seen_;
  const double* k0 = from_first ? first_ : k0_row_;
  const std::size_t k0_index = from_first ? (start < 0.0 ? 0 : n_) : k0_;
  if (k0_index + 1 < n_) {
    const double dt = last_[0] - k0[0];
    r.feed_mean[0] = (last_[1] - k0[1]) / dt * 60.0;
    r.feed_mean[1] = (last_[2] - k0[2]) / dt * 60.0;
  }
}

// The surface the programmed feed leaves and the one the marks measured along the path.
void Measure::surface(Run& r) const noexcept {
  Surface& sf = r.surface;
  const auto& cfg = rig_->config();
  const double s_p =
      cfg.setup == TwinSetup::FeedDivision ? 0.5 * cfg.feed_mm_per_rev : cfg.feed_mm_per_rev;
  sf.Rz_programmed_um = s_p * s_p / (8.0 * nose_mm_) * 1e3;
  sf.Ra_programmed_um = s_p * s_p / (32.0 * nose_mm_) * 1e3;
  sf.length_mm = path_;
  if (path_ > 0.0) {
    sf.Rz_mean_um = rz_path_ / path_ * 1e3;
    sf.Ra_mean_um = ra_path_ / path_ * 1e3;
    sf.Rz_min_um = rz_min_ * 1e3;
    sf.Rz_max_um = rz_max_ * 1e3;
  }
}

void Measure::result(Run& r, double dead_zone_um) {
  const double start = rig_->cut_start_s(), end = n_ == 0 ? 0.0 : last_[0];
  r.t_end = end;
  r.t0 = start + 0.7 * (end - start);
  r.t1 = end - 0.05;
  // The window's rows: the first at t ≥ t0 up to the last at t ≤ t1.
  const io::RowSpill& sp = *spill_;
  const std::size_t first = first_row_at(r.t0);
  // Hands the window's rows to f in order; returns the index past the last.
  std::vector<double> block(1024 * kWidth);
  const auto window = [&](auto&& f) {
    std::size_t i = first;
    for (;;) {
      const std::size_t n = sp.read(i, block);
      if (n == 0) return i;
      for (std::size_t k = 0; k < n; ++k, ++i) {
        const double* w = block.data() + k * kWidth;
        if (w[kT] > r.t1) return i;
        f(w);
      }
    }
  };
  double lo = 1e300, hi = -1e300, p = 0.0, pm = 0.0, n = 0.0, out = 0.0, ys = 0.0;
  window([&](const double* w) {
    const double y = w[kY], yh = w[kYh], dl = w[kDelay];
    r.vibration_um = std::max(r.vibration_um, std::abs(yh));
    lo = std::min(lo, y - yh);
    hi = std::max(hi, y - yh);
    p += w[kPower];
    pm += w[kPowerMeasured];
    ys += y;
    n += 1.0;
    if (w[kOneOut] != 0.0) out += 1.0;
    if (dl > 0.0) {
      r.delay_min_rev = std::isnan(r.delay_min_rev) ? dl : std::min(r.delay_min_rev, dl);
      r.delay_max_rev = std::isnan(r.delay_max_rev) ? dl : std::max(r.delay_max_rev, dl);
    }
  });
  if (n > 0.0) {
    r.forced_um = 0.5 * (hi - lo);
    r.static_um = ys / n;
    r.cut_power_W = p / n;
    r.cut_power_measured_W = pm / n;
    r.one_out_share = out / n;
    // Chatter frequency: crossings of ±20 % of the amplitude (hysteresis), over the window.
    Crossings crossings(0.2 * r.vibration_um);
    window([&](const double* w) { crossings(w[kT], w[kYh]); });
    if (crossings.count() > 4 && r.vibration_um > dead_zone_um)
      r.chatter_Hz = crossings.frequency_Hz();
  }
  mean_feeds(r, start);
  surface(r);
  depth_swing(r);
  spill_.reset();
}

// The depth's swing while tool 1 cuts (Run::swing_*): the rows it cuts counted, then the first
// and the last fifth of them read (each a pass over the kept rows).
void Measure::depth_swing(Run& r) const {
  const io::RowSpill& sp = *spill_;
  std::vector<double> block(1024 * kWidth);
  const auto rows = [&](auto&& f) {  // every kept row where tool 1 cuts, with its index
    std::size_t k = 0;
    for (std::size_t i = 0;;) {
      const std::size_t n = sp.read(i, block);
      if (n == 0) return k;
      for (std::size_t j = 0; j < n; ++j, ++i)
        if (const double* w = block.data() + j * kWidth; w[kDepth] > 0.0) f(k++, w);
    }
  };
  const std::size_t cutting = rows([](std::size_t, const double*) {});
  if (cutting < 50) return;
  const std::size_t fifth = cutting / 5, late = cutting - fifth;
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300}, sum = 0.0;
  rows([&](std::size_t k, const double* w) {
    const int part = k < fifth ? 0 : (k >= late ? 1 : -1);
    if (part < 0) return;
    lo[part] = std::min(lo[part], w[kDepth]);
    hi[part] = std::max(hi[part], w[kDepth]);
    if (part == 1) sum += w[kDepth];
  });
  r.swing_first_um = 0.5 * (hi[0] - lo[0]) * 1e3;
  r.swing_last_um = 0.5 * (hi[1] - lo[1]) * 1e3;
  r.swing_growth = r.swing_last_um / r.swing_first_um;
  const double mean = sum / static_cast<double>(fifth);
  Crossings crossings(0.2 * 0.5 * (hi[1] - lo[1]));
  rows([&](std::size_t k, const double* w) {
    if (k >= late) crossings(w[kT], w[kDepth] - mean);
  });
  if (crossings.count() > 4) r.swing_Hz = crossings.frequency_Hz();
}

Limits linear_limits(const RigConfig& b, double x_mm, double rpm, int points) {
  const auto modes = dynamics::beam_modes_at(b.part, x_mm * 1e-3, b.modes);
  double f_max = 0.0;
  for (const auto& m : modes) f_max = std::max(f_max, m.natural_frequency_Hz);
  const double tau = 60.0 / rpm;
  const auto& fp = b.cutting.material.Fp;
  const double sk = std::sin(b.cutting.approach_angle_deg * std::numbers::pi / 180.0);
  // dF_p/dt per tool at chip s: k_p/sin κ·(s·sin κ)^(1−m) [N/mm] → per metre.
  auto chip_for_gain = [&](double g) {
    return std::pow(g / (fp.k11_N_per_mm2 * 1e3 / sk), 1.0 / (1.0 - fp.m)) / sk;
  };
  Limits l;
  // The overlap μ is the coupling c of the delayed term; the gain is each tool's dF_p/db.
  const auto one = dynamics::critical_gain(modes, tau, b.overlap, 5.0, 2.5 * f_max, points);
  l.single_feed = chip_for_gain(one.gain_N_per_m);
  l.chatter_Hz = one.chatter_Hz;
  if (b.setup == dynamics::TwinSetup::FeedDivision) {
    const auto two =
        dynamics::critical_gain(modes, 0.5 * tau, -b.overlap, 5.0, 2.5 * f_max, points);
    l.twin_feed = 2.0 * chip_for_gain(0.5 * two.gain_N_per_m);
    l.chatter_Hz = two.chatter_Hz;
  }
  return l;
}

}  // namespace lathectl::systems::b_chatter
