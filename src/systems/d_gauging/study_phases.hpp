#pragma once
// System D's study (study.cpp: the runs, claims, summary and report; study_extra.cpp: the studies
// beside the runs), shared by the two files only.

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "lathectl/io/channel_stream.hpp"
#include "lathectl/io/study.hpp"
#include "lathectl/io/verdict.hpp"
#include "systems/d_gauging/rig.hpp"
#include "systems/d_gauging/settings.hpp"

namespace lathectl::systems::d_gauging::detail {

using io::Claims;
using io::Compare;
using io::fmt;
using io::json_number;
using io::Plot;
using io::Series;
using io::Table;
using nlohmann::json;
inline constexpr double kUm = 1e6;

struct Stats {
  double mean = 0.0, sigma = 0.0;
};
inline Stats stats(const std::vector<double>& v) {
  Stats s;
  for (double x : v) s.mean += x;
  s.mean /= static_cast<double>(v.size());
  for (double x : v) s.sigma += (x - s.mean) * (x - s.mean);
  s.sigma = v.size() > 1 ? std::sqrt(s.sigma / static_cast<double>(v.size() - 1)) : 0.0;
  return s;
}

inline const char* filter_name(sensors::VibroContactGauge::Params::Filter f) {
  using F = sensors::VibroContactGauge::Params::Filter;
  return f == F::SecondOrder ? "second_order" : f == F::Synchronous ? "synchronous" : "first_order";
}

// Trip time of the linear model without noise: S_det(t) = S_th.
inline double linear_trip(const GaugingProcess& p, const LinearGauge& g, double s_th) {
  return (s_th / g.gain_V_per_m - g.intercept_m + p.allowance_m) / p.removal_m_per_s + g.lag_s() +
         p.interruption.bridge_lag_s(g.supply_Hz);
}

// The gauging cycle on parts: the transducer calibrated against the seed's line, one full-model
// part without noise, the linearised Monte Carlo of finished sizes, the filter noise against (25),
// a few full-model parts with noise; beside them, the full model outside the linear range and the
// cause of its error.
class GaugingStudy final : public io::Study {
 public:
  GaugingStudy(const io::Scenario& sc, std::size_t kept_parts)
      : Study(sc),
        d_(sc.get<Settings>()),
        p_(d_.process),
        dt_(sc.run.step_s),
        kept_parts_(kept_parts) {}

 private:
  void run_controllers() override;
  void check_claims(Claims& claims) override;
  void extra_studies(io::RunOutput& out, Claims& claims) override;
  void summary(json& s) override;
  void report(io::Report& rep) override;
  void finish(io::RunOutput& out) override;

  void configure_gauge();
  void open_result_files();
  void calibrate();
  void full_part();
  void linear_monte_carlo();
  void noise_check();
  void full_parts_with_noise();
  void outside_the_range(io::RunOutput& out) const;
  void error_cause(io::RunOutput& out) const;
  void cycle_and_interruption(io::RunOutput& out, Claims& claims) const;
  void bias_notes(Claims& claims) const;
  void report_metrics(io::Report& rep) const;
  void size_histogram(io::Report& rep);
  void signal_plots(io::Report& rep) const;
  // The line the linearised parts are machined on: the seed's, the full model's local static
  // line, or (calibrated_dynamic) that line moved onto the full model's noiseless part.
  [[nodiscard]] const LinearGauge& line() const {
    return d_.threshold == "seed" ? seed_line_ : dynamic() ? dyn_line_ : cal_line_;
  }
  [[nodiscard]] bool dynamic() const { return d_.threshold == "calibrated_dynamic"; }
  [[nodiscard]] bool calibrated() const {
    return d_.threshold == "calibrated" || d_.threshold == "calibrated_dynamic";
  }
  // The probe regular at the trip point (the design rule on its spread).
  [[nodiscard]] bool regular() const {
    return plan_.calibrated_line.spread_m <= design::kRegularSpread * A0_;
  }
  // The finished sizes of the linearised parts (the backstop's included).
  template <class F>
  void each_size(F&& f) {
    parts_->for_each([&](std::size_t, const PartResult& r) {
      if (std::isfinite(r.finished_m)) f(r.finished_m);
    });
  }

  const Settings& d_;
  GaugingProcess p_;  // the scenario's, with the cycle's thresholds (calibrate())
  const double dt_;
  const std::size_t kept_parts_;
  GaugingProcess quiet_;       // the process without noise
  GaugingProcess size_step_;   // that without the cycle's earlier steps (the size step's studies)
  double A0_ = 0.0, K_ = 0.0;  // free amplitude, the seed's signal gain
  std::unique_ptr<io::ChannelStream> parts_csv_, rec_csv_;
  sim::Recorder rec_ = sim::Recorder::streamed({{"time_s", "s"},
                                                {"x_um", "µm"},
                                                {"x_seen_um", "µm"},
                                                {"signal_V", "V"},
                                                {"probe_um", "µm"}});
  // 1. Calibration.
  std::vector<double> xs_, s_full_;  // the full model's settled mean signal against x
  ThresholdPlan plan_;
  LinearGauge seed_line_, cal_line_, dyn_line_;
  double line_shift_m_ = 0.0;  // dyn_line_'s intercept − cal_line_'s
  SignalLevel level_at_trip_;
  double bias_m_ = 0.0, bias_se_m_ = 0.0, s_static_ = 0.0, s_th_ = 0.0;
  DynamicCalibration dyn_;
  double seed_signal_dev_pct_ = 0.0;
  // 2. One full-model part without noise.
  PartResult full_;
  double trip_lin_ = 0.0, full_err_um_ = 0.0;
  // 4. The linearised Monte Carlo.
  std::unique_ptr<LinearParts> parts_;
  std::size_t n_sizes_ = 0, never_ = 0, backstops_ = 0;
  Stats st_;
  double smallest_ = 0.0;  // of every cut's finished size
  double pred_sigma_ = 0.0, cp_ = 0.0, cpk_ = 0.0, se_ = 0.0;
  // 5. The filter noise.
  double noise_sigma_ = 0.0, noise_pred_ = 0.0;
  // 6. Full-model parts with noise.
  std::vector<double> full_sizes_;
  Stats fst_;
};

}  // namespace lathectl::systems::d_gauging::detail
