#include "systems/d_gauging/study.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "lathectl/control/types.hpp"
#include "lathectl/io/channel_stream.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/study.hpp"
#include "lathectl/io/verdict.hpp"
#include "lathectl/sim/config_error.hpp"
#include "lathectl/sim/parallel.hpp"
#include "systems/d_gauging/gauging.hpp"
#include "systems/d_gauging/settings.hpp"

namespace lathectl::d_gauging {

namespace {
using io::Claims;
using io::Compare;
using io::fmt;
using io::json_number;
using io::Plot;
using io::Series;
using io::Table;
using nlohmann::json;
constexpr double kUm = 1e6;

struct Stats {
  double mean = 0.0, sigma = 0.0;
};
Stats stats(const std::vector<double>& v) {
  Stats s;
  for (double x : v) s.mean += x;
  s.mean /= static_cast<double>(v.size());
  for (double x : v) s.sigma += (x - s.mean) * (x - s.mean);
  s.sigma = v.size() > 1 ? std::sqrt(s.sigma / static_cast<double>(v.size() - 1)) : 0.0;
  return s;
}

const char* filter_name(sensors::VibroContactGauge::Params::Filter f) {
  using F = sensors::VibroContactGauge::Params::Filter;
  return f == F::SecondOrder ? "second_order" : f == F::Synchronous ? "synchronous" : "first_order";
}

// Trip time of the linear model without noise: S_det(t) = S_th.
double linear_trip(const sim::GaugingProcess& p, const sim::LinearGauge& g, double s_th) {
  return (s_th / g.gain_V_per_m - g.intercept_m + p.allowance_m) / p.removal_m_per_s + g.lag_s();
}
}  // namespace

io::RunOutput run(const io::Scenario& sc) { return run(sc, sim::LinearParts::kKeptParts); }

io::RunOutput run(const io::Scenario& sc, std::size_t kept_parts) {
  const auto& d = sc.get<Settings>();
  const double dt = sc.run.step_s;
  sensors::VibroContactGauge gauge;
  try {
    gauge.configure(d.transducer, dt);
  } catch (const std::invalid_argument& e) {
    io::throw_at_key(sc, e, "transducer");
  }
  const double A0 = gauge.free_amplitude_m(), K = gauge.signal_gain_V_per_m();
  const auto& p = d.process;
  if (p.allowance_m > A0)
    io::throw_at_key(sc, sim::ConfigError("process.allowance_um",
                                          fmt(p.allowance_m * kUm) +
                                              " µm exceeds the largest allowance this transducer "
                                              "can measure, A0 = " +
                                              fmt(A0 * kUm) + " µm"));
  const double settle = std::max(0.8, 8.0 * d.transducer.filter_time_constant_s);
  // The result files stream into the stage, their disk space checked before any work:
  // channels.csv one row a linearised part, channels_compare.csv the full-model part recorded
  // (streamed: memory bounded whatever run.duration_s; the plots from its pyramids).
  io::OutputStage* stage = io::StreamScope::current();
  const auto parts_csv = io::open_channel_stream(
      sc, stage, "channels.csv",
      {{"part", ""}, {"trip_s", "s"}, {"stop_s", "s"}, {"finished_um", "µm"}},
      static_cast<double>(d.parts), "monte_carlo.parts", "lower monte_carlo.parts");
  sim::Recorder rec = sim::Recorder::streamed(
      {{"time_s", "s"}, {"x_um", "µm"}, {"x_seen_um", "µm"}, {"signal_V", "V"}, {"probe_um", "µm"}});
  const auto rec_csv = io::open_channel_stream(
      sc, stage, "channels_compare.csv", rec.channels(), sc.run.duration_s / dt / 50.0 + 16.0,
      "run.duration_s", "shorten run.duration_s, raise run.step_s");

  // 1. Calibration: the full model's settled mean signal against x, and the seed's line.
  std::vector<double> xs, s_full;
  for (int i = 0; i <= 16; ++i) xs.push_back(A0 * (-0.05 + 1.0 * i / 16.0));
  std::vector<double> sig(xs.size());
  sim::parallel_for(xs.size(), [&](std::size_t i) {
    sig[i] = sim::full_model_mean_signal(d.transducer, dt, xs[i], settle);
  });
  s_full = sig;
  const ThresholdPlan plan = plan_threshold(d, dt);
  const sim::LinearGauge seed_line = sim::linear_gauge({K, A0}, d.transducer);
  const sim::LinearGauge cal_line = sim::linear_gauge(plan.calibrated_line, d.transducer);
  const sim::LinearGauge& line = d.threshold == "seed" ? seed_line : cal_line;
  const double x_trip = plan.x_trip_m;
  const auto level_at_trip = sim::full_model_signal(d.transducer, dt, x_trip, settle);
  const double s_full_at_trip = level_at_trip.mean_V;
  // The first-passage bias of (23): the relay trips at the FIRST upward crossing of the noisy
  // signal, on average before the mean crossing (23) places, so the part is left large. No closed
  // form fits: Rice's crossing rate (Poisson crossings) gives 0.46 µm for d_gauging where the
  // Monte Carlo finds 0.02 µm (the level approaches at K·a = 0.40 V/s, 5.5 times the noise's
  // σ' = 0.072 V/s, so almost every path crosses once and the bias is the rare early excursion).
  // Calibrated instead: the linearised model's mean error over parts of its own (as many as the
  // study's, streams apart), made precise by a control variate: ε(t*)/K has mean 0 and follows
  // the finished size closely, so mean(e) − c·mean(ε*/K) has a small fraction of mean(e)'s
  // scatter. (23) is then aimed at target − bias.
  const bool calibrated = d.threshold == "calibrated" || d.threshold == "calibrated_dynamic";
  double bias_m = 0.0, bias_se_m = 0.0, s_static = plan.threshold_V;
  if (calibrated && p.noise_variance_m2 > 0.0) {
    sim::LinearParts cal(p, line, plan.threshold_V, d.parts, sc.run.seed + 1000003, kept_parts);
    const auto bias = sim::first_passage_bias(cal, p.target_m, line.gain_V_per_m);
    bias_m = bias.bias_m;
    bias_se_m = bias.standard_error_m;
    s_static = sim::threshold_23(line, [&] {
      auto q = p;
      q.target_m -= bias_m;
      return q;
    }());
  }
  // calibrated_dynamic: S_th moved until full-model parts (with noise) finish on target.
  sim::DynamicCalibration dyn;
  if (d.threshold == "calibrated_dynamic")
    dyn = sim::calibrate_dynamic(p, d.transducer, dt, s_static, cal_line.gain_V_per_m,
                                 d.calibration_parts_max, 0.025 * d.tolerance_m, sc.run.seed + 17,
                                 sc.run.duration_s);
  const double s_th = d.threshold == "calibrated_dynamic" ? dyn.threshold_V : s_static;
  const double seed_signal_dev_pct = 100.0 * (K * (A0 - x_trip) - s_full_at_trip) / s_full_at_trip;

  // 2. One full-model part without noise against the linear prediction (inside the range).
  auto quiet = p;
  quiet.noise_variance_m2 = 0.0;
  rec.attach(rec_csv.get());
  const auto full = sim::machine_part_full(quiet, d.transducer, dt, s_th, sc.run.seed, &rec, 50,
                                           sc.run.duration_s);
  rec_csv->finish();
  const double trip_lin = linear_trip(p, line, s_th);
  const double full_err_um = (full.finished_m - p.target_m) * kUm;

  // 3. Outside the range: fast removal, long filter, target near A0 — each with its own (23).
  struct Case {
    std::string name;
    sim::GaugingProcess proc;
    sensors::VibroContactGauge::Params tp;
  };
  std::vector<Case> cases;
  {
    Case c{"inside the range (this scenario)", quiet, d.transducer};
    cases.push_back(c);
    c = {"fast removal: a × 10", quiet, d.transducer};
    c.proc.removal_m_per_s *= 10.0;
    cases.push_back(c);
    c = {"long filter: T_f × 10", quiet, d.transducer};
    c.tp.filter_time_constant_s *= 10.0;
    cases.push_back(c);
    c = {"target near A0 (x_k = 0.85·A0)", quiet, d.transducer};
    c.proc.target_m = 0.85 * A0;
    c.proc.allowance_m = 0.97 * A0;
    c.proc.backstop_m = c.proc.target_m - d.tolerance_m;  // each case's own limit position
    cases.push_back(c);
    c = {"target near grazing (x_k = 0.02·A0)", quiet, d.transducer};
    c.proc.target_m = 0.02 * A0;
    c.proc.backstop_m = c.proc.target_m - d.tolerance_m;
    cases.push_back(c);
  }
  Table outside{
      "Full model against the linearised formulas (no noise; threshold (23) with the seed's A0 and "
      "K)",
      {"case", "trip (22)+(23) [s]", "trip, full model [s]", "finished − target, full [µm]",
       "ended by"},
      {}};
  json cases_json = json::array();
  for (const auto& c : cases) {
    const sim::LinearGauge lg = sim::linear_gauge({K, A0}, c.tp);
    const double th = sim::threshold_23(lg, c.proc);
    const double t_lin = linear_trip(c.proc, lg, th);
    const double horizon = 3.0 * (c.proc.allowance_m - c.proc.target_m) / c.proc.removal_m_per_s +
                           20.0 * lg.lag_s() + 1.0;
    const auto r = sim::machine_part_full(c.proc, c.tp, dt, th, sc.run.seed, nullptr, 50, horizon);
    const double err = (r.finished_m - c.proc.target_m) * kUm;
    outside.rows.push_back({c.name, fmt(t_lin, "%.3f"), fmt(r.trip_s, "%.3f"), fmt(err, "%.2f"),
                            r.backstop ? "backstop (alarm)" : "relay"});
    cases_json.push_back({{"case", c.name},
                          {"trip_linear_s", json_number(t_lin)},
                          {"trip_full_s", json_number(r.trip_s)},
                          {"finished_error_um", json_number(err)},
                          {"backstop", r.backstop}});
  }

  // 3b. The cause of the full model's error: ripple, subharmonic motion, or both —
  // the filters against the probe's regime (the seed's contact c_c = 5 N·s/m beside this one's).
  Table cause{
      "What the full model's error (no noise) comes from: the filter against the probe's "
      "regime, each with its own calibrated (23)",
      {"filter", "contact damping c_c [N·s/m]", "probe spread at trip [µm]", "ripple at trip [mV]",
       "finished − target [µm]"},
      {}};
  json cause_json = json::array();
  {
    using F = sensors::VibroContactGauge::Params::Filter;
    std::vector<sensors::VibroContactGauge::Params> variants;
    std::vector<double> contacts{5.0};  // the seed's example contact, and this one's
    if (d.transducer.contact_damping_N_s_per_m != 5.0)
      contacts.push_back(d.transducer.contact_damping_N_s_per_m);
    for (double cc : contacts)
      for (F f : {F::FirstOrder, F::SecondOrder, F::Synchronous}) {
        auto v = d.transducer;
        v.contact_damping_N_s_per_m = cc;
        v.filter = f;
        variants.push_back(v);
      }
    std::vector<sim::NoiselessPart> res(variants.size());
    sim::parallel_for(variants.size(), [&](std::size_t i) {
      res[i] = sim::noiseless_part(quiet, variants[i], dt, sc.run.seed, sc.run.duration_s);
    });
    for (std::size_t i = 0; i < variants.size(); ++i) {
      cause.rows.push_back({filter_name(variants[i].filter),
                            fmt(variants[i].contact_damping_N_s_per_m),
                            fmt(res[i].spread_m * kUm, "%.2f"), fmt(res[i].ripple_V * 1e3, "%.1f"),
                            fmt(res[i].error_m * kUm, "%.2f")});
      cause_json.push_back({{"filter", filter_name(variants[i].filter)},
                            {"contact_damping_N_s_per_m", variants[i].contact_damping_N_s_per_m},
                            {"probe_spread_um", json_number(res[i].spread_m * kUm)},
                            {"ripple_mV", json_number(res[i].ripple_V * 1e3)},
                            {"finished_error_um", json_number(res[i].error_m * kUm)}});
    }
  }

  // 4. Linearised Monte Carlo of finished sizes.
  // In passes over the parts (LinearParts): the first writes channels.csv (one row a part) and
  // sums the sizes, the second their spread about the mean, the third (the report) the histogram.
  sim::LinearParts parts(p, line, s_th, d.parts, sc.run.seed, kept_parts);
  const auto each_size = [&](auto&& f) {  // the finished sizes (the backstop's included)
    parts.for_each([&](std::size_t, const sim::PartResult& r) {
      if (std::isfinite(r.finished_m)) f(r.finished_m);
    });
  };
  std::size_t n_sizes = 0, never = 0, backstops = 0;
  Stats st;
  double smallest = full.finished_m;
  parts.for_each([&](std::size_t i, const sim::PartResult& r) {
    const std::array<double, 4> row{static_cast<double>(i), r.trip_s, r.stop_s,
                                    r.finished_m * kUm};
    parts_csv->row(row);
    never += std::isnan(r.trip_s) ? 1 : 0;
    backstops += r.backstop ? 1 : 0;
    if (!std::isfinite(r.finished_m)) return;
    st.mean += r.finished_m;
    smallest = std::min(smallest, r.finished_m);
    ++n_sizes;
  });
  parts_csv->finish();
  if (n_sizes < 2)  // only without removal (the backstop ends every cut that has one)
    io::throw_at_key(
        sc, sim::ConfigError("process.removal_um_per_s", "no part finished: nothing ends the cut"));
  st.mean /= static_cast<double>(n_sizes);
  each_size([&](double x) { st.sigma += (x - st.mean) * (x - st.mean); });
  st.sigma = std::sqrt(st.sigma / static_cast<double>(n_sizes - 1));
  // (25) extended to the filter: σ_x = sqrt(D·f), f = 1/(1 + βT_f) for the seed's first order.
  const double noise_factor = line.noise_factor(p.noise_beta_per_s);
  const double pred_sigma = std::sqrt(p.noise_variance_m2 * noise_factor);
  const double usl = p.target_m + d.tolerance_m, lsl = p.target_m - d.tolerance_m;
  const double cp = st.sigma > 0.0 ? (usl - lsl) / (6.0 * st.sigma) : INFINITY;
  const double cpk =
      st.sigma > 0.0 ? std::min(usl - st.mean, st.mean - lsl) / (3.0 * st.sigma) : INFINITY;
  const double se = st.sigma / std::sqrt(static_cast<double>(n_sizes));

  // 5. Seed (25) by Monte Carlo: filter-output noise, 1e5 samples far enough apart.
  const double spacing = 5.0 * std::max(line.lag_s(), 1.0 / p.noise_beta_per_s);
  const auto eps = sim::filter_noise_samples(p, line, 100000, spacing, sc.run.seed + 1);
  double v2 = 0.0;
  for (double e : eps) v2 += e * e;
  const double noise_sigma = std::sqrt(v2 / static_cast<double>(eps.size()));
  const double noise_pred =
      std::sqrt(p.noise_variance_m2 * line.gain_V_per_m * line.gain_V_per_m * noise_factor);

  // 6. A few full-model parts with noise, on all cores.
  std::vector<double> full_sizes(d.full_parts, 0.0);
  std::vector<char> full_backstop(d.full_parts, 0);
  sim::parallel_for(full_sizes.size(), [&](std::size_t i) {  // part i: its own seed
    const auto r = sim::machine_part_full(p, d.transducer, dt, s_th, sc.run.seed * 7919 + i,
                                          nullptr, 50, sc.run.duration_s);
    full_sizes[i] = r.finished_m;
    full_backstop[i] = r.backstop ? 1 : 0;
  });
  for (char b : full_backstop) backstops += static_cast<std::size_t>(b);
  backstops += full.backstop ? 1 : 0;
  // The one part of the run: ended by its backstop, it raises the gauging cycle's alarm.
  json alarms = json::array();
  if (full.backstop)
    alarms.push_back({{"time_s", json_number(full.stop_s)},
                      {"code", static_cast<int>(control::Reason::GaugeBackstop)},
                      {"reason", std::string(control::reason_name(control::Reason::GaugeBackstop))}});
  const Stats fst = full_sizes.size() > 1 ? stats(full_sizes) : Stats{};

  const bool regular = plan.calibrated_line.spread_m <= design::kRegularSpread * A0;
  io::RunOutput out;
  json& s = out.summary;
  s["system"] = sc.system;
  s["scenario"] = sc.name;
  s["file"] = sc.file;
  s["metrics"] = {{"parts", n_sizes},
                  {"parts_never_tripped", never},
                  {"size_mean_error_um", json_number((st.mean - p.target_m) * kUm)},
                  {"size_sigma_um", json_number(st.sigma * kUm)},
                  {"predicted_sigma_um", json_number(pred_sigma * kUm)},
                  {"size_mean_standard_error_um", json_number(se * kUm)},
                  {"cp", json_number(cp)},
                  {"cpk", json_number(cpk)},
                  {"tolerance_um", json_number(d.tolerance_m * kUm)},
                  {"threshold_V", json_number(s_th)},
                  {"threshold_kind", d.threshold},
                  {"free_amplitude_um", json_number(A0 * kUm)},
                  {"signal_gain_mV_per_um", json_number(K * 1e-3)},
                  {"calibrated_gain_mV_per_um", json_number(cal_line.gain_V_per_m * 1e-3)},
                  {"calibrated_intercept_um", json_number(cal_line.intercept_m * kUm)},
                  {"seed_signal_deviation_at_trip_pct", json_number(seed_signal_dev_pct)},
                  {"signal_ripple_at_trip_V", json_number(level_at_trip.ripple_V)},
                  {"noise_sigma_V", json_number(noise_sigma)},
                  {"noise_sigma_predicted_V", json_number(noise_pred)},
                  {"full_trip_time_s", json_number(full.trip_s)},
                  {"linear_trip_time_s", json_number(trip_lin)},
                  {"full_finished_error_um", json_number(full_err_um)},
                  {"full_mc_parts", full_sizes.size()},
                  {"full_mc_mean_error_um",
                   json_number(full_sizes.empty() ? NAN : (fst.mean - p.target_m) * kUm)},
                  {"full_mc_sigma_um", json_number(full_sizes.size() > 1 ? fst.sigma * kUm : NAN)},
                  {"backstop_um", json_number(p.backstop_m * kUm)},
                  {"filter", filter_name(d.transducer.filter)},
                  {"filter_lag_s", json_number(line.lag_s())},
                  {"bias_correction_um", json_number(bias_m * kUm)},
                  {"bias_correction_standard_error_um", json_number(bias_se_m * kUm)},
                  {"calibration_parts", dyn.parts},
                  {"probe_spread_at_trip_um", json_number(plan.calibrated_line.spread_m * kUm)},
                  {"probe_regular", regular},
                  {"backstop_trips", backstops},
                  {"threshold_forced", d.force_threshold && !plan.safe()},
                  {"safe_threshold_low_V", json_number(plan.range.low_V)},
                  {"safe_threshold_high_V", json_number(plan.range.high_V)},
                  {"signal_floor_V", json_number(plan.range.floor_V)},
                  {"signal_floor_from_um", json_number(plan.range.floor_start_m * kUm)},
                  {"largest_safe_target_um", json_number(plan.largest_target_m * kUm)},
                  {"alarms", alarms}};
  s["outside_range"] = cases_json;
  s["error_cause"] = cause_json;
  io::Acceptance acceptance(d.acceptance);
  acceptance.judge("min_cpk", cpk);
  acceptance.judge("max_mean_error_um", std::abs(st.mean - p.target_m) * kUm);
  s["acceptance"] = acceptance.json();

  Claims claims;
  claims.check(
      "(25): Monte Carlo σ of the filter-output noise / predicted (1e5 samples; within 3 %)",
      noise_sigma / noise_pred, Compare::RatioWithin, 0.03);
  claims.check("σ of finished size / sqrt(D/(1+βT_f))", st.sigma / pred_sigma, Compare::RatioWithin,
               0.05);
  const double bias_in_se = (st.mean - p.target_m) / se;
  // calibrated_dynamic aims the full model, not the linearised one: its linear mean is a note.
  if (d.threshold != "calibrated_dynamic")
    claims.check("threshold (23): mean finished size − target, in standard errors σ/√N (|·| ≤ 1)",
                 bias_in_se, Compare::Within, 1.0);
  else
    claims.note("calibrated_dynamic: the linearised model's parts at this threshold finish " +
                fmt((st.mean - p.target_m) * kUm, "%.3f") +
                " µm from target — how far the linearised model is from the full one there.");
  // Stated tolerance, fixed before looking: a tenth of the part's tolerance half-width.
  const double tol_full_um = 0.1 * d.tolerance_m * kUm;
  claims.check("inside the range: full-model part (no noise) finished − target [µm] (|·| ≤ " +
                   fmt(tol_full_um) + ", a tenth of the tolerance)",
               full_err_um, Compare::Within, tol_full_um);
  const double tol_trip_s = tol_full_um * 1e-6 / p.removal_m_per_s;
  claims.check("inside the range: full-model trip time − linear (22)+(23) [s] (|·| ≤ " +
                   fmt(tol_trip_s) + ": the same tenth in time)",
               full.trip_s - trip_lin, Compare::Within, tol_trip_s);
  claims.note("Filter ripple on the signal at the trip point: ±" +
              fmt(level_at_trip.ripple_V * 1e3) + " mV (±" +
              fmt(level_at_trip.ripple_V / cal_line.gain_V_per_m * kUm) +
              " µm of size). The relay trips on its crest, early by up to that; the linearised "
              "model, which "
              "has no ripple, cannot show it, and raising the threshold by it over-corrects (the "
              "probe's own "
              "amplitude lag works the other way). A longer or higher-order filter is the remedy.");
  claims.note("Mean filtered signal at the trip point x = " + fmt(x_trip * kUm) +
              " µm: full model " + fmt(s_full_at_trip) + " V, the seed's K·(A0 − x) " +
              fmt(K * (A0 - x_trip)) + " V (" + fmt(seed_signal_dev_pct, "%.2f") +
              " %); the local calibration gives K = " + fmt(cal_line.gain_V_per_m * 1e-3) +
              " mV/µm (seed: " + fmt(K * 1e-3) + "), intercept " + fmt(cal_line.intercept_m * kUm) +
              " µm (seed: A0 = " + fmt(A0 * kUm) + ").");
  if (calibrated && p.noise_variance_m2 > 0.0)
    claims.note(
        "First-passage bias: (23) places the mean crossing, the relay trips at the first; "
        "calibrated on " +
        std::to_string(d.parts) +
        " linearised parts of its own "
        "(control variate ε(t*)): " +
        fmt(bias_m * kUm, "%.4f") + " ± " + fmt(bias_se_m * kUm, "%.4f") +
        " µm, taken off the target in (23).");
  if (std::abs(bias_in_se) > 1.0 && !calibrated)
    claims.note(
        "The relay trips at the first upward crossing of S_th; with noise the first crossing comes "
        "early on "
        "average, so (23), which places the mean crossing, leaves the part slightly large: a "
        "first-passage "
        "bias of " +
        fmt((st.mean - p.target_m) * kUm, "%.4f") + " µm here (" + fmt(bias_in_se, "%.1f") +
        " standard errors of the mean, " + fmt(100.0 * (st.mean - p.target_m) / st.sigma, "%.2f") +
        " % of σ).");
  if (full_sizes.size() >= 30) {  // enough parts for their mean and σ to mean something
    claims.check("full model with noise: mean finished size − target [µm] (|·| ≤ 0.5)",
                 (fst.mean - p.target_m) * kUm, Compare::Within, 0.5);
    claims.check(
        "full model with noise: σ of finished size / (25) extended to the filter (within "
        "10 %)",
        fst.sigma / pred_sigma, Compare::RatioWithin, 0.10);
  }
  claims.note(std::string("Probe ") + (regular ? "regular" : "NOT regular") +
              " at the trip point: its position once per drive period spreads over " +
              fmt(plan.calibrated_line.spread_m * kUm) + " µm (" +
              fmt(100.0 * plan.calibrated_line.spread_m / A0, "%.1f") +
              " % of A0; the design rule asks ≤ " + fmt(100.0 * design::kRegularSpread) + " %).");
  if (d.threshold == "calibrated_dynamic")
    claims.note(
        "calibrated_dynamic: " + std::to_string(dyn.parts) + " full-model parts moved S_th from " +
        fmt(s_static) + " to " + fmt(dyn.threshold_V) + " V (pooled mean error " +
        fmt(dyn.mean_error_m * kUm, "%.3f") + " ± " + fmt(dyn.standard_error_m * kUm, "%.3f") +
        " µm" + (dyn.converged ? "" : ", not converged within calibration_parts_max") + ").");
  {
    for (double v : full_sizes) smallest = std::min(smallest, v);
    claims.check(
        "backstop: smallest finished size of every cut − the limit position [µm] (≥ 0: "
        "no part undersize beyond it)",
        (smallest - p.backstop_m) * kUm, Compare::AtLeast, -1e-9);
  }
  if (!plan.safe())
    claims.note("Forced (gauge.force_threshold): the threshold " + fmt(s_th) +
                " V lies outside the safe range " + fmt(plan.range.low_V) + "…" +
                fmt(plan.range.high_V) +
                " V the full model's signal reaches with its margin (the "
                "probe bounces on a floor of " +
                fmt(plan.range.floor_V) + " V from x = " + fmt(plan.range.floor_start_m * kUm) +
                " µm on); the safe range of targets ends at " + fmt(plan.largest_target_m * kUm) +
                " µm. " + std::to_string(backstops) + " cuts ended at the backstop " +
                fmt(p.backstop_m * kUm) + " µm.");
  s["claims"] = claims.json();

  io::Report& rep = out.report;
  rep.title = "System D — " + sc.name;
  rep.doc_page = "system-d-gauging.md";
  rep.subtitle = sc.file + " · vibro-contact in-process gauging, threshold: " + d.threshold;
  rep.description = sc.description;
  auto add = [&](const std::string& k, double v, const char* f = "%.4g") {
    rep.metrics.emplace_back(k, fmt(v, f));
  };
  add("parts (linearised Monte Carlo)", static_cast<double>(n_sizes), "%.0f");
  add("mean finished size − target [µm]", (st.mean - p.target_m) * kUm);
  add("σ of finished size [µm]", st.sigma * kUm);
  add("predicted σ sqrt(D/(1+βT_f)) [µm]", pred_sigma * kUm);
  add("Cp", cp);
  add("Cpk", cpk);
  add("threshold S_th [V]", s_th);
  add("safe range of S_th: from [V]", plan.range.low_V);
  add("safe range of S_th: to [V]", plan.range.high_V);
  add("signal floor (the probe bounces) [V]", plan.range.floor_V);
  add("signal floor from x [µm]", plan.range.floor_start_m * kUm);
  add("safe range of targets ends at [µm]", plan.largest_target_m * kUm);
  add("backstop (limit position) [µm]", p.backstop_m * kUm);
  add("cuts ended by the backstop", static_cast<double>(backstops), "%.0f");
  add("free amplitude A0 = largest allowance [µm]", A0 * kUm);
  add("signal gain K (seed) [mV/µm]", K * 1e-3);
  add("signal gain, calibrated at the trip point [mV/µm]", cal_line.gain_V_per_m * 1e-3);
  add("filter noise σ, Monte Carlo [mV]", noise_sigma * 1e3);
  add("filter noise σ, (25) [mV]", noise_pred * 1e3);
  add("full model (no noise): trip [s]", full.trip_s);
  add("linear (22)+(23): trip [s]", trip_lin);
  add("full model (no noise): finished − target [µm]", full_err_um);
  if (!full_sizes.empty()) {
    add("full-model parts with noise", static_cast<double>(full_sizes.size()), "%.0f");
    add("full-model parts: mean − target [µm]", (fst.mean - p.target_m) * kUm);
    if (full_sizes.size() > 1) add("full-model parts: σ [µm]", fst.sigma * kUm);
  }
  rep.notes = claims.notes();
  rep.note_ids = claims.note_ids();
  rep.tables.push_back(outside);
  rep.tables.push_back(cause);

  // Histogram of finished sizes with the normal law of the linear theory and the tolerance.
  {
    const double lo = std::min(st.mean - 5.0 * st.sigma, lsl - st.sigma);
    const double hi = std::max(st.mean + 5.0 * st.sigma, usl + st.sigma);
    const int bins = 80;
    const double w = (hi - lo) / bins;
    std::vector<double> counts(bins, 0.0);
    each_size([&](double v) {
      const int b = static_cast<int>((v - lo) / w);
      if (b >= 0 && b < bins) counts[static_cast<std::size_t>(b)] += 1.0;
    });
    Series hist{"finished sizes (" + std::to_string(n_sizes) + " parts)",
                {},
                {},
                "#1f77b4",
                false,
                false};
    for (int b = 0; b < bins; ++b) {
      hist.x.push_back((lo + b * w) * kUm);
      hist.y.push_back(counts[static_cast<std::size_t>(b)]);
      hist.x.push_back((lo + (b + 1) * w) * kUm);
      hist.y.push_back(counts[static_cast<std::size_t>(b)]);
    }
    Series normal{"normal, σ = sqrt(D/(1+βT_f)), mean at target", {}, {}, "#d62728", true, false};
    for (int k = 0; k <= 200; ++k) {
      const double x = lo + (hi - lo) * k / 200.0;
      const double z = (x - p.target_m) / pred_sigma;
      normal.x.push_back(x * kUm);
      normal.y.push_back(static_cast<double>(n_sizes) * w /
                         (pred_sigma * std::sqrt(2.0 * std::numbers::pi)) * std::exp(-0.5 * z * z));
    }
    Plot h{"Finished sizes: the controlled part x at the end of cut",
           "x [µm]",
           "parts per bin",
           {hist, normal},
           {{p.target_m * kUm, "target"}, {lsl * kUm, "LSL"}, {usl * kUm, "USL"}}};
    rep.plots.push_back(h);
  }
  {
    Series full_s{"full model: settled mean S", {}, {}, "#1f77b4", false, true};
    for (std::size_t i = 0; i < xs.size(); ++i) {
      full_s.x.push_back(xs[i] * kUm);
      full_s.y.push_back(s_full[i]);
    }
    Series seed_s{"seed (20): K·(A0 − x)", {0.0, A0 * kUm}, {K * A0, 0.0}, "#d62728", true, false};
    Series cal_s{"calibrated at the trip point",
                 {0.0, A0 * kUm},
                 {cal_line.gain_V_per_m * cal_line.intercept_m,
                  cal_line.gain_V_per_m * (cal_line.intercept_m - A0)},
                 "#2ca02c",
                 true,
                 false};
    rep.plots.push_back(Plot{"Mean filtered signal against the controlled size x",
                             "x [µm]",
                             "S [V]",
                             {full_s, seed_s, cal_s},
                             {{x_trip * kUm, "trip point"}, {A0 * kUm, "A0"}}});
  }
  {
    const auto along_time = [&](const char* channel, std::string name, std::string color) {
      Series r{std::move(name), {}, {}, std::move(color), false, false};
      rec.plot_points(channel, r.x, r.y);
      r.pyramid = rec.plot_pyramid(channel);
      return r;
    };
    Series sig_s = along_time("signal_V", "S(t), full model", "#1f77b4");
    // The recording ends when the part is finished: the constants end there too (not at the run's
    // duration, which left the axis running on past the data).
    const double t_end = rec.rows() == 0 ? 0.0 : rec.plot_pyramid("time_s")->x_last();
    Series th{"threshold S_th", {0.0, t_end}, {s_th, s_th}, "#555", true, false};
    rep.plots.push_back(Plot{"One part, full model without noise: filtered signal",
                             "time [s]",
                             "S [V]",
                             {sig_s, th},
                             {{full.trip_s, "relay trips"}, {full.stop_s, "cut ends"}}});
    Series xx = along_time("x_um", "x(t)", "#8c564b");
    Series tg{
        "target", {0.0, t_end}, {p.target_m * kUm, p.target_m * kUm}, "#555", true, false};
    rep.plots.push_back(Plot{"One part: the controlled size x(t)",
                             "time [s]",
                             "x [µm]",
                             {xx, tg},
                             {{full.stop_s, "cut ends"}}});
  }

  // Streamed into the stage; without one (a library caller) collected in memory.
  out.channels_csv = parts_csv->take_text();
  out.compare_csv = rec_csv->take_text();
  out.headline = std::to_string(n_sizes) + " parts: mean error " +
                 fmt((st.mean - p.target_m) * kUm, "%.4f") + " µm, σ " +
                 fmt(st.sigma * kUm, "%.3f") + " µm (predicted " + fmt(pred_sigma * kUm, "%.3f") +
                 "), Cpk " + fmt(cpk, "%.2f") + "; full model " + fmt(full_err_um, "%.2f") +
                 " µm off";
  return out;
}

}  // namespace lathectl::d_gauging
