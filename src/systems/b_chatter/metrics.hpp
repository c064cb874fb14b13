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
  enum : std::size_t { kT, kY, kYh, kPower, kPowerMeasured, kDelay, kOneOut, kWidth };
  const Rig* rig_;
  bool twin_;
  std::size_t t_, y_, yh_, c1_, c2_, pw_, pwm_, dl_, z1_, z2_;
  std::unique_ptr<io::RowSpill> spill_;
  std::size_t n_ = 0, k0_ = 0;  // rows seen; index of the first row of the cut
  bool k0_seen_ = false;
  double first_[3] = {0.0, 0.0, 0.0}, k0_row_[3] = {0.0, 0.0, 0.0}, last_[3] = {0.0, 0.0, 0.0};
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
};

// The linear limits of the loops at a cutting position, as chip per revolution at the program's
// speed: one tool (τ, +μ) and twin turrets in feed division (τ/2, −μ, gains added).
struct Limits {
  double single_feed = kNaN, twin_feed = kNaN, chatter_Hz = kNaN;
};
Limits linear_limits(const RigConfig& b, double x_mm, double rpm, int points = 20000);

}  // namespace lathectl::systems::b_chatter
