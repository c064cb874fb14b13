#include "systems/d_gauging/study.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "lathectl/control/types.hpp"
#include "lathectl/core/parallel.hpp"
#include "systems/d_gauging/machine_params.hpp"
#include "lathectl/io/channel_stream.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/study.hpp"
#include "lathectl/io/verdict.hpp"
#include "lathectl/sim/config_error.hpp"
#include "systems/d_gauging/rig.hpp"
#include "systems/d_gauging/settings.hpp"
#include "systems/d_gauging/study_phases.hpp"

namespace lathectl::systems::d_gauging {

namespace detail {

void GaugingStudy::run_controllers() {
  configure_gauge();
  open_result_files();
  calibrate();
  full_part();
  linear_monte_carlo();
  noise_check();
  full_parts_with_noise();
}

void GaugingStudy::configure_gauge() {
  sensors::VibroContactGauge gauge;
  configure_transducer(sc_, gauge);
  A0_ = gauge.free_amplitude_m();
  K_ = gauge.signal_gain_V_per_m();
  if (p_.allowance_m > A0_)
    io::throw_at_key(sc_, sim::ConfigError("process.allowance_um",
                                           fmt(p_.allowance_m * kUm) +
                                               " µm exceeds the largest allowance this transducer "
                                               "can measure, A0 = " +
                                               fmt(A0_ * kUm) + " µm"));
  quiet_ = p_;
  quiet_.noise_variance_m2 = 0.0;
}

// The result files stream into the stage, their disk space checked before any work:
// channels.csv one row a linearised part, channels_compare.csv the full-model part recorded
// (streamed: memory bounded whatever run.duration_s; the plots from its pyramids).
void GaugingStudy::open_result_files() {
  io::OutputStage* stage = io::StreamScope::current();
  parts_csv_ = io::open_channel_stream(
      sc_, stage, "channels.csv",
      {{"part", ""}, {"trip_s", "s"}, {"stop_s", "s"}, {"finished_um", "µm"}},
      static_cast<double>(d_.parts), "monte_carlo.parts", "lower monte_carlo.parts");
  rec_csv_ = io::open_channel_stream(sc_, stage, "channels_compare.csv", rec_.channels(),
                                     sc_.run.duration_s / dt_ / 50.0 + 16.0, "run.duration_s",
                                     "shorten run.duration_s, raise run.step_s");
}

// 1. Calibration: the full model's settled mean signal against x, and the seed's line.
void GaugingStudy::calibrate() {
  const double settle = std::max(0.8, 8.0 * d_.transducer.filter_time_constant_s);
  for (int i = 0; i <= 16; ++i) xs_.push_back(A0_ * (-0.05 + 1.0 * i / 16.0));
  s_full_.resize(xs_.size());
  core::parallel_for(xs_.size(), [&](std::size_t i) {
    s_full_[i] = full_model_mean_signal(d_.transducer, dt_, xs_[i], settle);
  });
  plan_ = plan_threshold(d_, dt_);
  // The steps before size ([sequence]): their thresholds on the plan's line, for every
  // full-model part (the linearised parts model the size step alone).
  try {
    p_.cycle = cycle_for(d_.transducer, d_.sequence, plan_.line, p_, plan_.threshold_V);
  } catch (const std::invalid_argument& e) {
    io::throw_at_key(sc_, sim::ConfigError("sequence.spark_um", e.what()));
  }
  quiet_.cycle = p_.cycle;
  size_step_ = quiet_;
  size_step_.cycle = {};
  seed_line_ = linear_gauge({K_, A0_}, d_.transducer);
  cal_line_ = linear_gauge(plan_.calibrated_line, d_.transducer);
  dyn_line_ = cal_line_;  // moved onto the full model in full_part()
  level_at_trip_ = full_model_signal(d_.transducer, dt_, plan_.x_trip_m, settle);
  // The threshold the machine runs (machine_threshold: lathectl_gauge aims with the same):
  // calibrated with noise, (23) aimed past the first-passage bias; calibrated_dynamic: S_th moved
  // until the full model's part WITHOUT noise finishes at target − the first-passage bias. With
  // noise the calibration was only as precise as its few full-model parts (64 parts: ±0.2 µm),
  // far coarser than the linearised Monte Carlo that judges the mean (20 000 parts: ±0.012 µm),
  // which then missed the target by 16 of its standard errors. Without noise each part is exact:
  // the deterministic part of the full model's error (ripple, the probe's amplitude lag) is
  // calibrated to a tenth of the judging Monte Carlo's standard error, and the noise's part is
  // the bias the linearised model measures precisely.
  const auto th = machine_threshold(d_, p_, plan_, dt_, sc_.run.seed, sc_.run.duration_s,
                                    kept_parts_);
  bias_m_ = th.bias.bias_m;
  bias_se_m_ = th.bias.standard_error_m;
  s_static_ = th.static_V;
  dyn_ = th.dyn;
  s_th_ = th.threshold_V;
  seed_signal_dev_pct_ =
      100.0 * (K_ * (A0_ - plan_.x_trip_m) - level_at_trip_.mean_V) / level_at_trip_.mean_V;
}

// The first-passage bias of (23): the relay trips at the FIRST upward crossing of the noisy
// signal, on average before the mean crossing (23) places, so the part is left large. No closed
// form fits: Rice's crossing rate (Poisson crossings) gives 0.46 µm for d_gauging where the
// Monte Carlo finds 0.02 µm (the level approaches at K·a = 0.40 V/s, 5.5 times the noise's
// σ' = 0.072 V/s, so almost every path crosses once and the bias is the rare early excursion).
// Calibrated instead: the linearised model's mean error over parts of its own (as many as the
// study's, streams apart), made precise by a control variate: ε(t*)/K has mean 0 and follows
// the finished size closely, so mean(e) − c·mean(ε*/K) has a small fraction of mean(e)'s
// scatter. (23) is then aimed at target − bias.
// (machine_threshold, calibration.cpp, computes it.)

// 2. One full-model part without noise against the linear prediction (inside the range).
void GaugingStudy::full_part() {
  rec_.attach(rec_csv_.get());
  full_ = machine_part_full(quiet_, d_.transducer, dt_, s_th_, sc_.run.seed, &rec_, 50,
                            sc_.run.duration_s);
  rec_csv_->finish();
  // The static line's prediction (the claim on the linearisation's trip time).
  trip_lin_ = linear_trip(p_, d_.threshold == "seed" ? seed_line_ : cal_line_, s_th_);
  full_err_um_ = (full_.finished_m - p_.target_m) * kUm;
  // calibrated_dynamic: the threshold is aimed at the full model, so the linearised parts that
  // judge the mean size are machined on the full model's line: the static line's intercept moved
  // so that, without noise, the line finishes where the full model's part did at this threshold
  // (x at the stop = B − S_th/K − a·(lag + t_r), (22)+(23)). The shift is what the static line
  // misses of the moving probe (its amplitude lag, the ripple at the crossing).
  if (dynamic() && !full_.backstop) {
    const double x_lin = cal_line_.intercept_m - s_th_ / cal_line_.gain_V_per_m -
                         p_.removal_m_per_s * (cal_line_.lag_s() + p_.relay_response_s +
                                               p_.interruption.bridge_lag_s(cal_line_.supply_Hz));
    line_shift_m_ = full_.finished_m - x_lin;
    dyn_line_.intercept_m += line_shift_m_;
  }
}

// 4. Linearised Monte Carlo of finished sizes.
// In passes over the parts (LinearParts): the first writes channels.csv (one row a part) and
// sums the sizes, the second their spread about the mean, the third (the report) the histogram.
void GaugingStudy::linear_monte_carlo() {
  parts_ = std::make_unique<LinearParts>(p_, line(), s_th_, d_.parts, sc_.run.seed, kept_parts_);
  smallest_ = full_.finished_m;
  parts_->for_each([&](std::size_t i, const PartResult& r) {
    const std::array<double, 4> row{static_cast<double>(i), r.trip_s, r.stop_s, r.finished_m * kUm};
    parts_csv_->row(row);
    never_ += std::isnan(r.trip_s) ? 1 : 0;
    backstops_ += r.backstop ? 1 : 0;
    if (!std::isfinite(r.finished_m)) return;
    st_.mean += r.finished_m;
    smallest_ = std::min(smallest_, r.finished_m);
    ++n_sizes_;
  });
  parts_csv_->finish();
  if (n_sizes_ < 2)  // only without removal (the backstop ends every cut that has one)
    io::throw_at_key(sc_, sim::ConfigError("process.removal_um_per_s",
                                           "no part finished: nothing ends the cut"));
  st_.mean /= static_cast<double>(n_sizes_);
  each_size([&](double x) { st_.sigma += (x - st_.mean) * (x - st_.mean); });
  st_.sigma = std::sqrt(st_.sigma / static_cast<double>(n_sizes_ - 1));
  // (25) extended to the filter: σ_x = sqrt(D·f), f = 1/(1 + βT_f) for the seed's first order.
  pred_sigma_ = std::sqrt(p_.noise_variance_m2 * line().noise_factor(p_.noise_beta_per_s));
  const double usl = p_.target_m + d_.tolerance_m, lsl = p_.target_m - d_.tolerance_m;
  cp_ = st_.sigma > 0.0 ? (usl - lsl) / (6.0 * st_.sigma) : INFINITY;
  cpk_ = st_.sigma > 0.0 ? std::min(usl - st_.mean, st_.mean - lsl) / (3.0 * st_.sigma) : INFINITY;
  se_ = st_.sigma / std::sqrt(static_cast<double>(n_sizes_));
}

// 5. Seed (25) by Monte Carlo: filter-output noise, 1e5 samples far enough apart.
void GaugingStudy::noise_check() {
  const double spacing = 5.0 * std::max(line().lag_s(), 1.0 / p_.noise_beta_per_s);
  const auto eps = filter_noise_samples(p_, line(), 100000, spacing, sc_.run.seed + 1);
  double v2 = 0.0;
  for (double e : eps) v2 += e * e;
  noise_sigma_ = std::sqrt(v2 / static_cast<double>(eps.size()));
  noise_pred_ = std::sqrt(p_.noise_variance_m2 * line().gain_V_per_m * line().gain_V_per_m *
                          line().noise_factor(p_.noise_beta_per_s));
}

// 6. A few full-model parts with noise, on all cores.
void GaugingStudy::full_parts_with_noise() {
  full_sizes_.assign(d_.full_parts, 0.0);
  std::vector<char> full_backstop(d_.full_parts, 0);
  core::parallel_for(full_sizes_.size(), [&](std::size_t i) {  // part i: its own seed
    const auto r = machine_part_full(p_, d_.transducer, dt_, s_th_, sc_.run.seed * 7919 + i,
                                     nullptr, 50, sc_.run.duration_s);
    full_sizes_[i] = r.finished_m;
    full_backstop[i] = r.backstop ? 1 : 0;
  });
  for (char b : full_backstop) backstops_ += static_cast<std::size_t>(b);
  backstops_ += full_.backstop ? 1 : 0;
  fst_ = full_sizes_.size() > 1 ? stats(full_sizes_) : Stats{};
  for (double v : full_sizes_) smallest_ = std::min(smallest_, v);
}

void GaugingStudy::check_claims(Claims& claims) {
  claims.check(
      "(25): Monte Carlo σ of the filter-output noise / predicted (1e5 samples; within 3 %)",
      noise_sigma_ / noise_pred_, Compare::RatioWithin, 0.03);
  claims.check("σ of finished size / sqrt(D/(1+βT_f))", st_.sigma / pred_sigma_,
               Compare::RatioWithin, 0.05);
  // The mean size is judged on the linearised parts (the one model with enough parts to judge
  // it), machined on the line the threshold was aimed with: the static line (calibrated), or
  // that line moved onto the full model's noiseless part (calibrated_dynamic). Its standard
  // error is that of a difference: this run's mean and the bias calibration's, both estimates.
  // Two of them: an exact calibration lands within one standard error in only 68 % of runs
  // (d_gauging's 10⁵ parts at 1.4), within two in 95 %.
  const bool aimed = calibrated() && p_.noise_variance_m2 > 0.0;
  const double judge_se = aimed ? std::hypot(se_, bias_se_m_) : se_;
  const double off_in_se = (st_.mean - p_.target_m) / judge_se;
  claims.check(
      std::string("threshold (23): linearised parts on the ") +
          (dynamic() ? "full model's line" : d_.threshold == "seed" ? "seed's line"
                                                                    : "full model's static line") +
          ": mean finished size − target, in standard errors" +
          (aimed ? " of it and of the bias calibration" : " σ/√N") + " (|·| ≤ 2)",
      off_in_se, Compare::Within, 2.0);
  if (dynamic())
    claims.note("calibrated_dynamic: the full model's noiseless part finishes " +
                fmt(line_shift_m_ * kUm, "%.3f") +
                " µm away from the static line's (22)+(23) at this threshold; the linearised "
                "parts are machined on the line moved by that much.");
  // Stated tolerance, fixed before looking: a tenth of the part's tolerance half-width.
  const double tol_full_um = 0.1 * d_.tolerance_m * kUm;
  claims.check("inside the range: full-model part (no noise) finished − target [µm] (|·| ≤ " +
                   fmt(tol_full_um) + ", a tenth of the tolerance)",
               full_err_um_, Compare::Within, tol_full_um);
  const double tol_trip_s = tol_full_um * 1e-6 / p_.removal_m_per_s;
  // With a cycle the earlier steps' faster feeds shorten the part: (22)'s time is the size
  // step's alone (the cycle's table shows where each step started).
  if (p_.cycle.before.empty())
    claims.check("inside the range: full-model trip time − linear (22)+(23) [s] (|·| ≤ " +
                   fmt(tol_trip_s) + ": the same tenth in time)",
               full_.trip_s - trip_lin_, Compare::Within, tol_trip_s);
  claims.note("Filter ripple on the signal at the trip point: ±" +
              fmt(level_at_trip_.ripple_V * 1e3) + " mV (±" +
              fmt(level_at_trip_.ripple_V / cal_line_.gain_V_per_m * kUm) +
              " µm of size). The relay trips on its crest, early by up to that; the linearised "
              "model, which "
              "has no ripple, cannot show it, and raising the threshold by it over-corrects (the "
              "probe's own "
              "amplitude lag works the other way). A longer or higher-order filter is the remedy.");
  claims.note("Mean filtered signal at the trip point x = " + fmt(plan_.x_trip_m * kUm) +
              " µm: full model " + fmt(level_at_trip_.mean_V) + " V, the seed's K·(A0 − x) " +
              fmt(K_ * (A0_ - plan_.x_trip_m)) + " V (" + fmt(seed_signal_dev_pct_, "%.2f") +
              " %); the local calibration gives K = " + fmt(cal_line_.gain_V_per_m * 1e-3) +
              " mV/µm (seed: " + fmt(K_ * 1e-3) + "), intercept " +
              fmt(cal_line_.intercept_m * kUm) + " µm (seed: A0 = " + fmt(A0_ * kUm) + ").");
  bias_notes(claims);
  if (full_sizes_.size() >= 30) {  // enough parts for their mean and σ to mean something
    claims.check("full model with noise: mean finished size − target [µm] (|·| ≤ 0.5)",
                 (fst_.mean - p_.target_m) * kUm, Compare::Within, 0.5);
    claims.check(
        "full model with noise: σ of finished size / (25) extended to the filter (within "
        "10 %)",
        fst_.sigma / pred_sigma_, Compare::RatioWithin, 0.10);
  }
  claims.note(std::string("Probe ") + (regular() ? "regular" : "NOT regular") +
              " at the trip point: its position once per drive period spreads over " +
              fmt(plan_.calibrated_line.spread_m * kUm) + " µm (" +
              fmt(100.0 * plan_.calibrated_line.spread_m / A0_, "%.1f") +
              " % of A0; the design rule asks ≤ " + fmt(100.0 * design::kRegularSpread) + " %).");
  if (dynamic())
    claims.note("calibrated_dynamic: " + std::to_string(dyn_.parts) +
                " full-model parts without noise moved S_th from " + fmt(s_static_) + " to " +
                fmt(dyn_.threshold_V) + " V (the last finished " +
                fmt((dyn_.mean_error_m - bias_m_) * kUm, "%.4f") +
                " µm from target, aimed at −" + fmt(bias_m_ * kUm, "%.4f") +
                " µm, the first-passage bias" +
                (dyn_.converged ? ""
                 : dyn_.jump_m != 0.0 && std::abs(dyn_.jump_m) < 0.1 * d_.tolerance_m
                     ? "; the noiseless size jumps by " + fmt(dyn_.jump_m * kUm, "%.4f") +
                           " µm across the aim between two thresholds " +
                           fmt(dyn_.bracket_V * 1e6, "%.3g") + " µV apart: the nearer side"
                     : std::string("; not converged within calibration_parts_max")) +
                ").");
  claims.check(
      "backstop: smallest finished size of every cut − the limit position [µm] (≥ 0: "
      "no part undersize beyond it)",
      (smallest_ - p_.backstop_m) * kUm, Compare::AtLeast, -1e-9);
  if (!plan_.safe())
    claims.note("Forced (gauge.force_threshold): the threshold " + fmt(s_th_) +
                " V lies outside the safe range " + fmt(plan_.range.low_V) + "…" +
                fmt(plan_.range.high_V) +
                " V the full model's signal reaches with its margin (the "
                "probe bounces on a floor of " +
                fmt(plan_.range.floor_V) + " V from x = " + fmt(plan_.range.floor_start_m * kUm) +
                " µm on); the safe range of targets ends at " + fmt(plan_.largest_target_m * kUm) +
                " µm. " + std::to_string(backstops_) + " cuts ended at the backstop " +
                fmt(p_.backstop_m * kUm) + " µm.");
}

// The first-passage bias: calibrated away, or seen.
void GaugingStudy::bias_notes(Claims& claims) const {
  const double bias_in_se = (st_.mean - p_.target_m) / se_;
  if (calibrated() && p_.noise_variance_m2 > 0.0)
    claims.note(
        "First-passage bias: (23) places the mean crossing, the relay trips at the first; "
        "calibrated on " +
        std::to_string(d_.parts) +
        " linearised parts of its own "
        "(control variate ε(t*)): " +
        fmt(bias_m_ * kUm, "%.4f") + " ± " + fmt(bias_se_m_ * kUm, "%.4f") +
        " µm, taken off the target in (23).");
  if (std::abs(bias_in_se) > 1.0 && !calibrated())
    claims.note(
        "The relay trips at the first upward crossing of S_th; with noise the first crossing comes "
        "early on "
        "average, so (23), which places the mean crossing, leaves the part slightly large: a "
        "first-passage "
        "bias of " +
        fmt((st_.mean - p_.target_m) * kUm, "%.4f") + " µm here (" + fmt(bias_in_se, "%.1f") +
        " standard errors of the mean, " +
        fmt(100.0 * (st_.mean - p_.target_m) / st_.sigma, "%.2f") + " % of σ).");
}

void GaugingStudy::summary(json& s) {
  // The one part of the run: ended by its backstop, it raises the gauging cycle's alarm.
  json alarms = json::array();
  if (full_.backstop)
    alarms.push_back(
        {{"time_s", json_number(full_.stop_s)},
         {"code", static_cast<int>(control::Reason::GaugeBackstop)},
         {"reason", std::string(control::reason_name(control::Reason::GaugeBackstop))}});
  s["metrics"] = {
      {"parts", n_sizes_},
      {"parts_never_tripped", never_},
      {"size_mean_error_um", json_number((st_.mean - p_.target_m) * kUm)},
      {"size_sigma_um", json_number(st_.sigma * kUm)},
      {"predicted_sigma_um", json_number(pred_sigma_ * kUm)},
      {"size_mean_standard_error_um", json_number(se_ * kUm)},
      {"cp", json_number(cp_)},
      {"cpk", json_number(cpk_)},
      {"tolerance_um", json_number(d_.tolerance_m * kUm)},
      {"threshold_V", json_number(s_th_)},
      {"threshold_kind", d_.threshold},
      {"free_amplitude_um", json_number(A0_ * kUm)},
      {"signal_gain_mV_per_um", json_number(K_ * 1e-3)},
      {"calibrated_gain_mV_per_um", json_number(cal_line_.gain_V_per_m * 1e-3)},
      {"calibrated_intercept_um", json_number(cal_line_.intercept_m * kUm)},
      {"seed_signal_deviation_at_trip_pct", json_number(seed_signal_dev_pct_)},
      {"signal_ripple_at_trip_V", json_number(level_at_trip_.ripple_V)},
      {"noise_sigma_V", json_number(noise_sigma_)},
      {"noise_sigma_predicted_V", json_number(noise_pred_)},
      {"full_trip_time_s", json_number(full_.trip_s)},
      {"linear_trip_time_s", json_number(trip_lin_)},
      {"full_finished_error_um", json_number(full_err_um_)},
      {"full_mc_parts", full_sizes_.size()},
      {"full_mc_mean_error_um",
       json_number(full_sizes_.empty() ? NAN : (fst_.mean - p_.target_m) * kUm)},
      {"full_mc_sigma_um", json_number(full_sizes_.size() > 1 ? fst_.sigma * kUm : NAN)},
      {"backstop_um", json_number(p_.backstop_m * kUm)},
      {"filter", filter_name(d_.transducer.filter)},
      {"filter_lag_s", json_number(line().lag_s())},
      {"bias_correction_um", json_number(bias_m_ * kUm)},
      {"bias_correction_standard_error_um", json_number(bias_se_m_ * kUm)},
      {"calibration_parts", dyn_.parts},
      {"linear_line_shift_um", json_number(line_shift_m_ * kUm)},
      {"probe_spread_at_trip_um", json_number(plan_.calibrated_line.spread_m * kUm)},
      {"probe_regular", regular()},
      {"backstop_trips", backstops_},
      {"threshold_forced", d_.force_threshold && !plan_.safe()},
      {"safe_threshold_low_V", json_number(plan_.range.low_V)},
      {"safe_threshold_high_V", json_number(plan_.range.high_V)},
      {"signal_floor_V", json_number(plan_.range.floor_V)},
      {"signal_floor_from_um", json_number(plan_.range.floor_start_m * kUm)},
      {"largest_safe_target_um", json_number(plan_.largest_target_m * kUm)},
      {"alarms", alarms}};
  io::Acceptance acceptance(d_.acceptance);
  acceptance.judge("min_cpk", cpk_);
  acceptance.judge("max_mean_error_um", std::abs(st_.mean - p_.target_m) * kUm);
  s["acceptance"] = acceptance.json();
}

void GaugingStudy::report(io::Report& rep) {
  rep.title = "System D — " + sc_.name;
  rep.doc_page = "system-d-gauging.md";
  rep.subtitle = sc_.file + " · vibro-contact in-process gauging, threshold: " + d_.threshold;
  report_metrics(rep);
  size_histogram(rep);
  signal_plots(rep);
}

void GaugingStudy::report_metrics(io::Report& rep) const {
  auto add = [&](const std::string& k, double v, const char* f = "%.4g") {
    rep.metrics.emplace_back(k, fmt(v, f));
  };
  add("parts (linearised Monte Carlo)", static_cast<double>(n_sizes_), "%.0f");
  add("mean finished size − target [µm]", (st_.mean - p_.target_m) * kUm);
  add("σ of finished size [µm]", st_.sigma * kUm);
  add("predicted σ sqrt(D/(1+βT_f)) [µm]", pred_sigma_ * kUm);
  add("Cp", cp_);
  add("Cpk", cpk_);
  add("threshold S_th [V]", s_th_);
  add("safe range of S_th: from [V]", plan_.range.low_V);
  add("safe range of S_th: to [V]", plan_.range.high_V);
  add("signal floor (the probe bounces) [V]", plan_.range.floor_V);
  add("signal floor from x [µm]", plan_.range.floor_start_m * kUm);
  add("safe range of targets ends at [µm]", plan_.largest_target_m * kUm);
  add("backstop (limit position) [µm]", p_.backstop_m * kUm);
  add("cuts ended by the backstop", static_cast<double>(backstops_), "%.0f");
  add("free amplitude A0 = largest allowance [µm]", A0_ * kUm);
  add("signal gain K (seed) [mV/µm]", K_ * 1e-3);
  add("signal gain, calibrated at the trip point [mV/µm]", cal_line_.gain_V_per_m * 1e-3);
  add("filter noise σ, Monte Carlo [mV]", noise_sigma_ * 1e3);
  add("filter noise σ, (25) [mV]", noise_pred_ * 1e3);
  add("full model (no noise): trip [s]", full_.trip_s);
  add("linear (22)+(23): trip [s]", trip_lin_);
  add("full model (no noise): finished − target [µm]", full_err_um_);
  if (!full_sizes_.empty()) {
    add("full-model parts with noise", static_cast<double>(full_sizes_.size()), "%.0f");
    add("full-model parts: mean − target [µm]", (fst_.mean - p_.target_m) * kUm);
    if (full_sizes_.size() > 1) add("full-model parts: σ [µm]", fst_.sigma * kUm);
  }
}

// Histogram of finished sizes with the normal law of the linear theory and the tolerance.
void GaugingStudy::size_histogram(io::Report& rep) {
  const double usl = p_.target_m + d_.tolerance_m, lsl = p_.target_m - d_.tolerance_m;
  const double lo = std::min(st_.mean - 5.0 * st_.sigma, lsl - st_.sigma);
  const double hi = std::max(st_.mean + 5.0 * st_.sigma, usl + st_.sigma);
  const int bins = 80;
  const double w = (hi - lo) / bins;
  std::vector<double> counts(bins, 0.0);
  each_size([&](double v) {
    const int b = static_cast<int>((v - lo) / w);
    if (b >= 0 && b < bins) counts[static_cast<std::size_t>(b)] += 1.0;
  });
  Series hist{
      "finished sizes (" + std::to_string(n_sizes_) + " parts)", {}, {}, "#1f77b4", false, false};
  for (int b = 0; b < bins; ++b) {
    hist.x.push_back((lo + b * w) * kUm);
    hist.y.push_back(counts[static_cast<std::size_t>(b)]);
    hist.x.push_back((lo + (b + 1) * w) * kUm);
    hist.y.push_back(counts[static_cast<std::size_t>(b)]);
  }
  Series normal{"normal, σ = sqrt(D/(1+βT_f)), mean at target", {}, {}, "#d62728", true, false};
  for (int k = 0; k <= 200; ++k) {
    const double x = lo + (hi - lo) * k / 200.0;
    const double z = (x - p_.target_m) / pred_sigma_;
    normal.x.push_back(x * kUm);
    normal.y.push_back(static_cast<double>(n_sizes_) * w /
                       (pred_sigma_ * std::sqrt(2.0 * std::numbers::pi)) * std::exp(-0.5 * z * z));
  }
  Plot h{"Finished sizes: the controlled part x at the end of cut",
         "x [µm]",
         "parts per bin",
         {hist, normal},
         {{p_.target_m * kUm, "target"}, {lsl * kUm, "LSL"}, {usl * kUm, "USL"}}};
  rep.plots.push_back(h);
}

void GaugingStudy::signal_plots(io::Report& rep) const {
  {
    Series full_s{"full model: settled mean S", {}, {}, "#1f77b4", false, true};
    for (std::size_t i = 0; i < xs_.size(); ++i) {
      full_s.x.push_back(xs_[i] * kUm);
      full_s.y.push_back(s_full_[i]);
    }
    Series seed_s{
        "seed (20): K·(A0 − x)", {0.0, A0_ * kUm}, {K_ * A0_, 0.0}, "#d62728", true, false};
    Series cal_s{"calibrated at the trip point",
                 {0.0, A0_ * kUm},
                 {cal_line_.gain_V_per_m * cal_line_.intercept_m,
                  cal_line_.gain_V_per_m * (cal_line_.intercept_m - A0_)},
                 "#2ca02c",
                 true,
                 false};
    rep.plots.push_back(Plot{"Mean filtered signal against the controlled size x",
                             "x [µm]",
                             "S [V]",
                             {full_s, seed_s, cal_s},
                             {{plan_.x_trip_m * kUm, "trip point"}, {A0_ * kUm, "A0"}}});
  }
  {
    const auto along_time = [&](const char* channel, std::string name, std::string color) {
      Series r{std::move(name), {}, {}, std::move(color), false, false};
      rec_.plot_points(channel, r.x, r.y);
      r.pyramid = rec_.plot_pyramid(channel);
      return r;
    };
    Series sig_s = along_time("signal_V", "S(t), full model", "#1f77b4");
    // The recording ends when the part is finished: the constants end there too (not at the run's
    // duration, which left the axis running on past the data).
    const double t_end = rec_.rows() == 0 ? 0.0 : rec_.plot_pyramid("time_s")->x_last();
    Series th{"threshold S_th", {0.0, t_end}, {s_th_, s_th_}, "#555", true, false};
    rep.plots.push_back(Plot{"One part, full model without noise: filtered signal",
                             "time [s]",
                             "S [V]",
                             {sig_s, th},
                             {{full_.trip_s, "relay trips"}, {full_.stop_s, "cut ends"}}});
    Series xx = along_time("x_um", "x(t)", "#8c564b");
    Series tg{"target", {0.0, t_end}, {p_.target_m * kUm, p_.target_m * kUm}, "#555", true, false};
    rep.plots.push_back(Plot{"One part: the controlled size x(t)",
                             "time [s]",
                             "x [µm]",
                             {xx, tg},
                             {{full_.stop_s, "cut ends"}}});
  }
}

void GaugingStudy::finish(io::RunOutput& out) {
  // Streamed into the stage; without one (a library caller) collected in memory.
  out.channels_csv = parts_csv_->take_text();
  out.channels_values = parts_csv_->take_values();
  out.compare_csv = rec_csv_->take_text();
  out.headline = std::to_string(n_sizes_) + " parts: mean error " +
                 fmt((st_.mean - p_.target_m) * kUm, "%.4f") + " µm, σ " +
                 fmt(st_.sigma * kUm, "%.3f") + " µm (predicted " + fmt(pred_sigma_ * kUm, "%.3f") +
                 "), Cpk " + fmt(cpk_, "%.2f") + "; full model " + fmt(full_err_um_, "%.2f") +
                 " µm off";
}

}  // namespace detail

io::RunOutput run(const io::Scenario& sc) {
  return run(sc, LinearParts::kKeptParts);
}

io::RunOutput run(const io::Scenario& sc, std::size_t kept_parts) {
  return detail::GaugingStudy(sc, kept_parts).run();
}

}  // namespace lathectl::systems::d_gauging
