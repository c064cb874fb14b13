#pragma once
// What system B's study measures on a run of the rig (the steady window of the cut), and the
// linear stability limits of the set-up's delay equation at a cutting position.

#include <limits>
#include <memory>
#include <span>
#include <string>

#include "lathectl/io/channel_stream.hpp"
#include "systems/b_chatter/rig.hpp"

namespace lathectl::systems::b_chatter {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Run;

// What system B's study measures on a run, row by row as the rig records (a RowSink attached to a
// streamed Rig between configure and run). The window, the last 30 % of the cut up to 50 ms
// before its end, is placed by the end of the cut, which only the run finds (the turrets reach
// z_end when the modulated feed gets them there): the few values the window's measures read are
// kept bit for bit in an io::RowSpill (on disk beside channels.csv when the run streams into an
// output set), and read back once at the end — memory does not grow with the cut's length, and
// the numbers are the whole-record ones. The rest (the mean feeds) is accumulated as rows come.
class Measure final : public sim::RowSink {
 public:
  // rig: configured; stage: where the window's rows go (nullptr: memory), spill_block_rows at a
  // time.
  Measure(const Rig& rig, bool twin, io::OutputStage* stage,
          std::size_t spill_block_rows = io::RowSpill::kBlockRows);
  void row(std::span<const double> v) noexcept override;
  // Fills r's measures (after the run; the kept rows are released). The chatter frequency only
  // when the vibration is above the dead zone (else it is noise).
  void result(Run& r, double dead_zone_um);

 private:
  enum : std::size_t { kT, kY, kYh, kPower, kPowerMeasured, kDelay, kOneOut, kDepth, kWidth };
  // The feed marks of the row on the finished surface (Surface below), path-weighted.
  void marks(std::span<const double> v) noexcept;
  // result()'s phases (metrics.cpp).
  [[nodiscard]] std::size_t first_row_at(double t0) const;
  void mean_feeds(Run& r, double start) const noexcept;
  void surface(Run& r) const noexcept;
  void depth_swing(Run& r) const;
  const Rig* rig_;
  bool twin_;
  std::size_t t_, y_, yh_, c1_, c2_, pw_, pwm_, dl_, z1_, z2_, v1_, v2_, rpm_, d1_;
  double nose_mm_ = 0.8;
  bool marks_started_ = false;
  double z_marks_ = 0.0;  // the finishing tool's position at the last row
  double path_ = 0.0, rz_path_ = 0.0, ra_path_ = 0.0, rz_min_ = 0.0, rz_max_ = 0.0;
  std::unique_ptr<io::RowSpill> spill_;
  std::size_t n_ = 0, k0_ = 0;  // rows seen; index of the first row of the cut
  bool k0_seen_ = false;
  double first_[3] = {0.0, 0.0, 0.0}, k0_row_[3] = {0.0, 0.0, 0.0}, last_[3] = {0.0, 0.0, 0.0};
};

// The surface the cut leaves, geometric: the cusps of the nose radius r_ε between successive feed
// marks on the finished surface, Rz = p²/(8·r_ε) for a mark spacing p (the largest cusp's height)
// and Ra ≈ Σ p_i³/(32·r_ε·Σ p_i) for the cusps p_i of one revolution (p²/(32·r_ε) when equal):
//   one tool        p = v/n (its local feed per revolution, v the turret's measured feed rate);
//   depth division  the trailing tool 2 cuts the finished surface: p = v₂/n;
//   feed division   the two tools, half a revolution apart, leave marks at z1 and z2 − s/2 each
//                   revolution, s = (v₁ + v₂)/(2n): cusps d = (z1 − z2 + s/2) mod s and s − d, so
//                   p = s/2 when synchronised and up to s as the offset swings (a tool out of
//                   the cut leaves no mark: p = the other's v/n).
// Path-weighted along the part from the first contact to the end of the cut. The vibration at the
// tool adds its peak-to-valley 2·a on the radius where it lasts (…_with_vibration: the steady
// window's amplitude added to Rz, 2a/π — a sine's Ra — to Ra, an upper bound: not a measured
// profile).
struct Surface {
  double length_mm = 0.0;  // the finished length measured
  double Rz_mean_um = kNaN, Rz_min_um = kNaN, Rz_max_um = kNaN, Ra_mean_um = kNaN;
  double Rz_programmed_um = kNaN, Ra_programmed_um = kNaN;  // at the programmed feed, no offset
};

// What one run of the rig answers, measured over the last 30 % of the cut (the steady state).
struct Run {
  Rig rig;
  std::string label;
  std::unique_ptr<Measure> measure;        // fed as the rig records
  std::unique_ptr<io::ChannelStream> csv;  // channels.csv / channels_compare.csv (or none)
  double vibration_um = 0.0;         // chatter band: peak |y_highpass|
  double forced_um = 0.0;            // below the band: half the swing of y − y_highpass
  double static_um = 0.0;            // mean y: the bending by unbalanced radial forces
  double chatter_Hz = kNaN;          // zero crossings of y_highpass
  double feed_mean[2] = {0.0, 0.0};  // per turret over the cut [mm/min]
  double cut_power_W = 0.0, cut_power_measured_W = 0.0;
  double one_out_share = 0.0;  // share of the window with one turret out of the cut
  // Depth division: the revolutions (+½) back of tool 1's pass tool 2 met, over the window.
  double delay_min_rev = kNaN, delay_max_rev = kNaN;
  double t0 = 0.0, t1 = 0.0;   // the window
  double t_end = 0.0;          // the last recorded row's time
  Surface surface;
  // The depth tool 1 (the right turret) cuts, over the rows where it cuts: half its swing (max −
  // min) in the first and the last fifth of those rows, their ratio (> 1: the vibration grows,
  // chatter; < 1: it dies out), and the frequency of its crossings about the last fifth's mean
  // (hysteresis ±20 % of that swing). NaN with fewer than 50 cutting rows.
  double swing_first_um = kNaN, swing_last_um = kNaN, swing_growth = kNaN, swing_Hz = kNaN;
};

// The linear limits of the loops at a cutting position, as chip per revolution at the program's
// speed: one tool (τ, +μ) and twin turrets in feed division (τ/2, −μ, gains added).
struct Limits {
  double single_feed = kNaN, twin_feed = kNaN, chatter_Hz = kNaN;
};
Limits linear_limits(const RigConfig& b, double x_mm, double rpm, int points = 20000);

}  // namespace lathectl::systems::b_chatter
