#pragma once
// Metrics that answer system A's claims, computed from a run's recorded rows.
// Definitions (also in the README):
//   t_d        time the tool reaches the first disturbance (depth step or hardness change)
//   S_ref      mean feed rate over the second before t_d (the feed the disturbance disturbs)
//   feed_rate_deviation_pct         max |S(t) − S_ref| / S_ref after t_d, S the feed averaged
//                                   over the scenario's feed window (pulse ripple removed)
//   feed_rate_steady_deviation_pct  |mean S over the last 10 % of the run − S_ref| / S_ref
//   force_settling_time_s           from t_d until the per-revolution mean force stays within
//                                   5 % of the set force (NaN when it never does)
//   feed_drift_pct                  mean S over the last 5 % of the run against 5–10 %

#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "lathectl/sim/metrics.hpp"
#include "lathectl/sim/recorder.hpp"
#include "systems/a_pulse_feed/rig.hpp"

namespace lathectl::systems::a_pulse_feed {

struct Metrics {
  double feed_rate_programmed_mm_per_min = 0.0;
  double feed_rate_mean_mm_per_min = 0.0;
  double feed_rate_reference_mm_per_min = 0.0;
  double feed_rate_deviation_pct = 0.0;
  double feed_rate_steady_deviation_pct = 0.0;
  double feed_drift_pct = 0.0;
  double force_nominal_N = 0.0;
  double force_peak_N = 0.0;
  double force_setpoint_N = std::numeric_limits<double>::quiet_NaN();
  double force_settling_time_s = std::numeric_limits<double>::quiet_NaN();
  double force_final_error_pct = std::numeric_limits<double>::quiet_NaN();
  double first_disturbance_s = std::numeric_limits<double>::quiet_NaN();
  double flow_mean_cm3_per_min = 0.0;
  double flow_formula_cm3_per_min =
      std::numeric_limits<double>::quiet_NaN();  // seed (1), fixed h,f
  double flow_formula_error_pct = std::numeric_limits<double>::quiet_NaN();
  // Size: the radial force bends the tool holder by δ = Py/k_holder and moves the
  // tool off the work, so the diameter grows by 2δ. Feed-window means of Py; reference: the
  // second before t_d (as the feed's). NaN without a disturbance.
  double deflection_reference_um = std::numeric_limits<double>::quiet_NaN();
  double deflection_end_um = std::numeric_limits<double>::quiet_NaN();   // last 10 % of the run
  double size_error_diameter_um = std::numeric_limits<double>::quiet_NaN();       // 2·(end − ref)
  double size_error_peak_diameter_um = std::numeric_limits<double>::quiet_NaN();  // max 2·|δ−ref|
  // The tool (roughing's reason to be): how long its per-revolution mean load stood above the set
  // force's 5 % band, and its wear as tool life used (Rig::tool_life_used): over the run, and per
  // metre of feed travel from the first disturbance on (NaN without a tool-life law in the
  // material library or without a disturbance).
  double force_over_band_s = std::numeric_limits<double>::quiet_NaN();
  double tool_life_used_pct = std::numeric_limits<double>::quiet_NaN();
  double tool_life_per_m_after_disturbance_pct = std::numeric_limits<double>::quiet_NaN();
  std::vector<sim::AlarmEvent> alarms;
  double first_alarm_delay_s = std::numeric_limits<double>::quiet_NaN();  // after the first fault
  // Oil balance (Rig::volume_balance): travel not explained by the net inflow, and oil the
  // model made or lost, both as % of the delivered volume.
  double volume_balance_pct = 0.0;
  double volume_conservation_error_pct = 0.0;
};

// From a finished rig with columns (its rows replayed through MetricsAccumulator).
Metrics compute_metrics(const Rig& rig);

// The same metrics row by row as the rig records (a RowSink attached to a streamed Rig between
// configure and run): the windows relative to the run's end are known before it starts (the last
// row's time, Rig::last_record_time), the second before t_d is kept in a ring of rows, the
// largest deviation from a mean known only at the end by the extremes (|x − ref| is largest at
// the largest or the smallest x). Memory is bounded by the record interval, not the duration.
class MetricsAccumulator final : public sim::RowSink {
 public:
  // rig: configured; last_t: the time of the last row it will record (Rig::last_record_time()
  // for run()).
  MetricsAccumulator(const Rig& rig, double last_t);
  void row(std::span<const double> v) noexcept override;
  [[nodiscard]] Metrics result(const Rig& rig) const;
  // The regulator flow averaged over the feed window (NaN over the first, partial window),
  // decimated for the report's plot.
  [[nodiscard]] const sim::PlotPyramid& flow_smoothed_plot() const noexcept { return flow_plot_; }
  // Without the plot (it grows as the run goes): what a plant in a real-time thread attaches
  // (lathectl_slide_plant), whose row() then allocates only at an alarm's onset.
  void set_plot(bool plot) noexcept { plot_ = plot; }
  [[nodiscard]] double first_time() const noexcept { return t_first_; }
  [[nodiscard]] double last_time() const noexcept { return t_last_; }

