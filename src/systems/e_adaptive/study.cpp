// System E (seed 004): runs the scenario's controller and those it is compared with, the prior art
// at seed 004's tool budget and the planned-depth sweep, computes the claims they answer (force
// held, productivity order, tool life against plan, sensor faults, cost per part) and lays out
// the report (the phases of io::Study).
#include "systems/e_adaptive/study.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <stdexcept>

#include "lathectl/control/types.hpp"
#include "lathectl/core/parallel.hpp"
#include "lathectl/io/channel_stream.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/study.hpp"
#include "lathectl/io/verdict.hpp"
#include "systems/e_adaptive/metrics.hpp"
#include "systems/e_adaptive/plots.hpp"
#include "systems/e_adaptive/settings.hpp"
#include "systems/e_adaptive/study_phases.hpp"

namespace lathectl::systems::e_adaptive {

namespace detail {

// A cycle time only when the part was finished; else where the run stopped (run.duration_s).
std::string cycle_cell(const Metrics& m) {
  return m.finished ? fmt(m.cycle_time_s, "%.1f")
                    : "not finished (stopped at " + fmt(m.cycle_time_s, "%.1f") + ")";
}
std::string cycle_phrase(const Metrics& m) {
  return m.finished ? "cycle " + fmt(m.cycle_time_s, "%.1f") + " s"
                    : "part not finished, the run stopped at " + fmt(m.cycle_time_s, "%.1f") + " s";
}
// A controller as the controllers' table names it.
std::string short_name(Mode m) {
  return m == Mode::Fixed       ? std::string("fixed")
         : m == Mode::ForceFeed ? std::string("prior art")
                                : std::string("seed 004");
}

// csv: the result file the run's channels go to (nullptr: none), streamed into `stage`.
void run_one(const Scenario& sc, RigConfig cfg, Mode mode, bool as_comparison, Run& r,
             const char* csv, OutputStage* stage) {
  cfg.controller.mode = mode;
  // The baseline must be set for the worst case to avoid overload: that is what makes it slow.
  if (mode == Mode::Fixed && as_comparison) cfg.worst_case_feed = true;
  configure_rig(sc, r.rig, cfg);
  r.acc = std::make_unique<MetricsAccumulator>(r.rig);
  r.rig.attach(r.acc.get());
  r.path = std::make_unique<PathPlots>(r.rig.recorder());
  r.rig.attach(r.path.get());
  if (csv) {
    try {
      r.csv = open_channel_stream(stage, csv, r.rig.recorder().channels(),
                                  sc.run.duration_s / sc.run.record_interval_s + 2.0);
    } catch (const std::invalid_argument& e) {
      throw_at_key(sc, e);
    }
    r.rig.attach(r.csv.get());
  }
  run_rig(sc, r.rig);
  if (r.csv) r.csv->finish();
  r.m = r.acc->result(r.rig);
  r.mode = mode;
  r.label = mode == Mode::ForceFeedSpeed && cfg.life_law ? "force by feed + tool-life speed law"
                                                          : mode_name(mode);
}
PartCost part_cost(const Metrics& m, const Cost& c) {
  PartCost pc;
  pc.machine = m.cycle_time_s / 3600.0 * c.machine_rate_per_h;
  pc.tool = m.tool_life_used_fraction *
            (c.tool_edge_cost + c.tool_change_min / 60.0 * c.machine_rate_per_h);
  pc.total = pc.machine + pc.tool;
  return pc;
}

json metrics_json(const Run& r, const std::string& unit, const Cost& cost) {
  const auto& m = r.m;
  const PartCost pc = part_cost(m, cost);
  return {{"finished", m.finished},
          {"cost_per_part", json_number(pc.total)},
          {"cost_machine_time", json_number(pc.machine)},
          {"cost_tool", json_number(pc.tool)},
          {"cycle_time_s", json_number(m.cycle_time_s)},
          {"time_in_cut_s", json_number(m.time_in_cut_s)},
          {"force_parameter_unit", unit},
          {"force_limit_N", json_number(m.load_limit)},
          {"force_peak_N", json_number(m.force_peak)},
          {"force_peak_rev_mean_N", json_number(m.force_peak_rev_mean)},
          {"force_overshoot_pct", json_number(m.force_overshoot_pct)},
          {"force_within_5pct_fraction", json_number(m.force_within_5pct_fraction)},
          {"force_mean_steady_N", json_number(m.force_mean_steady)},
          {"force_Pz_peak_N", json_number(m.force_Pz_peak_N)},
          {"tool_life_used_fraction", json_number(m.tool_life_used_fraction)},
          {"tool_life_plan_fraction", json_number(m.tool_life_plan_fraction)},
          {"tool_life_used_nominal_hardness_fraction",
           json_number(m.tool_life_used_nominal_hardness_fraction)},
          {"tool_life_used_nominal_hardness_to_plan",
           json_number(m.tool_life_used_nominal_hardness_fraction / m.tool_life_plan_fraction)},
          {"tool_life_used_to_plan",
           json_number(m.tool_life_used_fraction / m.tool_life_plan_fraction)},
          {"tool_life_planned_min", json_number(m.tool_life_planned_min)},
          {"material_removed_cm3", json_number(m.material_removed_cm3)},
          {"mrr_cm3_per_min", json_number(m.mrr_cm3_per_min)},
          {"feed_mean_mm_per_rev", json_number(m.feed_mean_mm_per_rev)},
          {"feed_programmed_mm_per_rev", json_number(m.feed_programmed_mm_per_rev)},
          {"speed_mean_m_per_min", json_number(m.speed_mean_m_per_min)},
          {"spindle_power_peak_kW", json_number(m.spindle_power_peak_kW)},
          {"first_alarm_delay_s", json_number(m.first_alarm_delay_s)},
          {"feed_hold_delay_s", json_number(m.feed_hold_delay_s)},
          {"alarms", alarms_json(m.alarms)}};
}

Series constant(double x0, double x1, double y, const std::string& name) {
  return Series{name, {x0, x1}, {y, y}, "#555", true, false};
}

std::string alarm_name(const sim::AlarmEvent& a) {
  return std::string(control::reason_name(static_cast<control::Reason>(a.code)));
}

void EStudy::run_controllers() {
  std::vector<Mode> modes{e().controller.mode};
  for (const Mode m : st_.compare_modes)
    if (m != e().controller.mode) modes.push_back(m);
  for (std::size_t i = 0; i < modes.size(); ++i) runs_.push_back(std::make_unique<Run>());
  // The runs are independent: side by side on two cores (each is one core's work).
  // channels.csv (main run) and channels_compare.csv (first comparison) stream into the output
  // set's stage as the runs record.
  OutputStage* stage = StreamScope::current();
  core::parallel_for(
      modes.size(),
      [&](std::size_t i) {
        const char* csv = i == 0 ? "channels.csv" : i == 1 ? "channels_compare.csv" : nullptr;
        run_one(sc_, e(), modes[i], i > 0, *runs_[i], csv, stage);
      },
      2);
  for (const auto& r : runs_) by_mode_[static_cast<std::size_t>(r->mode)] = r.get();
  run_beside();
}

// The runs the extra studies need, side by side: the prior art at seed 004's tool budget, the
// depth-corrected law at each planned depth, the seed law when the main run is not it.
void EStudy::run_beside() {
  // Productivity at equal tool use. (a) Cost per part at the [cost] rates.
  // (b) The prior art given seed 004's tool-life budget: its speed raised until it uses as much
  // of an edge. At a held force Pz ∝ s^0.75·V^−0.15, so s ∝ V^0.2, time in cut ∝ 1/(V·s) ∝ V^−1.2
  // and T ∝ V^−5·s^(−y_v/m), so the share used ∝ V^(3.8 + y_v): one run at the speed this
  // predicts, then the cycle time interpolated log-log to the seed's use between that run and
  // the prior art at V_p (both measured).
  const Run* seed = by_mode_[2];
  const Run* prior = by_mode_[1];
  tradeoff_ = seed && prior && e().faults.empty() && seed->m.finished && prior->m.finished &&
              prior->m.tool_life_used_fraction > 0.0 && seed->m.tool_life_used_fraction > 0.0;
  // Item 5: the used/plan verdict against the planned depth t_p (jobs: depth-corrected law at
  // each t_p; the seed law from the main run, which never reads t_p, or one run of it).
  main_seed_law_ =
      e().controller.mode == Mode::ForceFeedSpeed && e().controller.depth_exponent_xv == 0.0;
  std::vector<std::function<void()>> jobs;
  if (tradeoff_) {
    budget_speed_factor_ =
        std::pow(seed->m.tool_life_used_fraction / prior->m.tool_life_used_fraction,
                 1.0 / (3.8 + e().controller.y_v));
    jobs.push_back([this] {
      auto c = e();
      c.controller.speed_programmed_m_per_min *= budget_speed_factor_;
      run_one(sc_, c, Mode::ForceFeed, true, budget_);
    });
  }
  for (const double d : depths()) {
    corrected_.push_back(std::make_unique<Run>());
    jobs.push_back([this, d, r = corrected_.back().get()] {
      auto c = e();
      c.planned_depth_mm = d;
      use_depth_corrected_law(c);
      run_one(sc_, c, Mode::ForceFeedSpeed, false, *r);
    });
  }
  if ((!depths().empty() || e().life_law) && !main_seed_law_)
    jobs.push_back([this] {
      auto c = e();
      c.controller.depth_exponent_xv = 0.0;
      c.life_law = false;
      run_one(sc_, c, Mode::ForceFeedSpeed, false, seed_law_);
    });
  core::parallel_for(
      jobs.size(), [&](std::size_t i) { jobs[i](); }, 2);
}

void EStudy::check_claims(Claims& claims) {
  for (const auto& r : runs_) force_claims(*r, claims);
  if (by_mode_[0] && by_mode_[1] && by_mode_[2]) productivity_claim(claims);
  if (by_mode_[2] && e().faults.empty()) tool_life_claims(claims);
  if (!e().faults.empty()) fault_claims(claims);
  if (by_mode_[0]) baseline_note(*by_mode_[0], claims);
}

// An unfinished part; a controller's force held at its limit (not the fixed run's, nor under
// sensor faults).
void EStudy::force_claims(const Run& r, Claims& claims) const {
  if (!r.m.finished)
    claims.note("✘ " + r.label + ": the part was not finished within run.duration_s");
  if (r.mode == Mode::Fixed || !e().faults.empty()) return;
  // A part never cut holds no force at its limit and so cannot keep it: these claims are not
  // met (no number), however far below the limit a force of zero is.
  const bool cut = r.m.time_in_cut_s > 0.0;
  if (!cut)
    claims.note("✘ " + r.label +
                ": the tool never cut the part, so the force claims below do not apply");
  const double nan = std::nan("");
  // Not cut: the value is NaN, which meets no threshold.
  claims.check(r.label + ": share of steady cutting with the per-revolution " + pname_ +
                   " within 5 % of its limit (≥ 0.95)",
               cut ? r.m.force_within_5pct_fraction : nan, Compare::AtLeast, 0.95);
  claims.check(r.label + ": largest per-revolution " + pname_ + " above its limit, % (≤ 15)",
               cut ? r.m.force_overshoot_pct : nan, Compare::AtMost, 15.0);
}

// How the fixed baseline's feed was chosen, and what it would take to finish.
void EStudy::baseline_note(const Run& fixed, Claims& claims) const {
  const RigConfig& c = e();
  // (a compared fixed run is set for the worst case, run_one; a main one only if asked)
  if (&fixed == &main() && !c.worst_case_feed) {
    claims.note("fixed baseline: the programmed feed " +
                fmt(fixed.m.feed_programmed_mm_per_rev, "%.3f") + " mm/rev and V_p " +
                fmt(c.controller.speed_programmed_m_per_min) + " m/min, as the scenario sets them");
    return;
  }
  cutting::CuttingModel cut;
  cut.configure(c.cutting);
  cutting::Stock stock;
  stock.configure(c.stock);
  const Rig::WorstCase w = Rig::worst_case(c, cut, stock);
  std::string s = "fixed baseline: s = " + fmt(w.feed_mm_per_rev, "%.3f") + " mm/rev at V_p " +
                  fmt(w.speed_m_per_min) + " m/min, the largest feed whose handbook " + pname_ +
                  " stays within the limit (" + fmt(c.controller.load_limit, "%.0f") + " " +
                  unit_ + ") at the worst spot the scenario knows: depth " +
                  fmt(w.depth_mm, "%.2f") + " mm (the deepest pass + 3σ of the allowance), " +
                  "hardness " + fmt(w.hardness, "%.2f") + ", worn-tool force factor " +
                  fmt(w.wear_factor, "%.2f") + " (" + fmt(w.parameter_at_feed, "%.0f") + " " +
                  unit_ + " there)";
  if (w.at_min)
    s += "; even s_min exceeds the limit there, so the baseline runs at s_min";
  if (!fixed.m.finished && main().m.finished && fixed.m.material_removed_cm3 > 0.0) {
    const double need = fixed.m.cycle_time_s * main().m.material_removed_cm3 /
                        fixed.m.material_removed_cm3;
    s += "; it did not finish within run.duration_s = " + fmt(fixed.m.cycle_time_s, "%.0f") +
         " s: at its removal rate so far it needs at least about " + fmt(need, "%.0f") + " s (" +
         fmt(fixed.m.material_removed_cm3, "%.1f") + " of " +
         fmt(main().m.material_removed_cm3, "%.1f") + " cm³ removed) — raise run.duration_s";
  }
  claims.note(s);
}

void EStudy::productivity_claim(Claims& claims) const {
  const double c0 = by_mode_[0]->m.cycle_time_s, c1 = by_mode_[1]->m.cycle_time_s,
               c2 = by_mode_[2]->m.cycle_time_s;
  const std::string law = e().life_law ? "the tool-life law" : "seed 004";
  claims.add("productivity: cycle time " + law + " < prior art < fixed (" + fmt(c2) + " s < " +
                 fmt(c1) + " s < " + fmt(c0) + " s); " + law + " / prior art",
             c2 / c1,
             c2 < c1 && c1 < c0 && by_mode_[0]->m.finished && by_mode_[1]->m.finished &&
                 by_mode_[2]->m.finished);
}

// Seed 004's tool-life use against plan, and how much of it the part's hardness takes.
void EStudy::tool_life_claims(Claims& claims) const {
  const auto& m2 = by_mode_[2]->m;
  const double ratio = m2.tool_life_used_fraction / m2.tool_life_plan_fraction;
  if (e().life_law) {
    // Beyond the seed: the tool-life law, side by side with the seed's own on the same part.
    const auto& ms = seed_law_.m;
    const double seed_ratio = ms.tool_life_used_fraction / ms.tool_life_plan_fraction;
    claims.add("tool-life law (depth from the stock model, hardness from the specific force): "
                   "tool-life consumption against plan, within 15 % (seed 004's law on the same "
                   "part: " +
                   fmt(seed_ratio, "%.2f") + "; cycle " + fmt(m2.cycle_time_s) + " s against " +
                   fmt(ms.cycle_time_s) + " s)",
               ratio, std::abs(ratio - 1.0) <= 0.15);
    return;
  }
  claims.add(
      "seed 004: tool-life consumption against plan (∫dt/T over time-in-cut/T_plan), within 15 %",
      ratio, std::abs(ratio - 1.0) <= 0.15);
  claims.note(
      "of that, hardness (tool-life factor " +
      fmt(m2.tool_life_used_fraction / m2.tool_life_used_nominal_hardness_fraction, "%.3f") +
      "; T ∝ h^(−n_v/m), the handbook's K_mv): at nominal hardness the same run uses " +
      fmt(m2.tool_life_used_nominal_hardness_fraction / m2.tool_life_plan_fraction, "%.3f") +
      "× the plan. No speed law that sees only force and feed can tell hardness from "
      "depth; seed 004's raises the speed where hardness has lowered the feed");
}

void EStudy::fault_claims(Claims& claims) const {
  const Metrics& m = main().m;
  // (1 ns of slack: the delay is a difference of step times)
  claims.check("sensor fault: feed held, delay after the fault [s] (≤ one control period " +
                   fmt(e().controller.period_s) + " s)",
               m.feed_hold_delay_s, Compare::AtMost, e().controller.period_s + 1e-9);
  claims.add("sensor fault: alarm raised with a reason code (code)",
             m.alarms.empty() ? std::nan("") : static_cast<double>(m.alarms.front().code),
             !m.alarms.empty());
}

void EStudy::summary(json& s) {
  s["label"] = main().label;
  s["metrics"] = metrics_json(main(), unit_, st_.cost);
  json cmp = json::array();
  for (std::size_t i = 1; i < runs_.size(); ++i)
    cmp.push_back(
        {{"label", runs_[i]->label}, {"metrics", metrics_json(*runs_[i], unit_, st_.cost)}});
  if (!cmp.empty()) s["comparisons"] = cmp;
  // The user's part is the main run's (the comparisons are for reference).
  const Metrics& m = main().m;
  Acceptance acceptance(st_.acceptance);
  const double nan = std::nan("");
  acceptance.judge("max_force_over_limit_pct", m.time_in_cut_s > 0.0 ? m.force_overshoot_pct : nan);
  acceptance.judge("max_cycle_time_s", m.finished ? m.cycle_time_s : nan);
  acceptance.judge("max_tool_life_used_pct", 100.0 * m.tool_life_used_fraction);
  s["acceptance"] = acceptance.json();
}

void EStudy::report(Report& rep) {
  rep.title = "System E — " + sc_.name;
  rep.doc_page = "system-e-adaptive.md";
  rep.subtitle =
      sc_.file + " · " + main().label +
      (runs_.size() > 1 ? " against " + std::to_string(runs_.size() - 1) + " other controller(s)"
                        : "");
  report_metrics(rep);
  rep.tables.push_back(controllers_table());
  if (runs_.size() > 1 || tradeoff_) rep.tables.push_back(cost_table());
  if (!depths().empty()) rep.tables.push_back(depth_table_);
  reasons_table(rep);
  if (!depths().empty()) rep.plots.push_back(depth_plot_);
  run_plots(rep);
}

void EStudy::report_metrics(Report& rep) const {
  const Metrics& m = main().m;
  auto add = [&](const std::string& k, double v, const char* f = "%.4g") {
    rep.metrics.emplace_back(k, fmt(v, f));
  };
  // An unfinished part has no cycle time: the run stopped at run.duration_s.
  if (m.finished)
    add("cycle time [s]", m.cycle_time_s);
  else
    rep.metrics.emplace_back("cycle time [s]", "part not finished: the run stopped at " +
                                                   fmt(m.cycle_time_s, "%.1f") + " s");
  add("time in cut [s]", m.time_in_cut_s);
  add(pname_ + " limit [" + unit_ + "]", m.load_limit);
  add("peak per-revolution " + pname_ + " [" + unit_ + "]", m.force_peak_rev_mean);
  add("peak " + pname_ + " incl. runout within a revolution [" + unit_ + "]", m.force_peak);
  add("steady cutting within 5 % of the limit [share]", m.force_within_5pct_fraction, "%.3f");
  add("tool life used [share of one edge]", m.tool_life_used_fraction, "%.4f");
  add("planned tool life T(V_p, S_p, t_p) [min]", m.tool_life_planned_min);
  add("tool life at plan for the time in cut [share]", m.tool_life_plan_fraction, "%.4f");
  add("material removed [cm³]", m.material_removed_cm3);
  add("removal rate [cm³/min]", m.mrr_cm3_per_min);
  add("mean feed in cut [mm/rev]", m.feed_mean_mm_per_rev);
  add("programmed feed [mm/rev]", m.feed_programmed_mm_per_rev);
  add("mean cutting speed in cut [m/min]", m.speed_mean_m_per_min);
  add("peak spindle input power (electrical, incl. acceleration) [kW]", m.spindle_power_peak_kW);
  for (const auto& a : m.alarms)
    rep.metrics.emplace_back("alarm at " + fmt(a.time_s) + " s",
                             alarm_name(a) + " (code " + std::to_string(a.code) + ")");
}

Table EStudy::controllers_table() const {
  Table t{"Controllers on this part",
          {"controller", "cycle [s]", "feed [mm/rev]", "V [m/min]", "life used", "plan",
           "used/plan", "peak F_rev [" + unit_ + "]", "within 5 %"},
          {}};
  for (const auto& r : runs_) {
    const Metrics& m = r->m;
    t.rows.push_back(
        {short_name(r->mode) + (r->mode == Mode::Fixed
                                    ? " (s = " + fmt(m.feed_programmed_mm_per_rev, "%.3f") + ")"
                                    : ""),
         cycle_cell(m), fmt(m.feed_mean_mm_per_rev, "%.3f"), fmt(m.speed_mean_m_per_min, "%.1f"),
         fmt(m.tool_life_used_fraction, "%.4f"), fmt(m.tool_life_plan_fraction, "%.4f"),
         fmt(m.tool_life_used_fraction / m.tool_life_plan_fraction, "%.3f"),
         fmt(m.force_peak_rev_mean, "%.0f"), fmt(m.force_within_5pct_fraction, "%.3f")});
  }
  return t;
}

// Each controller's cost per part and, with the trade-off, the prior art at seed 004's budget.
Table EStudy::cost_table() const {
  const Cost& cost = st_.cost;
  Table t{"Cost per part: machine time at " + fmt(cost.machine_rate_per_h) + "/h, an edge " +
              fmt(cost.tool_edge_cost) + " + " + fmt(cost.tool_change_min) + " min to change it",
          {"controller", "cycle [s]", "edge used", "machine", "tool", "cost per part"},
          {}};
  for (const auto& r : runs_) {
    const PartCost pc = part_cost(r->m, cost);
    t.rows.push_back({r->label, cycle_cell(r->m), fmt(r->m.tool_life_used_fraction, "%.4f"),
                      fmt(pc.machine, "%.3f"), fmt(pc.tool, "%.3f"), fmt(pc.total, "%.3f")});
  }
  if (tradeoff_) {
    const PartCost pc = part_cost(budget_.m, cost);
    t.rows.push_back(
        {"prior art at V = " + fmt(budget_speed(), "%.1f") + " m/min (seed 004's tool budget)",
         fmt(budget_.m.cycle_time_s, "%.1f"), fmt(budget_.m.tool_life_used_fraction, "%.4f"),
         fmt(pc.machine, "%.3f"), fmt(pc.tool, "%.3f"), fmt(pc.total, "%.3f")});
  }
  return t;
}

// Decisions of the main run, by reason code: how long each held, how often, first and last.
void EStudy::reasons_table(Report& rep) const {
  Table rt{"Decisions of the main run (reason codes, from the recorded timeline)",
           {"reason", "code", "total time [s]", "episodes", "first at [s]", "last at [s]"},
           {}};
  for (const auto& a : main().acc->reasons())
    rt.rows.push_back({std::string(control::reason_name(static_cast<control::Reason>(a.code))),
                       std::to_string(a.code), fmt(a.total_s, "%.2f"), std::to_string(a.episodes),
                       fmt(a.first_s, "%.2f"), fmt(a.last_s, "%.2f")});
  if (!rt.rows.empty()) rep.tables.push_back(rt);
}

// The controllers compared along the part and the main run's detail, marked with its faults
// and alarms.
void EStudy::run_plots(Report& rep) const {
  std::vector<Marker> mk;
  for (const auto& f : e().faults) mk.push_back({f.at_s, "sensor fault"});
  for (const auto& a : main().m.alarms) mk.push_back({a.time_s, "alarm: " + alarm_name(a)});
  std::vector<PlotRun> plot_runs;
  for (const auto& r : runs_)
    plot_runs.push_back({&r->rig.recorder(), r->path.get(), r->acc.get(), &r->m, r->label,
                         r->mode == Mode::ForceFeedSpeed});
  add_run_plots(rep, plot_runs, mk, pname_, unit_);
}

void EStudy::finish(RunOutput& out) {
  // In memory only without a stage (library callers, tests); else on disk already.
  out.channels_csv = main().csv->take_text();
  out.channels_values = main().csv->take_values();
  if (runs_.size() > 1) out.compare_csv = runs_[1]->csv->take_text();
  const Metrics& m = main().m;
  out.headline = main().label + ": " + cycle_phrase(m) + ", tool life used " +
                 fmt(m.tool_life_used_fraction, "%.4f") + " (plan " +
                 fmt(m.tool_life_plan_fraction, "%.4f") + "), peak per-rev " + pname_ + " " +
                 fmt(m.force_peak_rev_mean, "%.0f") + " " + unit_;
  for (std::size_t i = 1; i < runs_.size(); ++i)
    out.headline += "; " + runs_[i]->label + " " + cycle_phrase(runs_[i]->m);
}
}  // namespace detail

io::RunOutput run(const io::Scenario& sc) {
  // The rig cuts the scenario's passes; a scenario may leave them out when a program's path
  // cuts the blank (lathectl optimize, LinuxCNC).
  if (sc.get<Settings>().rig.stock.passes.empty()) {
    const std::string msg =
        "lathectl run cuts the scenario's passes: add [[stock.passes]] {z_start_mm, z_end_mm, "
        "diameter_mm} (lathectl optimize and LinuxCNC take the path from the program and need "
        "none)";
    if (sc.keys) sc.keys->fail("stock.passes", msg);
    throw io::InputError(io::located(sc.file, 0, 0, msg));
  }
  return detail::EStudy(sc).run();
}

}  // namespace lathectl::systems::e_adaptive
