#pragma once
// The per-revolution mean of a recorded signal: at each sample, the mean over the trailing
// window of one spindle revolution at that sample's speed, w = round(60 / max(n, 1 rpm) / Δt)
// samples (at least 1; fewer at the start of the record). A feed drive cannot act within a
// revolution, so this is the force a feed controller answers for. One function for every claim,
// metric and plot that shows it, so that what is plotted is what is claimed.

#include <cstddef>
#include <span>
#include <vector>

namespace lathectl::sim {

// `x` and `rpm` sampled together every `dt_s` seconds (same length).
std::vector<double> per_revolution_mean(std::span<const double> x, std::span<const double> rpm,
                                        double dt_s);

// The same mean sample by sample, as a run records (bit-identical to per_revolution_mean): it
// keeps only the cumulative sums of the longest window (one revolution at 1 rpm), so its memory
// is bounded by dt_s, not by the run's length. dt_s may be given at the second sample (the
// first sample's mean is itself whatever the window).
class PerRevolutionMean {
 public:
  PerRevolutionMean() = default;
  explicit PerRevolutionMean(double dt_s) { set_dt(dt_s); }
  void set_dt(double dt_s);
  [[nodiscard]] bool has_dt() const noexcept { return dt_ > 0.0; }
  // Adds a sample and returns the mean of the trailing revolution ending with it.
  double push(double x, double rpm);

 private:
  std::vector<double> cum_;  // ring: cum_[k % m_] = Σ x[0..k−1], the last m_ of them
  std::size_t m_ = 0;
  double dt_ = 0.0;
  double sum_ = 0.0;
  double first_ = 0.0;
  std::size_t n_ = 0;  // samples pushed
};

}  // namespace lathectl::sim
