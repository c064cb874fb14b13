#include "systems/b_chatter/study.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <thread>

#include "lathectl/dynamics/van_der_pol.hpp"
#include "lathectl/io/channel_stream.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/study.hpp"
#include "lathectl/io/verdict.hpp"
#include "lathectl/sim/parallel.hpp"
#include "systems/b_chatter/metrics.hpp"
#include "systems/b_chatter/settings.hpp"

namespace lathectl::b_chatter {

namespace {
using io::Claims;
using io::Compare;
using io::fmt;
using io::json_number;
using io::Plot;
using io::Series;
using io::Table;
using nlohmann::json;

// The rig records streamed (its memory bounded whatever the cut's length): the measures are taken
// row by row, csv (nullptr: none) is written into `stage` as the rows come. Without csv the run is
// only measured (the sweep): no plots are kept either.
void run_one(const io::Scenario& sc, const sim::RigBConfig& cfg, Run& r, io::OutputStage* stage,
             const char* csv = nullptr) {
  r.rig.set_streamed(true, csv != nullptr);
  io::configure_rig(sc, r.rig, cfg);
  try {  // the disk-space checks: channels.csv first, then the window's rows
    if (csv)
      r.csv =
          io::open_channel_stream(stage, csv, r.rig.recorder().channels(), r.rig.max_record_rows());
    r.measure = std::make_unique<Measure>(r.rig, cfg.setup != sim::TwinSetup::Single, stage);
  } catch (const std::invalid_argument& e) {
    io::throw_at_key(sc, e);
  }
  r.rig.attach(r.measure.get());
  if (r.csv) r.rig.attach(r.csv.get());
  io::run_rig(sc, r.rig, "|y| > 50 mm");
  if (r.csv) r.csv->finish();
  r.measure->result(r, cfg.vibration.dead_zone_m * 1e6);
}

std::string source_name(control::ModulationSource s) {
  return s == control::ModulationSource::Automatic    ? "automatic module"
         : s == control::ModulationSource::Programmed ? "programmed modulation"
                                                      : "no modulation";
}

}  // namespace

io::RunOutput run(const io::Scenario& sc) {
  const Settings& settings = sc.get<Settings>();
  const sim::RigBConfig& b = settings.rig;
  const bool twin = b.setup != sim::TwinSetup::Single;
  const bool modulated = b.source != control::ModulationSource::None;
  auto with = std::make_unique<Run>();
  auto without = std::make_unique<Run>();
  with->label = source_name(b.source);
  without->label = "no modulation";
  const bool compared = modulated && settings.compare;
  io::OutputStage* stage = io::StreamScope::current();  // this thread's: the runs use other ones
  {
    // The run as programmed and, to compare, the same without modulation: side by side (the one
    // on the calling thread moves its progress line; both are as long).
    // channels.csv and channels_compare.csv stream into the output set's stage as they record.
    sim::RigBConfig off = b;
    off.source = control::ModulationSource::None;
    sim::parallel_for(
        compared ? 2 : 1,
        [&](std::size_t i) {
          i == 0 ? run_one(sc, b, *with, stage, "channels.csv")
                 : run_one(sc, off, *without, stage, "channels_compare.csv");
        },
        2);
  }
  const Run& main = *with;
  const Run* off = compared ? without.get() : (modulated ? nullptr : with.get());

  // Sweep over feeds: with and without, in parallel on the machine's cores.
  struct SweepPoint {
    double feed = 0.0;
    Run on, off;
  };
  std::vector<std::unique_ptr<SweepPoint>> sweep;
  for (double f : settings.sweep_feed_mm_per_rev) {
    sweep.push_back(std::make_unique<SweepPoint>());
    sweep.back()->feed = f;
  }
  if (!sweep.empty()) {
    // Job j: feed j/2, with (even) or without (odd) modulation; each writes its own run.
    const unsigned threads = std::max(1u, std::min(4u, std::thread::hardware_concurrency()));
    sim::parallel_for(
        2 * sweep.size(),
        [&](std::size_t j) {
          SweepPoint& p = *sweep[j / 2];
          sim::RigBConfig c = b;
          c.feed_mm_per_rev = p.feed;
          if (j % 2 == 1) c.source = control::ModulationSource::None;
          if (c.source == control::ModulationSource::None && j % 2 == 0 && !modulated) return;
          run_one(sc, c, j % 2 ? p.off : p.on, stage);
        },
        threads);
  }

  // Linear limits at the softest position of the cut (the modes follow the tool).
  Limits lim;
  double lim_x = b.z_start_mm;
  for (int k = 0; k <= 10; ++k) {
    const double x = b.z_start_mm + (b.z_end_mm - b.z_start_mm) * k / 10.0;
    const Limits l = linear_limits(b, x, b.rpm);
    const double key =
        twin && b.setup == sim::TwinSetup::FeedDivision ? l.twin_feed : l.single_feed;
    const double best =
        twin && b.setup == sim::TwinSetup::FeedDivision ? lim.twin_feed : lim.single_feed;
    if (std::isnan(best) || key < best) {
      lim = l;
      lim_x = x;
    }
  }
  // Van der Pol: the measured quenching threshold against averaging theory and the seed.
  const double vdp_B = dynamics::quenching_threshold(0.1, 5.0);  // a0 = 2

  const double s_prog = b.feed_mm_per_rev * b.rpm;  // mm/min per turret
  const double dead_zone_um = b.vibration.dead_zone_m * 1e6;
  const auto& mo = main.rig.module_output();
  const int t = static_cast<int>(b.turret);

  io::RunOutput out;
  json& s = out.summary;
  s["system"] = sc.system;
  s["scenario"] = sc.name;
  s["file"] = sc.file;
  s["label"] = main.label;
  json vib = {{"with", json_number(main.vibration_um)}};
  if (off) vib["without"] = json_number(off->vibration_um);
  if (!modulated) vib = {{"without", json_number(main.vibration_um)}};
  json forced = {{"with", json_number(main.forced_um)}};
  if (off) forced["without"] = json_number(off->forced_um);
  if (!modulated) forced = {{"without", json_number(main.forced_um)}};
  json bent = {{"with", json_number(main.static_um)}};
  if (off) bent["without"] = json_number(off->static_um);
  if (!modulated) bent = {{"without", json_number(main.static_um)}};
  const Run& chat = off ? *off : main;
  s["metrics"] = {
      {"vibration_amplitude_um", vib},
      {"forced_deflection_um", forced},
      {"static_deflection_um", bent},
      {"chatter_frequency_Hz", json_number(chat.chatter_Hz)},
      {"modulation",
       {{"S_min_mm_per_min", mo.plan.s_min_mm_per_min},
        {"dS_mm_per_min", mo.plan.ds_mm_per_min},
        {"dl_mm", mo.plan.dl_mm},
        {"n_s", mo.plan.n_s},
        {"S_max_mm_per_min", mo.plan.active() ? mo.plan.s_max_mm_per_min() : 0.0},
        {"omega_m_Hz", mo.omega_m_rad_per_s / (2.0 * std::numbers::pi)},
        {"turret", t == 0 ? "right" : "left"},
        {"engaged", mo.engaged},
        {"engaged_at_s",
         json_number(main.rig.engaged_at_s() >= 0 ? main.rig.engaged_at_s() : kNaN)},
        {"force_amplitude_required_N", mo.force_amplitude_required_N},
        {"force_amplitude_planned_N", mo.force_amplitude_planned_N},
        {"reason", std::string(control::reason_name(mo.reason))}}},
      {"mean_feed_mm_per_min",
       {{"programmed", s_prog},
        {"right", main.feed_mean[0]},
        {"left", twin ? json_number(main.feed_mean[1]) : json(nullptr)}}},
      {"cutting_power_W", {{"true", main.cut_power_W}, {"measured", main.cut_power_measured_W}}},
      {"one_turret_out_of_cut_share",
       modulated ? json{{"with", main.one_out_share},
                        {"without", off ? json_number(off->one_out_share) : json(nullptr)}}
                 : json{{"without", main.one_out_share}}},
      {"linear_limits",
       {{"at_mm", lim_x},
        {"single_tool_feed_mm_per_rev", json_number(lim.single_feed)},
        {"feed_division_feed_mm_per_rev", json_number(lim.twin_feed)},
        {"chatter_Hz", json_number(lim.chatter_Hz)},
        {"programmed_feed_mm_per_rev", b.feed_mm_per_rev}}},
      {"quenching_check",
       {{"van_der_pol_threshold_B_over_a0", vdp_B / 2.0},
        {"averaging_theory", 1.0 / std::numbers::sqrt2},
        {"seed_coefficient", b.seed_coefficient}}}};
  // The quenching condition under both readings of the seed's 1.41, for the a0 the module
  // planned on (just above the dead zone, chatter still growing) and for the document's a0, the
  // steady amplitude without modulation. K = a0·m_d·|ω_d² − ω_m²|: the module's
  // required force is c·K (multiply) or K/c (divide).
  const double c_seed = b.seed_coefficient;
  const bool automatic_engaged = b.source == control::ModulationSource::Automatic && mo.engaged;
  double k_planned = kNaN, k_steady = kNaN, a0_steady_um = kNaN;
  if (automatic_engaged) {
    k_planned = mo.force_amplitude_required_N / b.module_coefficient();
    if (off && std::isfinite(off->chatter_Hz)) {
      const double wd = 2.0 * std::numbers::pi * off->chatter_Hz;
      const double wm = mo.omega_m_rad_per_s;
      a0_steady_um = off->vibration_um;
      k_steady = a0_steady_um * 1e-6 * b.module.part_mass_kg * std::abs(wd * wd - wm * wm);
    }
    auto reading = [&](double k, double a0_um) {
      return json{{"a0_um", json_number(a0_um)},
                  {"required_multiply_N", json_number(c_seed * k)},
                  {"required_divide_N", json_number(k / c_seed)},
                  {"ratio_multiply", json_number(mo.force_amplitude_planned_N / (c_seed * k))},
                  {"ratio_divide", json_number(mo.force_amplitude_planned_N * c_seed / k)}};
    };
    const double wd_plan =
        off && std::isfinite(off->chatter_Hz) ? 2.0 * std::numbers::pi * off->chatter_Hz : kNaN;
    const double a0_plan_um =
        k_planned /
        (b.module.part_mass_kg * std::abs(wd_plan * wd_plan -
                                          mo.omega_m_rad_per_s * mo.omega_m_rad_per_s)) *
        1e6;
    s["metrics"]["quenching_condition"] = {
        {"reading", b.seed_divides ? "divide" : "multiply"},
        {"planned_N", mo.force_amplitude_planned_N},
        {"at_planned_a0", reading(k_planned, a0_plan_um)},
        {"at_steady_a0", reading(k_steady, a0_steady_um)}};
  }
  if (b.setup == sim::TwinSetup::DepthDivision) {
    const auto& pc = main.rig.process();
    s["metrics"]["inter_tool_delay"] = {
        {"model", b.inter_tool_delay == dynamics::InterToolDelay::Fixed ? "fixed"
                                                                         : "axial_positions"},
        {"min_rev", json_number(main.delay_min_rev)},
        {"max_rev", json_number(main.delay_max_rev)},
        {"uncut_reads", pc.uncut_reads()},
        {"clipped_reads", pc.clipped_reads()}};
  }
  if (b.process_damping.on())
    s["metrics"]["process_damping"] = {
        {"model", "indentation"},
        {"K_sp_N_per_mm3", b.process_damping.k_sp_N_per_m3 * 1e-9},
        {"wear_land_mm", b.process_damping.wear_land_mm},
        {"clearance_deg", b.process_damping.clearance_deg},
        {"linear_equivalent_N_s_per_m",
         b.process_damping.k_sp_N_per_m3 * b.depth_mm[0] * 1e-3 *
             std::pow(b.process_damping.wear_land_mm * 1e-3, 2) /
             (4.0 * std::numbers::pi * b.part.diameter_m * b.rpm / 60.0)}};
  if (!sweep.empty()) {
    json sw = json::array();
    for (const auto& p : sweep)
      sw.push_back({{"feed_mm_per_rev", p->feed},
                    {"without_um", p->off.vibration_um},
                    {"with_um", json_number(modulated ? p->on.vibration_um : kNaN)},
                    {"mean_feed_ratio", modulated && p->feed > 0
                                            ? json_number(p->on.feed_mean[t] / (p->feed * b.rpm))
                                            : json(nullptr)}});
    s["metrics"]["sweep"] = sw;
  }

  {  // The user's cut is the main run's (with its modulation, if any).
    io::Acceptance acceptance(settings.acceptance);
    acceptance.judge("max_vibration_um", main.vibration_um);
    if (modulated) acceptance.judge("min_mean_feed_pct", 100.0 * main.feed_mean[t] / s_prog);
    s["acceptance"] = acceptance.json();
  }

  Claims claims;
  if (compared)
    claims.check(
        "without modulation the part chatters: steady vibration [µm] above the dead zone (" +
            fmt(dead_zone_um) + " µm)",
        off->vibration_um, Compare::Above, dead_zone_um);
  else if (!modulated)
    claims.note("No modulation in this scenario: steady vibration " +
                fmt(main.vibration_um, "%.3g") + " µm against the dead zone of " +
                fmt(dead_zone_um) + " µm — the part " +
                (main.vibration_um > dead_zone_um ? "chatters." : "does not chatter."));
  if (modulated && off) {
    const double ratio = off->vibration_um / std::max(main.vibration_um, 1e-9);
    claims.add("with " + main.label + ": vibration below the dead zone or reduced ≥ 5× (ratio)",
               ratio, main.vibration_um < dead_zone_um || ratio >= 5.0);
  }
  if (modulated) {
    const double fr = main.feed_mean[t] / s_prog;
    claims.check("mean feed of the modulated turret / programmed (within 10 %)", fr,
                 Compare::RatioWithin, 0.1);
  }
  if (b.source == control::ModulationSource::Automatic && mo.engaged) {
    claims.check("quenching condition: planned A_P / required c·a0·m_d·|ω_d² − ω_m²| (" +
                     fmt(mo.force_amplitude_planned_N) + " N of " +
                     fmt(mo.force_amplitude_required_N) + " N)",
                 mo.force_amplitude_planned_N / std::max(mo.force_amplitude_required_N, 1e-12),
                 Compare::AtLeast, 1.0 - 1e-3);
    if (mo.force_amplitude_planned_N < mo.force_amplitude_required_N)
      claims.note(
          "The quenching condition asks for a force swing of " +
          fmt(mo.force_amplitude_required_N) +
          " N against the measured a0; feed modulation between S_min and S_max can swing the "
          "radial "
          "force by " +
          fmt(mo.force_amplitude_planned_N) +
          " N at most. A forced vibration of the size the condition wants (≈ a0) would itself be "
          "as large as the chatter: asynchronous quenching is not what a feed drive can do on this "
          "part.");
  }
  claims.note(
      "Van der Pol check: forced amplitude at which a small self-excited oscillation stops "
      "growing, measured " +
      fmt(vdp_B / 2.0, "%.4f") + "·a0; averaging theory a0/√2 = 0.7071·a0; the seed asks " +
      fmt(b.module_coefficient()) + "·a0 (a " +
      fmt(b.module_coefficient() * std::numbers::sqrt2, "%.2f") + "× margin).");
  if (automatic_engaged)
    claims.note(
        "The seed's 1.41, read both ways (coefficient_reading = \"" +
        std::string(b.seed_divides ? "divide" : "multiply") +
        "\" here). At the a0 the module planned on (just above the dead zone): required " +
        fmt(c_seed * k_planned) + " N multiplying, " + fmt(k_planned / c_seed) +
        " N dividing, against " + fmt(mo.force_amplitude_planned_N) + " N planned (ratio " +
        fmt(mo.force_amplitude_planned_N / (c_seed * k_planned), "%.2f") + " or " +
        fmt(mo.force_amplitude_planned_N * c_seed / k_planned, "%.2f") +
        ")." +
        (std::isfinite(k_steady)
             ? " At the document's a0, the steady amplitude without modulation (" +
                   fmt(a0_steady_um, "%.0f") + " µm): " + fmt(c_seed * k_steady, "%.0f") +
                   " N or " + fmt(k_steady / c_seed, "%.0f") + " N (ratio " +
                   fmt(mo.force_amplitude_planned_N / (c_seed * k_steady), "%.3f") + " or " +
                   fmt(mo.force_amplitude_planned_N * c_seed / k_steady, "%.3f") +
                   "): the document's rule, read either way, asks a feed drive for a force "
                   "swing it cannot make once chatter is developed."
             : std::string()));
  if (b.setup == sim::TwinSetup::DepthDivision &&
      b.inter_tool_delay == dynamics::InterToolDelay::AxialPositions)
    claims.note("Inter-tool delay from the tools' axial positions: tool 2 met the surface tool 1 "
                "left " +
                fmt(main.delay_min_rev, "%.2f") + " … " + fmt(main.delay_max_rev, "%.2f") +
                " revolutions earlier over the steady window (frozen model: round(lag/s) + ½ = " +
                fmt(std::round(b.tool2_lag_mm / b.feed_mm_per_rev) + 0.5, "%.1f") + ").");
  if (b.process_damping.on())
    claims.note("Process damping (flank indentation, K_sp = " +
                fmt(b.process_damping.k_sp_N_per_m3 * 1e-9, "%.3g") + " N/mm³, VB = " +
                fmt(b.process_damping.wear_land_mm) + " mm, γ = " +
                fmt(b.process_damping.clearance_deg) + "°) is on: beyond the seed's model.");
  if (b.setup == sim::TwinSetup::FeedDivision)
    claims.note("Linear limits at z = " + fmt(lim_x) + " mm, " + fmt(b.rpm) +
                " rpm: feed division chatters above s = " + fmt(lim.twin_feed, "%.3f") +
                " mm/rev (each tool s/2 of the surface the other left half a turn earlier); one "
                "tool alone above s = " +
                fmt(lim.single_feed, "%.3f") +
                " mm/rev. Programmed s = " + fmt(b.feed_mm_per_rev, "%.3f") + " mm/rev.");
  else
    claims.note("Linear limit at z = " + fmt(lim_x) + " mm, " + fmt(b.rpm) +
                " rpm, one tool's own regeneration: s = " + fmt(lim.single_feed, "%.3f") +
                " mm/rev; programmed s = " + fmt(b.feed_mm_per_rev, "%.3f") + " mm/rev.");
  if (modulated && twin)
    claims.note(
        "With modulation one turret was out of the cut for " +
        fmt(100.0 * main.one_out_share, "%.0f") + " % of the steady window (without: " +
        (off ? fmt(100.0 * off->one_out_share, "%.0f") : std::string("—")) +
        " %): the modulated turret falls behind or runs ahead of the other by more than half "
        "the feed per revolution, the other takes the whole chip, and the summed "
        "regenerative gain drops from 2·g(s/2) to g(s) = 2^−(1−m)·2·g(s/2). Its price: the "
        "radial forces no longer balance — mean deflection " +
        fmt(main.static_um) + " µm with, " + (off ? fmt(off->static_um) : std::string("—")) +
        " µm without (a diameter error of twice that), swinging ±" + fmt(main.forced_um) +
        " µm with the modulation. A fixed axial offset of the turrets by more than s/2 does the "
        "same without any modulation (b_twin_offset).");
  s["claims"] = claims.json();

  io::Report& rep = out.report;
  rep.title = "System B — " + sc.name;
  rep.doc_page = "system-b-chatter.md";
  rep.subtitle = sc.file + " · " + main.label +
                 (b.setup == sim::TwinSetup::FeedDivision    ? " · feed division"
                  : b.setup == sim::TwinSetup::DepthDivision ? " · depth division"
                                                             : " · one tool");
  rep.description = sc.description;
  auto add = [&](const std::string& k, double v, const char* f = "%.4g") {
    rep.metrics.emplace_back(k, fmt(v, f));
  };
  if (off) add("vibration, no modulation [µm]", off->vibration_um);
  if (modulated) add("vibration, " + main.label + " [µm]", main.vibration_um);
  add("dead zone [µm]", dead_zone_um);
  add("chatter frequency [Hz]", chat.chatter_Hz);
  add("programmed feed per turret [mm/min]", s_prog);
  if (modulated) {
    add("mean feed, modulated turret [mm/min]", main.feed_mean[t]);
    add("S_min [mm/min]", mo.plan.s_min_mm_per_min);
    add("ΔS [mm/min]", mo.plan.ds_mm_per_min);
    add("Δl [mm]", mo.plan.dl_mm);
    add("n_s", mo.plan.n_s, "%.0f");
    add("ω_m/2π [Hz]", mo.omega_m_rad_per_s / (2.0 * std::numbers::pi));
    add("A_P required [N]", mo.force_amplitude_required_N);
    add("A_P planned [N]", mo.force_amplitude_planned_N);
  }
  add("forced deflection (below the chatter band) [µm]", main.forced_um);
  add("static deflection (mean y) [µm]", main.static_um);
  add("cutting power (true) [W]", main.cut_power_W);
  add("cutting power measured N_c [W]", main.cut_power_measured_W);
  rep.notes = claims.notes();
  rep.note_ids = claims.note_ids();

  const char* colors[] = {"#d62728", "#1f77b4"};
  auto series = [&](const Run& r, const char* col, const std::string& name, const char* color,
                    bool dashed = false) {
    return io::recorded_series(r.rig.recorder(), col, name, color, dashed);
  };
  // The unmodulated run chatters at hundreds of µm, the modulated one stays near 0.1 µm: each
  // gets its own panel (same time axis), or the smaller would be a flat line beside the other.
  const std::vector<const Run*> panels =
      off && off != &main ? std::vector<const Run*>{off, &main} : std::vector<const Run*>{&main};
  double t_end = 0.0;
  for (const Run* r : panels) t_end = std::max(t_end, r->t_end);
  const auto panel = [&](std::string title, std::string y_label) {
    Plot p{std::move(title), "time [s]", std::move(y_label), {}, {}};
    p.x_min = 0.0;
    p.x_max = t_end;
    return p;
  };
  for (std::size_t k = 0; k < panels.size(); ++k) {
    const Run& r = *panels[k];
    const char* color = colors[panels.size() == 2 ? k : 1];
    Plot p = panel("Part displacement at the tool, " + r.label, "y [µm]");
    p.series.push_back(series(r, "y_um", r.label, color));
    if (r.rig.engaged_at_s() >= 0.0) p.markers.push_back({r.rig.engaged_at_s(), "engaged"});
    p.markers.push_back({r.t0, "steady window"});
    rep.plots.push_back(p);
  }
  for (std::size_t k = 0; k < panels.size(); ++k) {
    const Run& r = *panels[k];
    Plot p = panel("Chatter band (high-pass " + fmt(b.vibration.highpass_Hz) + " Hz), " + r.label,
                   "y_hp [µm]");
    p.series.push_back(series(r, "y_highpass_um", r.label, colors[panels.size() == 2 ? k : 1]));
    rep.plots.push_back(p);
  }
  if (modulated) {
    Plot p{"Feed rates (" + main.label + ")", "time [s]", "feed [mm/min]", {}, {}};
    p.series.push_back(series(main, "feed1_mm_per_min", "right turret", "#2ca02c"));
    if (twin) p.series.push_back(series(main, "feed2_mm_per_min", "left turret", "#9467bd"));
    rep.plots.push_back(p);
    Plot c{"Chip per tool (" + main.label + ")", "time [s]", "chip [mm]", {}, {}};
    c.series.push_back(series(main, "chip1_mm", "right", "#2ca02c"));
    if (twin) c.series.push_back(series(main, "chip2_mm", "left", "#9467bd"));
    rep.plots.push_back(c);
  }
  {
    // Two panels: the amplitude in µm and the detected frequency in Hz share no axis.
    const Run& r = off && off != &main ? *off : main;
    Plot a0 = panel("Measurement chain: amplitude a0 (ADC 19), " + r.label, "a0 [µm]");
    a0.series.push_back(series(r, "a0_um", "a0, " + r.label, "#ff7f0e"));
    rep.plots.push_back(a0);
    Plot wd = panel("Measurement chain: frequency ω_d/2π (detector 20), " + r.label, "f [Hz]");
    wd.series.push_back(series(r, "omega_d_Hz", "ω_d/2π, " + r.label, "#8c564b"));
    rep.plots.push_back(wd);
  }
  {
    Plot p{"Cutting power: true and measured (N_m − N_idle)", "time [s]", "power [W]", {}, {}};
    p.series.push_back(series(main, "cut_power_W", "true", "#555"));
    p.series.push_back(series(main, "cut_power_measured_W", "measured N_c", "#17becf"));
    rep.plots.push_back(p);
  }
  {
    // The machine's own stability chart at the softest position of the cut: the feed per
    // revolution above which the regenerative loop is unstable, against the spindle speed.
    Plot p{"Stability limits at z = " + fmt(lim_x) + " mm (linear, the set-up's delay equation)",
           "spindle speed [rpm]",
           "feed per revolution [mm/rev]",
           {},
           {}};
    Series one{"one tool (τ, +μ)", {}, {}, "#1f77b4", false, false};
    Series two{"feed division (τ/2, −μ)", {}, {}, "#d62728", false, false};
    for (int k = 0; k <= 160; ++k) {
      const double n = b.rpm * (0.7 + 0.6 * k / 160.0);
      const Limits l = linear_limits(b, lim_x, n, 6000);
      one.x.push_back(n);
      one.y.push_back(l.single_feed);
      if (std::isfinite(l.twin_feed)) {
        two.x.push_back(n);
        two.y.push_back(l.twin_feed);
      }
    }
    p.series.push_back(one);
    if (!two.x.empty()) p.series.push_back(two);
    p.series.push_back({"programmed", {b.rpm}, {b.feed_mm_per_rev}, "#000", false, true});
    p.markers.push_back({b.rpm, "programmed speed"});
    rep.plots.push_back(p);
  }
  if (!sweep.empty()) {
    Plot p{
        "Steady vibration against the programmed feed", "feed [mm/rev]", "vibration [µm]", {}, {}};
    p.log_y = true;  // from 0.001 µm (modulated, stable) to hundreds of µm (chatter)
    Series s0{"no modulation", {}, {}, colors[0], false, true},
        s1{main.label, {}, {}, colors[1], false, true};
    Table tb{"Sweep over the feed",
             {"feed [mm/rev]", "no modulation [µm]", main.label + " [µm]", "ratio",
              "mean feed / programmed"},
             {}};
    for (const auto& q : sweep) {
      s0.x.push_back(q->feed);
      s0.y.push_back(q->off.vibration_um);
      if (modulated) {
        s1.x.push_back(q->feed);
        s1.y.push_back(q->on.vibration_um);
      }
      tb.rows.push_back(
          {fmt(q->feed, "%.3f"), fmt(q->off.vibration_um, "%.3g"),
           modulated ? fmt(q->on.vibration_um, "%.3g") : "—",
           modulated ? fmt(q->off.vibration_um / std::max(q->on.vibration_um, 1e-9), "%.3g") : "—",
           modulated ? fmt(q->on.feed_mean[t] / (q->feed * b.rpm), "%.3f") : "—"});
    }
    p.series.push_back(s0);
    if (modulated) p.series.push_back(s1);
    if (std::isfinite(lim.twin_feed)) p.markers.push_back({lim.twin_feed, "feed-division limit"});
    if (std::isfinite(lim.single_feed)) p.markers.push_back({lim.single_feed, "one-tool limit"});
    rep.plots.push_back(p);
    rep.tables.push_back(tb);
  }

  // In memory only without a stage (library callers, tests); else on disk already.
  out.channels_csv = main.csv->take_text();
  if (compared) out.compare_csv = without->csv->take_text();
  out.headline =
      (off ? "no modulation " + fmt(off->vibration_um, "%.3g") + " µm" : std::string()) +
      (modulated ? (off ? "; " : "") + main.label + " " + fmt(main.vibration_um, "%.3g") +
                       " µm, mean feed " + fmt(main.feed_mean[t] / s_prog, "%.3f") + "× programmed"
                 : std::string());
  return out;
}

}  // namespace lathectl::b_chatter