 private:
  struct Past {
    double t, feed, force;
  };
  void start_windows(double dt_rec);
  void windows(double dt_rec, std::size_t& w, std::size_t& rev, std::size_t& w_flow) const noexcept;
  void on_disturbance(double t_settle);
  void late_row(double t, double feed, double force, double f_rev, double py, std::size_t i);
  const Rig* rig_;
  std::size_t t_, feed_, force_, flow_, alarm_, reason_;
  bool roughing_;
  double T_, t_settle_, set_, k_um_, feed_window_s_, rpm_;
  sim::MeanBetween feed_all_, feed_end90_, feed_end95_, feed_early_, force_end90_, flow_all_,
      f_rev_end90_;
  double force_peak_ = 0.0;
  double feed_max_ = -std::numeric_limits<double>::infinity();
  double feed_min_ = std::numeric_limits<double>::infinity();
  bool any_late_ = false;  // a row at t ≥ t_settle
  bool plot_ = true;
  // t_d and what hangs on it
  double td_ = -1.0, ref_ = 0.0, d_ref_ = 0.0, dev_ = 0.0, peak_ = 0.0, last_out_ = 0.0;
  bool td_seen_ = false;
  std::vector<Past> past_;  // ring: the rows of the last second
  std::size_t past_n_ = 0;
  // moving averages (windows from the first two rows' times)
  std::size_t w_ = 1, rev_ = 1, w_flow_ = 1;
  sim::MovingAverage py_, f_rev_, flow_avg_;
  sim::PlotPyramid flow_plot_;
  sim::AlarmOnsets onsets_;
  std::size_t n_ = 0;
  double row0_force_ = 0.0, row0_flow_ = 0.0, t_first_ = 0.0, t_last_ = 0.0;
  double over_band_s_ = 0.0;  // roughing: time the per-revolution force stood above set + 5 %
};

// The regulator's flow averaged over whole pulses, for the report's plot, row by row: between the
// opening of one pulse and the opening of the pulse N periods later, N the whole number of periods
// nearest the feed window at the recorded frequency. A window that does not start and end between
// pulses catches a varying part of a pulse (a 2 ms sample of an 8 ms pulse is 1/250 of a 500 ms
// window but 1/4 of the pulse volume): with FIM's moving frequency a fixed window's mean jumps
// like a square wave. A sample gets the mean that ended at the last opening before it (NaN until
// N pulses have been seen). Where the flow never stops (fewer than two openings: the continuous
// throttle) the caller plots the trailing mean over the window instead (plot() returns null).
// Memory: the last kMaxPeriods openings (a window of up to 4096 pulses), whatever the duration.
class PulseMeanFlowPlot final : public sim::RowSink {
 public:
  static constexpr std::size_t kMaxPeriods = 4096;
  PulseMeanFlowPlot(const sim::Recorder& rec, double window_s);
  void row(std::span<const double> v) noexcept override;
  // The plot's finished pyramid; null when the flow had fewer than two openings.
  [[nodiscard]] std::shared_ptr<const sim::PlotPyramid> plot() const;

 private:
  std::size_t t_, flow_, freq_;
  double window_s_;
  double sum_ = 0.0, prev_flow_ = 0.0, value_;
  std::size_t n_ = 0, opens_seen_ = 0;
  std::vector<std::pair<std::size_t, double>> opens_;  // ring: (sample index, sum before it)
  sim::PlotPyramid plot_;
};

// Simulated mean flow of a pulsed regulator at slot h and frequency f for each pulse width,
// over `periods` periods (the first discarded). Validates (1) and shows switching effects.
std::vector<double> regulator_characteristic(const hydraulics::PulseRegulator::Params& p,
                                             double slot_m, double frequency_Hz,
                                             const std::vector<double>& pulse_widths_s,
                                             int periods = 40);

// Measured by bisection on the simulated regulator: the largest duty that gives no flow (dead
// zone) and the smallest duty at which the spool no longer gets back to its closed position
// between pulses (from there on the flow bends toward the continuous-opening value).
struct SwitchingLimits {
  double dead_zone_duty = 0.0;
  double saturation_duty = 1.0;
};
SwitchingLimits regulator_switching_limits(const hydraulics::PulseRegulator::Params& p,
                                           double slot_m, double frequency_Hz);

}  // namespace lathectl::systems::a_pulse_feed
