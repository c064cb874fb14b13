#pragma once
// The per-revolution mean: at each sample, the mean over the trailing window of one spindle
// revolution at that sample's speed, w = 60 / max(n, n_min) / Δt samples (at least 1): its
// whole samples and the fraction w − ⌊w⌋ of the sample before them, so a once-per-revolution
// swing cancels whatever the record's interval; until a whole revolution has been pushed since
// the last restart, the mean of the samples since it (at most ⌊w⌋). A feed drive cannot act
// within a revolution, so this is the force a feed controller answers for. One class for the controller's regulated force, the
// machine side's overload levels and operation log (AdaptiveMachine), and every claim, metric and
// plot of a run that shows it — so what a machine limits is what a simulation reports.
//
// It keeps the cumulative sums of the longest window (one revolution at n_min) in a ring
// allocated by configure(); push() never allocates. A recorded signal whose interval is known
// only at its second sample may push the first sample before configure() (its mean is itself).

#include <cstddef>
#include <span>
#include <vector>

namespace lathectl::control {

class PerRevolutionMean {
 public:
  PerRevolutionMean() = default;
  explicit PerRevolutionMean(double dt_s, double rpm_min = 1.0) { configure(dt_s, rpm_min); }
  // Allocates the ring for one revolution at rpm_min (> 0) at dt_s (> 0); keeps what was pushed
  // before. Throws std::invalid_argument on a non-positive interval or speed.
  void configure(double dt_s, double rpm_min = 1.0);
  [[nodiscard]] bool configured() const noexcept { return dt_ > 0.0; }
  // Forget the samples so far: the next one starts a new mean (a new cut).
  void restart() noexcept {
    since_restart_ = 0;
    full_ = false;
  }
  // Adds a sample at the spindle speed rpm (sign ignored) and returns the mean of the trailing
  // revolution ending with it.
  double push(double x, double rpm) noexcept;
  [[nodiscard]] double value() const noexcept { return value_; }
  // The sample one revolution before the last one pushed, at speed rpm, interpolated between
  // the two samples around it; NaN while fewer samples than a revolution and two are held.
  [[nodiscard]] double revolution_ago(double rpm) const noexcept;
  [[nodiscard]] std::size_t samples() const noexcept { return since_restart_; }
  // The last mean spans a whole revolution (not fewer samples since the restart).
  [[nodiscard]] bool full() const noexcept { return full_; }

 private:
  std::vector<double> cum_;  // ring: cum_[k % m_] = Σ x[0..k−1]
  std::size_t m_ = 0;
  double dt_ = 0.0;
  double rpm_min_ = 1.0;
  double sum_ = 0.0;
  std::size_t n_ = 0;              // samples pushed in all
  std::size_t since_restart_ = 0;  // of them since restart(), at most m_ − 1
  double value_ = 0.0;
  bool full_ = false;
};

// The peak a run reports of its force: the largest per-revolution mean over its cuts, each cut's
// first revolution left out (the chip is still building and the window still holds air: not a
// cut's mean yet). One rule for `lathectl run`'s metric (force_peak_rev_mean_N) and the LinuxCNC
// plant's pin of the same name, so a simulation and a machine report the same number.
class PerRevolutionPeak {
 public:
  // As PerRevolutionMean::configure (allocates; may be called after the first push).
  void configure(double dt_s, double rpm_min = 1.0) { mean_.configure(dt_s, rpm_min); }
  // A sample at time t_s: x at speed rpm, while cutting (chip depth and feed > 0) or not.
  // Returns the trailing revolution's mean.
  double push(double t_s, double x, double rpm, bool cutting) noexcept;
  [[nodiscard]] double peak() const noexcept { return peak_; }
  [[nodiscard]] double value() const noexcept { return mean_.value(); }
  // The last sample counted toward the peak: in a cut, past the cut's first revolution.
  [[nodiscard]] bool counted() const noexcept { return counted_; }
  // Time since the present (or last) cut began; large before the first.
  [[nodiscard]] double since_contact_s(double t_s) const noexcept { return t_s - contact_t_; }

 private:
  PerRevolutionMean mean_;
  double contact_t_ = -1e9;
  double peak_ = 0.0;
  bool was_cutting_ = false;
  bool counted_ = false;
};

// The same mean over a whole record sampled every dt_s (x and rpm of the same length).
std::vector<double> per_revolution_mean(std::span<const double> x, std::span<const double> rpm,
                                        double dt_s);

// PerRevolutionPeak over a whole record sampled every dt_s: sample i at time t_s[i], x[i] at
// speed rpm[i], in a cut when cutting[i] != 0 (all of the same length). For a host that reports a
// recorded or predicted run's peak (`lathectl optimize`'s prediction and its --verify runs) by
// the rule the rig and the LinuxCNC plant use.
struct PerRevolutionRecord {
  std::vector<double> mean;            // each sample's trailing-revolution mean
  std::vector<unsigned char> counted;  // 1: the sample counts toward the peak
  double peak = 0.0;                   // the largest mean of the samples that count
};
PerRevolutionRecord per_revolution_peak(std::span<const double> t_s, std::span<const double> x,
                                        std::span<const double> rpm,
                                        std::span<const unsigned char> cutting, double dt_s);

}  // namespace lathectl::control
