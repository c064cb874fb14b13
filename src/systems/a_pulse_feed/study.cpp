// System A (seed 000): runs a scenario, its comparison and its K_leak sweep, computes the
// metrics and the claims they answer, and lays out the report.
#include "systems/a_pulse_feed/study.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "lathectl/control/types.hpp"
#include "lathectl/io/channel_stream.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/runner.hpp"
#include "lathectl/io/study.hpp"
#include "lathectl/io/verdict.hpp"
#include "systems/a_pulse_feed/metrics.hpp"
#include "systems/a_pulse_feed/regulator_studies.hpp"
#include "systems/a_pulse_feed/settings.hpp"

namespace lathectl::systems::a_pulse_feed {

namespace {
using namespace io;
using nlohmann::json;
using sim::ControllerKind;
using sim::RegulatorKind;

json metrics_json(const sim::MetricsA& m) {
  json alarms = json::array();
  for (const auto& a : m.alarms)
    alarms.push_back(
        {{"time_s", a.time_s},
         {"code", a.code},
         {"reason", std::string(control::reason_name(static_cast<control::Reason>(a.code)))}});
  return {{"feed_rate_programmed_mm_per_min", json_number(m.feed_rate_programmed_mm_per_min)},
          {"feed_rate_mean_mm_per_min", json_number(m.feed_rate_mean_mm_per_min)},
          {"feed_rate_reference_mm_per_min", json_number(m.feed_rate_reference_mm_per_min)},
          {"feed_rate_deviation_pct", json_number(m.feed_rate_deviation_pct)},
          {"feed_rate_steady_deviation_pct", json_number(m.feed_rate_steady_deviation_pct)},
          {"feed_drift_pct", json_number(m.feed_drift_pct)},
          {"force_nominal_N", json_number(m.force_nominal_N)},
          {"force_peak_N", json_number(m.force_peak_N)},
          {"force_setpoint_N", json_number(m.force_setpoint_N)},
          {"force_settling_time_s", json_number(m.force_settling_time_s)},
          {"force_final_error_pct", json_number(m.force_final_error_pct)},
          {"first_disturbance_s", json_number(m.first_disturbance_s)},
          {"flow_mean_cm3_per_min", json_number(m.flow_mean_cm3_per_min)},
          {"flow_formula_cm3_per_min", json_number(m.flow_formula_cm3_per_min)},
          {"flow_formula_error_pct", json_number(m.flow_formula_error_pct)},
          {"first_alarm_delay_s", json_number(m.first_alarm_delay_s)},
          {"volume_balance_pct", json_number(m.volume_balance_pct)},
          {"volume_conservation_error_pct", json_number(m.volume_conservation_error_pct)},
          {"deflection_reference_um", json_number(m.deflection_reference_um)},
          {"deflection_end_um", json_number(m.deflection_end_um)},
          {"size_error_diameter_um", json_number(m.size_error_diameter_um)},
          {"size_error_peak_diameter_um", json_number(m.size_error_peak_diameter_um)},
          {"alarms", alarms}};
}

struct Run {
  sim::RigA rig;
  std::unique_ptr<sim::MetricsAAccumulator> acc;  // fed as the rig records
  std::unique_ptr<sim::PulseMeanFlowPlot> pulse;  // the flow over whole pulses, for the plot
  std::unique_ptr<io::ChannelStream> csv;          // channels.csv / channels_compare.csv
  sim::MetricsA metrics;
  std::string label;
};

std::string label_of(const sim::RigAConfig& a) {
  if (a.regulator_kind == RegulatorKind::Throttle) return "continuous throttle";
  return a.controller_kind == ControllerKind::None ? "pulsed, no control"
                                                   : controller_kind_name(a.controller_kind);
}

// The rig records streamed (its memory bounded whatever run.duration_s): the metrics are
// computed row by row, csv (nullptr: none) is written into `stage` as the rows come.
void run_one(const io::Scenario& sc, const sim::RigAConfig& cfg, Run& r, const char* csv = nullptr,
             io::OutputStage* stage = nullptr) {
  r.rig.set_streamed(true);
  io::configure_rig(sc, r.rig, cfg);
  r.acc = std::make_unique<sim::MetricsAAccumulator>(r.rig, r.rig.last_record_time());
  r.rig.attach(r.acc.get());
  r.pulse = std::make_unique<sim::PulseMeanFlowPlot>(r.rig.recorder(), cfg.feed_window_s);
  r.rig.attach(r.pulse.get());
  if (csv) {
    try {
      r.csv = io::open_channel_stream(stage, csv, r.rig.recorder().channels(),
                                      sc.run.duration_s / sc.run.record_interval_s + 2.0);
    } catch (const std::invalid_argument& e) {
      io::throw_at_key(sc, e);
    }
    r.rig.attach(r.csv.get());
  }
  io::run_rig(sc, r.rig);
  if (r.csv) r.csv->finish();
  r.metrics = r.acc->result(r.rig);
  r.label = label_of(cfg);
}

// A recorded channel against time, decimated to a bounded number of points (sim::Recorder).
Series series(const Run& r, const char* channel, std::string name, std::string color,
              bool dashed = false) {
  return io::recorded_series(r.rig.recorder(), channel, std::move(name), std::move(color), dashed);
}

Series constant(const Run& r, double value, std::string name) {
  Series s;
  s.name = std::move(name);
  s.x = {r.acc->first_time(), r.acc->last_time()};
  s.y = {value, value};
  s.color = "#555";
  s.dashed = true;
  return s;
}

// The whole run's time span: every time plot gets it, so a sensor's NaN stretch at the end shows
// as a gap, not as a shorter axis.
void span_run(Plot& p, const Run& r) {
  p.x_min = 0.0;
  p.x_max = r.acc->last_time() > 0.0 ? r.acc->last_time() : 1.0;
}

std::vector<Marker> markers(const Run& r) {
  std::vector<Marker> m;
  if (!std::isnan(r.metrics.first_disturbance_s))
    m.push_back({r.metrics.first_disturbance_s, "disturbance"});
  for (const auto& f : r.rig.config().faults) m.push_back({f.at_s, "sensor fault"});
  for (const auto& a : r.metrics.alarms)
    m.push_back({a.time_s, "alarm: " + std::string(control::reason_name(
                                           static_cast<control::Reason>(a.code)))});
  return m;
}

constexpr const char* kMain = "#1f77b4";
constexpr const char* kCmp = "#d62728";
}  // namespace

io::RunOutput run(const io::Scenario& sc) {
  using namespace io;
  const Settings& settings = sc.get<Settings>();
  RunOutput out;
  auto main = std::make_unique<Run>();
  OutputStage* stage = StreamScope::current();
  run_one(sc, settings.rig, *main, "channels.csv", stage);
  std::unique_ptr<Run> cmp;
  if (settings.compare) {
    auto c = settings.rig;
    if (settings.compare->controller) c.controller_kind = *settings.compare->controller;
    if (settings.compare->regulator) c.regulator_kind = *settings.compare->regulator;
    if (c.regulator_kind == RegulatorKind::Throttle) c.controller_kind = ControllerKind::None;
    cmp = std::make_unique<Run>();
    run_one(sc, c, *cmp, "channels_compare.csv", stage);
    if (!settings.compare->label.empty()) cmp->label = settings.compare->label;
  }

  // Sweep of the controller's leakage estimate: how the finishing benefit degrades.
  json sweep = json::array();
  Table sweep_table{"Controller K_leak estimate against the true K_leak",
                    {"K_leak estimate / true", "feed deviation [%]", "steady deviation [%]",
                     "ratio to uncontrolled"},
                    {}};
  Plot sweep_plot{"Feed deviation vs the controller's K_leak error",
                  "K_leak estimate / true K_leak",
                  "feed deviation [%]",
                  {},
                  {}};
  if (!settings.sweep_leak_estimate_factor.empty()) {
    Series dev{"max deviation (controlled)", {}, {}, kMain, false, true};
    Series st{"steady deviation (controlled)", {}, {}, "#2ca02c", false, true};
    const double base = cmp && cmp->rig.config().controller_kind == ControllerKind::None
                            ? cmp->metrics.feed_rate_steady_deviation_pct
                            : std::numeric_limits<double>::quiet_NaN();
    for (const double f : settings.sweep_leak_estimate_factor) {
      auto c = settings.rig;
      c.leak_estimate_factor = f;
      Run r;
      run_one(sc, c, r);
      const double ratio = r.metrics.feed_rate_steady_deviation_pct / base;
      sweep.push_back({{"leak_estimate_factor", f},
                       {"feed_rate_deviation_pct", json_number(r.metrics.feed_rate_deviation_pct)},
                       {"feed_rate_steady_deviation_pct",
                        json_number(r.metrics.feed_rate_steady_deviation_pct)},
                       {"steady_ratio_to_uncontrolled", json_number(ratio)}});
      sweep_table.rows.push_back({fmt(f), fmt(r.metrics.feed_rate_deviation_pct),
                                  fmt(r.metrics.feed_rate_steady_deviation_pct),
                                  fmt(ratio, "%.3f")});
      dev.x.push_back(f);
      dev.y.push_back(r.metrics.feed_rate_deviation_pct);
      st.x.push_back(f);
      st.y.push_back(r.metrics.feed_rate_steady_deviation_pct);
    }
    sweep_plot.series = {dev, st};
    if (cmp) {
      Series un{"uncontrolled steady deviation",
                {settings.sweep_leak_estimate_factor.front(), settings.sweep_leak_estimate_factor.back()},
                {base, base},
                kCmp,
                true,
                false};
      sweep_plot.series.push_back(un);
    }
  }

  const auto& m = main->metrics;
  json& s = out.summary;
  s["system"] = sc.system;
  s["scenario"] = sc.name;
  s["file"] = sc.file;
  s["label"] = main->label;
  s["metrics"] = metrics_json(m);
  if (cmp) s["comparison"] = {{"label", cmp->label}, {"metrics", metrics_json(cmp->metrics)}};
  if (!sweep.empty()) s["sweep"] = sweep;

  const bool roughing =
      settings.rig.controller.mode == control::PulseFeedController::Mode::Roughing;
  {  // The user's cut is the main run's; each mode is judged by what it holds.
    Acceptance acceptance(settings.acceptance);
    if (roughing)
      acceptance.judge("max_force_over_set_pct",
                       100.0 * (m.force_peak_N / m.force_setpoint_N - 1.0));
    else
      acceptance.judge("max_feed_deviation_pct", m.feed_rate_deviation_pct);
    acceptance.judge("max_size_error_um", std::abs(m.size_error_diameter_um));
    s["acceptance"] = acceptance.json();
  }

  // Claims this run can answer, each with its number.
  Claims claims;
  if (cmp && settings.rig.controller_kind != ControllerKind::None &&
      cmp->rig.config().controller_kind == ControllerKind::None) {
    if (!roughing) {
      const double r2 = m.feed_rate_deviation_pct / cmp->metrics.feed_rate_deviation_pct;
      claims.check(
          "finishing: max feed deviation after the force change incl. the transient, controlled / "
          "uncontrolled (≤ 0.2; " +
              fmt(m.feed_rate_deviation_pct) + " % against " +
              fmt(cmp->metrics.feed_rate_deviation_pct) + " %)",
          r2, Compare::AtMost, 0.2);
      const double r1 =
          m.feed_rate_steady_deviation_pct / cmp->metrics.feed_rate_steady_deviation_pct;
      claims.check(
          "finishing: steady feed deviation after the force change, controlled / uncontrolled (≤ "
          "0.2)",
          r1, Compare::AtMost, 0.2);
      s["metrics"]["feed_deviation_ratio_to_uncontrolled"] = json_number(r2);
      // The finishing mode exists for the size; holding the feed does not hold it.
      const auto& c = cmp->metrics;
      claims.note(
          "size: the holder deflection Py/k goes " + fmt(m.deflection_reference_um, "%.3g") +
          " → " + fmt(m.deflection_end_um, "%.3g") + " µm with control (" +
          fmt(c.deflection_reference_um, "%.3g") + " → " + fmt(c.deflection_end_um, "%.3g") +
          " µm without), so the diameter grows by " + fmt(m.size_error_diameter_um, "%.3g") +
          " µm with control and " + fmt(c.size_error_diameter_um, "%.3g") +
          " µm without. Holding the feed holds the feed per revolution, and with it the "
          "roughness (Rz = s²/8r), and does not hold the size: the force follows the allowance. "
          "Holding the size needs the force held (the roughing mode's law), at a changing feed");
      s["metrics"]["size_error_ratio_to_uncontrolled"] =
          json_number(m.size_error_diameter_um / c.size_error_diameter_um);
      claims.check(
          "finishing, read as the document means it (size): steady diameter error from the holder "
          "deflection 2·ΔPy/k, controlled / uncontrolled (≤ 0.2, the feed claim's bound; " +
              fmt(m.size_error_diameter_um, "%.3g") + " µm against " +
              fmt(c.size_error_diameter_um, "%.3g") + " µm)",
          m.size_error_diameter_um / c.size_error_diameter_um, Compare::AtMost, 0.2);
    } else {
      claims.check("roughing: force within 5 % of its set value at the end (final error, %)",
                   m.force_final_error_pct, Compare::Within, 5.0);
      claims.add("roughing: force settling time after the disturbance [s]",
                 m.force_settling_time_s, !std::isnan(m.force_settling_time_s));
      const double rise = cmp->metrics.force_peak_N / cmp->metrics.force_nominal_N;
      claims.note("uncontrolled: force peak / nominal force = " + fmt(rise, "%.3f") + " (" +
                  fmt(cmp->metrics.force_peak_N) + " N)");
    }
  }
  if (cmp && cmp->rig.config().regulator_kind == RegulatorKind::Throttle) {
    claims.check("obliteration: continuous throttle feed drift over the run, % (|drift| > 5)",
                 cmp->metrics.feed_drift_pct, Compare::Outside, 5.0);
    claims.check("obliteration: pulsed regulator feed drift over the run, % (|drift| < 1; rests "
                 "on each closing stroke sweeping off the share " +
                     fmt(settings.rig.regulator.obliteration.removal_per_stroke) +
                     " of the layer, an assumption: see the η sweep when given)",
                 m.feed_drift_pct, Compare::Within, 1.0);
  }
  if (!std::isnan(m.flow_formula_error_pct))
    claims.note("mean flow " + fmt(m.flow_mean_cm3_per_min) + " cm³/min against formula (1) " +
                fmt(m.flow_formula_cm3_per_min) + " cm³/min: error " +
                fmt(m.flow_formula_error_pct, "%.3f") + " %");
  if (!settings.rig.faults.empty())
    claims.add("sensor fault: alarm raised, delay after the fault [s]", m.first_alarm_delay_s,
               !std::isnan(m.first_alarm_delay_s));
  // The regulator alone, where the seed's advantages 4 and 5 are decided.
  if (settings.tolerance && settings.rig.regulator_kind == RegulatorKind::Pulsed)
    tolerance_study(settings, *settings.tolerance,
                    settings.rig.controller_kind == ControllerKind::Fim
                        ? settings.rig.slot_m
                        : main->rig.fixed_actuator(),
                    sc.run.seed, out, claims);
  if (!settings.obliteration_removal.empty() && cmp &&
      cmp->rig.config().regulator_kind == RegulatorKind::Throttle &&
      settings.rig.regulator_kind == RegulatorKind::Pulsed)
    obliteration_study(settings, main->rig.fixed_actuator(), cmp->rig.fixed_actuator(),
                       sc.run.duration_s, out, claims);
  // (their tables and plots go after the run's own, below)
  const auto study_tables = static_cast<std::ptrdiff_t>(out.report.tables.size());
  const auto study_plots = static_cast<std::ptrdiff_t>(out.report.plots.size());
  s["claims"] = claims.json();

  // Report.
  Report& rep = out.report;
  rep.title = "System A — " + sc.name;
  rep.doc_page = "system-a-pulse-feed.md";
  rep.subtitle = sc.file + " · " + main->label + (cmp ? " against " + cmp->label : "") + " · " +
                 std::string(roughing ? "roughing" : "finishing") + " mode";
  rep.description = sc.description;
  auto add = [&](const std::string& k, double v, const char* f = "%.4g") {
    rep.metrics.emplace_back(k, fmt(v, f));
  };
  add("programmed feed [mm/min]", m.feed_rate_programmed_mm_per_min);
  add("mean feed [mm/min]", m.feed_rate_mean_mm_per_min);
  add("feed deviation after disturbance [%]", m.feed_rate_deviation_pct);
  add("steady feed deviation [%]", m.feed_rate_steady_deviation_pct);
  add("feed drift over run [%]", m.feed_drift_pct);
  add("nominal force Py [N]", m.force_nominal_N);
  add("peak force Py [N]", m.force_peak_N);
  if (roughing) {
    add("force setpoint [N]", m.force_setpoint_N);
    add("force settling time [s]", m.force_settling_time_s);
    add("final force error [%]", m.force_final_error_pct);
  }
  if (!std::isnan(m.size_error_diameter_um)) {
    add("holder deflection before → after the disturbance [µm]", m.deflection_reference_um);
    rep.metrics.back().second += " → " + fmt(m.deflection_end_um);
    add("diameter error from the deflection, steady [µm]", m.size_error_diameter_um);
  }
  add("mean regulator flow [cm³/min]", m.flow_mean_cm3_per_min);
  add("travel not explained by net inflow [% of delivered oil]", m.volume_balance_pct);
  if (cmp) {
    rep.metrics.emplace_back("— comparison —", cmp->label);
    add("feed deviation (comparison) [%]", cmp->metrics.feed_rate_deviation_pct);
    add("steady feed deviation (comparison) [%]", cmp->metrics.feed_rate_steady_deviation_pct);
    add("feed drift (comparison) [%]", cmp->metrics.feed_drift_pct);
    add("peak force (comparison) [N]", cmp->metrics.force_peak_N);
    if (!std::isnan(cmp->metrics.size_error_diameter_um))
      add("diameter error, steady (comparison) [µm]", cmp->metrics.size_error_diameter_um);
  }
  for (const auto& a : m.alarms)
    rep.metrics.emplace_back(
        "alarm at " + fmt(a.time_s) + " s",
        std::string(control::reason_name(static_cast<control::Reason>(a.code))) + " (code " +
            std::to_string(a.code) + ")");
  rep.notes = claims.notes();
  rep.note_ids = claims.note_ids();
  if (!sweep.empty()) rep.tables.push_back(sweep_table);

  const auto mk = markers(*main);
  const double window_s = settings.rig.feed_window_s;
  Plot feed{"Feed rate (averaged over the whole pulse periods nearest " + fmt(window_s * 1000) +
                " ms)",
            "time [s]",
            "feed [mm/min]",
            {},
            mk};
  // The rig's feed channel from its first full window on (before, the mean mixes in the assumed
  // steady motion before t = 0: a ripple that is not the run's).
  const auto from_full_window = [&](Series sr) {
    for (std::size_t i = 0; i < sr.y.size() && sr.x[i] - sr.x.front() < window_s; ++i)
      sr.y[i] = std::nan("");
    return sr;
  };
  feed.series.push_back(from_full_window(series(*main, "feed_mm_per_min", main->label, kMain)));
  if (cmp)
    feed.series.push_back(from_full_window(series(*cmp, "feed_mm_per_min", cmp->label, kCmp)));
  feed.series.push_back(constant(*main, m.feed_rate_programmed_mm_per_min, "programmed"));
  span_run(feed, *main);
  rep.plots.push_back(feed);

  Plot force{"Radial cutting force Py", "time [s]", "force [N]", {}, mk};
  force.series.push_back(series(*main, "force_Py_N", main->label, kMain));
  if (cmp) force.series.push_back(series(*cmp, "force_Py_N", cmp->label, kCmp));
  if (roughing) force.series.push_back(constant(*main, m.force_setpoint_N, "set force"));
  span_run(force, *main);
  rep.plots.push_back(force);

  const bool fim = settings.rig.controller_kind == ControllerKind::Fim;
  const bool aim = settings.rig.controller_kind == ControllerKind::Aim;
  Plot act{fim   ? "Pulse frequency f (FIM actuator: converter)"
           : aim ? "Regulator slot h (AIM actuator: eccentric)"
                 : "Regulator slot h",
           "time [s]",
           fim ? "frequency [Hz]" : "slot [µm]",
           {},
           mk};
  act.series.push_back(series(*main, fim ? "frequency_Hz" : "slot_um", main->label, kMain));
  if (cmp && cmp->rig.config().regulator_kind == RegulatorKind::Pulsed)
    act.series.push_back(series(*cmp, fim ? "frequency_Hz" : "slot_um", cmp->label, kCmp));
  span_run(act, *main);
  rep.plots.push_back(act);

  Plot sens{"Inductive sensor signal U_D", "time [s]", "U_D [V]", {}, mk};
  sens.series.push_back(series(*main, "sensor_V", main->label, kMain));
  span_run(sens, *main);
  rep.plots.push_back(sens);

  Plot flow{"Regulator flow (averaged over whole pulse periods) and internal leakage",
            "time [s]",
            "flow [cm³/min]",
            {},
            mk};
  const auto smooth = [&](const Run& r, Series sr) {
    // whole pulses (sim::PulseMeanFlowPlot); a flow that never stops: the trailing window mean
    auto p = r.pulse->plot();
    if (!p) p = r.acc->flow_smoothed_plot().finished();
    p->points(sr.x, sr.y);
    sr.pyramid = std::move(p);
    return sr;
  };
  flow.series.push_back(
      smooth(*main, series(*main, "flow_cm3_per_min", "regulator flow, " + main->label, kMain)));
  flow.series.push_back(series(*main, "leak_cm3_per_min", "leakage, " + main->label, "#2ca02c"));
  if (cmp)
    flow.series.push_back(
        smooth(*cmp, series(*cmp, "flow_cm3_per_min", "regulator flow, " + cmp->label, kCmp)));
  span_run(flow, *main);
  rep.plots.push_back(flow);

  // Depth [mm] and the strength factor share no unit: one panel each.
  Plot depth{"Disturbance: depth of cut", "time [s]", "depth [mm]", {}, mk};
  depth.series.push_back(series(*main, "depth_mm", "depth of cut", "#8c564b"));
  span_run(depth, *main);
  rep.plots.push_back(depth);
  Plot hard{"Disturbance: hardness (strength factor)", "time [s]", "strength factor", {}, mk};
  hard.series.push_back(series(*main, "strength_factor", "strength factor", "#9467bd"));
  span_run(hard, *main);
  rep.plots.push_back(hard);

  if (cmp && cmp->rig.config().regulator_kind == RegulatorKind::Throttle) {
    Plot ob{
        "Obliteration layer in the continuous throttle", "time [s]", "layer per wall [µm]", {}, {}};
    ob.series.push_back(series(*cmp, "obliteration_layer_um", cmp->label, kCmp));
    rep.plots.push_back(ob);
  }
  if (!sweep.empty()) rep.plots.push_back(sweep_plot);

  // Regulator characteristic: simulated mean flow against formula (1) over the duty range.
  if (settings.rig.regulator_kind == RegulatorKind::Pulsed) {
    const double f = fim ? std::max(main->rig.controller().actuator_for(
                                        settings.rig.controller.feed_m_per_s, m.force_nominal_N),
                                    1.0)
                         : settings.rig.frequency_Hz;
    const double h = fim ? settings.rig.slot_m : main->rig.fixed_actuator();
    std::vector<double> widths, duty;
    for (int k = 0; k <= 40; ++k) {
      duty.push_back(k / 40.0);
      widths.push_back(k / 40.0 / f);
    }
    auto ideal_p = settings.rig.regulator;
    ideal_p.opening_time_s = ideal_p.closing_time_s = ideal_p.lap_m = 0.0;
    const auto q_real = sim::regulator_characteristic(settings.rig.regulator, h, f, widths);
    const auto q_ideal_sim = sim::regulator_characteristic(ideal_p, h, f, widths);
    Plot ch{"Regulator characteristic at h = " + fmt(h * 1e6) + " µm, f = " + fmt(f) + " Hz",
            "duty Δt/T",
            "mean flow [cm³/min]",
            {},
            {}};
    Series formula{"formula (1): μπd·h·√(2Δp/ρ)·Δt/T", duty, {}, "#555", true, false};
    for (double d : duty) formula.y.push_back(settings.rig.regulator.orifice.gain_per_m() * h * d * 6e7);
    Series ideal{"simulated, instantaneous switching", duty, {}, "#2ca02c", false, true};
    for (double q : q_ideal_sim) ideal.y.push_back(q * 6e7);
    Series real{"simulated, opening " + fmt(settings.rig.regulator.opening_time_s * 1e3) +
                    " ms / closing " + fmt(settings.rig.regulator.closing_time_s * 1e3) + " ms, overlap " +
                    fmt(settings.rig.regulator.lap_m * 1e6) + " µm",
                duty,
                {},
                kMain,
                false,
                false};
    for (double q : q_real) real.y.push_back(q * 6e7);
    ch.series = {formula, ideal, real};
    rep.plots.push_back(ch);
    double worst = 0.0;
    for (std::size_t k = 1; k < duty.size() - 1; ++k)
      worst = std::max(
          worst,
          std::abs(q_ideal_sim[k] / (settings.rig.regulator.orifice.gain_per_m() * h * duty[k]) - 1.0));
    s["metrics"]["regulator_ideal_flow_max_error_pct"] = 100.0 * worst;
    // Dead zone and saturation from the switching model, closed form against simulation:
    //   no flow while Δt < lap/v_open;  full flow once T − Δt < (h + lap)/v_close.
    const auto& rp = settings.rig.regulator;
    const double travel = rp.lap_m + rp.max_slot_m;
    const double dead_theory = rp.opening_time_s * rp.lap_m / travel * f;
    const double sat_theory = 1.0 - rp.closing_time_s * (h + rp.lap_m) / travel * f;
    const auto lim = sim::regulator_switching_limits(rp, h, f);
    const double dead_sim = lim.dead_zone_duty, sat_sim = lim.saturation_duty;
    s["metrics"]["regulator_dead_zone_duty"] = dead_theory;
    s["metrics"]["regulator_dead_zone_duty_simulated"] = dead_sim;
    s["metrics"]["regulator_saturation_duty"] = sat_theory;
    s["metrics"]["regulator_saturation_duty_simulated"] = sat_sim;
    if (rp.opening_time_s > 0.0 || rp.closing_time_s > 0.0 || rp.lap_m > 0.0) {
      claims.note("regulator dead zone: no flow below duty " + fmt(dead_theory, "%.3f") +
                  " (closed form; simulated " + fmt(dead_sim, "%.5f") +
                  "); the spool stops closing between pulses from duty " + fmt(sat_theory, "%.4f") +
                  " (closed form; simulated " + fmt(sat_sim, "%.5f") + ")");
      rep.notes = claims.notes();
      rep.note_ids = claims.note_ids();
    }
  }

  std::rotate(rep.tables.begin(), rep.tables.begin() + study_tables, rep.tables.end());
  std::rotate(rep.plots.begin(), rep.plots.begin() + study_plots, rep.plots.end());
  // In memory only without a stage (library callers, tests); else on disk already.
  out.channels_csv = main->csv->take_text();
  if (cmp) out.compare_csv = cmp->csv->take_text();
  out.headline = main->label + (cmp ? " vs " + cmp->label : "") + ": feed dev " +
                 fmt(m.feed_rate_deviation_pct) + " %, steady " +
                 fmt(m.feed_rate_steady_deviation_pct) + " %, peak Py " + fmt(m.force_peak_N) +
                 " N" + (roughing ? ", settle " + fmt(m.force_settling_time_s) + " s" : "") +
                 (cmp && cmp->rig.config().regulator_kind == RegulatorKind::Throttle
                      ? ", drift " + fmt(m.feed_drift_pct) + " % vs throttle " +
                            fmt(cmp->metrics.feed_drift_pct) + " %"
                      : "");
  return out;
}

}  // namespace lathectl::systems::a_pulse_feed
