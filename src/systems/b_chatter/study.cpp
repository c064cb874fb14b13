#include "systems/b_chatter/study.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <thread>

#include "lathectl/core/parallel.hpp"
#include "lathectl/dynamics/van_der_pol.hpp"
#include "lathectl/io/channel_stream.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/study.hpp"
#include "lathectl/io/verdict.hpp"
#include "systems/b_chatter/metrics.hpp"
#include "systems/b_chatter/settings.hpp"
#include "systems/b_chatter/study_phases.hpp"

namespace lathectl::systems::b_chatter {

namespace detail {

// The rig records streamed (its memory bounded whatever the cut's length): the measures are taken
// row by row, csv (nullptr: none) is written into `stage` as the rows come. Without csv the run is
// only measured (the sweep): no plots are kept either.
void run_one(const io::Scenario& sc, const RigConfig& cfg, Run& r, io::OutputStage* stage,
             const char* csv) {
  r.rig.set_streamed(true, csv != nullptr);
  io::configure_rig(sc, r.rig, cfg);
  try {  // the disk-space checks: channels.csv first, then the window's rows
    if (csv)
      r.csv =
          io::open_channel_stream(stage, csv, r.rig.recorder().channels(), r.rig.max_record_rows());
    r.measure = std::make_unique<Measure>(r.rig, cfg.setup != dynamics::TwinSetup::Single, stage);
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

void ChatterStudy::run_controllers() {
  with_->label = source_name(b_.source);
  without_->label = "no modulation";
  io::OutputStage* stage = io::StreamScope::current();  // this thread's: the runs use other ones
  // The run as programmed and, to compare, the same without modulation: side by side (the one on
  // the calling thread moves its progress line; both are as long).
  // channels.csv and channels_compare.csv stream into the output set's stage as they record.
  RigConfig off = b_;
  off.source = control::ModulationSource::None;
  core::parallel_for(
      compared_ ? 2 : 1,
      [&](std::size_t i) {
        i == 0 ? run_one(sc_, b_, *with_, stage, "channels.csv")
               : run_one(sc_, off, *without_, stage, "channels_compare.csv");
      },
      2);
  off_ = compared_ ? without_.get() : (modulated_ ? nullptr : with_.get());
  find_linear_limits();
  // A constant of the model (a0 = 2), ~10⁹ instructions: computed once per process, not per
  // run (a sweep's every case asked for it again).
  static const double vdp_B = dynamics::quenching_threshold(0.1, 5.0);
  vdp_B_ = vdp_B;
  quench_ = quenching();
}

// Linear limits at the softest position of the cut (the modes follow the tool).
void ChatterStudy::find_linear_limits() {
  lim_x_ = b_.z_start_mm;
  const bool by_twin = twin_ && b_.setup == TwinSetup::FeedDivision;
  for (int k = 0; k <= 10; ++k) {
    const double x = b_.z_start_mm + (b_.z_end_mm - b_.z_start_mm) * k / 10.0;
    const Limits l = linear_limits(b_, x, b_.rpm);
    const double key = by_twin ? l.twin_feed : l.single_feed;
    const double best = by_twin ? lim_.twin_feed : lim_.single_feed;
    if (std::isnan(best) || key < best) {
      lim_ = l;
      lim_x_ = x;
    }
  }
}

Quenching ChatterStudy::quenching() const {
  Quenching q;
  if (!automatic_engaged()) return q;
  q.k_planned = mo().force_amplitude_required_N / b_.module_coefficient();
  const double wm = mo().omega_m_rad_per_s;
  if (off_ && std::isfinite(off_->chatter_Hz)) {
    const double wd = 2.0 * std::numbers::pi * off_->chatter_Hz;
    q.a0_steady_um = off_->vibration_um;
    q.k_steady = q.a0_steady_um * 1e-6 * b_.module.part_mass_kg * std::abs(wd * wd - wm * wm);
  }
  const double wd_plan =
      off_ && std::isfinite(off_->chatter_Hz) ? 2.0 * std::numbers::pi * off_->chatter_Hz : kNaN;
  q.a0_planned_um =
      q.k_planned / (b_.module.part_mass_kg * std::abs(wd_plan * wd_plan - wm * wm)) * 1e6;
  return q;
}

// Sweep over feeds: with and without, in parallel on the machine's cores.
void ChatterStudy::extra_studies(io::RunOutput& out, Claims& /*claims*/) {
  if (st_.sweep_feed_mm_per_rev.empty()) return;
  for (double f : st_.sweep_feed_mm_per_rev) {
    sweep_.push_back(std::make_unique<SweepPoint>());
    sweep_.back()->feed = f;
  }
  // Job j: feed j/2, with (even) or without (odd) modulation; each writes its own run.
  io::OutputStage* stage = io::StreamScope::current();
  const unsigned threads = std::max(1u, std::min(4u, std::thread::hardware_concurrency()));
  core::parallel_for(
      2 * sweep_.size(),
      [&](std::size_t j) {
        SweepPoint& p = *sweep_[j / 2];
        RigConfig c = b_;
        c.feed_mm_per_rev = p.feed;
        if (j % 2 == 1) c.source = control::ModulationSource::None;
        if (c.source == control::ModulationSource::None && j % 2 == 0 && !modulated_) return;
        run_one(sc_, c, j % 2 ? p.off : p.on, stage);
      },
      threads);

  json sw = json::array();
  Plot p{"Steady vibration against the programmed feed", "feed [mm/rev]", "vibration [µm]", {}, {}};
  p.log_y = true;  // from 0.001 µm (modulated, stable) to hundreds of µm (chatter)
  Series s0{"no modulation", {}, {}, kColors[0], false, true},
      s1{main().label, {}, {}, kColors[1], false, true};
  Table tb{"Sweep over the feed",
           {"feed [mm/rev]", "no modulation [µm]", main().label + " [µm]", "ratio",
            "mean feed / programmed"},
           {}};
  for (const auto& q : sweep_) {
    const double feed_ratio = q->on.feed_mean[turret_] / (q->feed * b_.rpm);
    sw.push_back(
        {{"feed_mm_per_rev", q->feed},
         {"without_um", q->off.vibration_um},
         {"with_um", json_number(modulated_ ? q->on.vibration_um : kNaN)},
         {"mean_feed_ratio", modulated_ && q->feed > 0 ? json_number(feed_ratio) : json(nullptr)}});
    s0.x.push_back(q->feed);
    s0.y.push_back(q->off.vibration_um);
    if (modulated_) {
      s1.x.push_back(q->feed);
      s1.y.push_back(q->on.vibration_um);
    }
    tb.rows.push_back(
        {fmt(q->feed, "%.3f"), fmt(q->off.vibration_um, "%.3g"),
         modulated_ ? fmt(q->on.vibration_um, "%.3g") : "—",
         modulated_ ? fmt(q->off.vibration_um / std::max(q->on.vibration_um, 1e-9), "%.3g") : "—",
         modulated_ ? fmt(feed_ratio, "%.3f") : "—"});
  }
  out.summary["metrics"]["sweep"] = sw;
  p.series.push_back(s0);
  if (modulated_) p.series.push_back(s1);
  if (std::isfinite(lim_.twin_feed)) p.markers.push_back({lim_.twin_feed, "feed-division limit"});
  if (std::isfinite(lim_.single_feed)) p.markers.push_back({lim_.single_feed, "one-tool limit"});
  out.report.plots.push_back(p);
  out.report.tables.push_back(tb);
}

void ChatterStudy::check_claims(Claims& claims) {
  const Run& m = main();
  if (compared_)
    claims.check(
        "without modulation the part chatters: steady vibration [µm] above the dead zone (" +
            fmt(dead_zone_um_) + " µm)",
        off_->vibration_um, Compare::Above, dead_zone_um_);
  else if (!modulated_)
    claims.note("No modulation in this scenario: steady vibration " + fmt(m.vibration_um, "%.3g") +
                " µm against the dead zone of " + fmt(dead_zone_um_) + " µm — the part " +
                (m.vibration_um > dead_zone_um_ ? "chatters." : "does not chatter."));
  if (modulated_ && off_) {
    const double ratio = off_->vibration_um / std::max(m.vibration_um, 1e-9);
    claims.add("with " + m.label + ": vibration below the dead zone or reduced ≥ 5× (ratio)", ratio,
               m.vibration_um < dead_zone_um_ || ratio >= 5.0);
  }
  if (modulated_)
    claims.check("mean feed of the modulated turret / programmed (within 10 %)",
                 m.feed_mean[turret_] / s_prog_, Compare::RatioWithin, 0.1);
  quenching_claims(claims);
  setup_notes(claims);
}

void ChatterStudy::quenching_claims(Claims& claims) const {
  const auto& o = mo();
  if (automatic_engaged()) {
    claims.check("quenching condition: planned A_P / required c·a0·m_d·|ω_d² − ω_m²| (" +
                     fmt(o.force_amplitude_planned_N) + " N of " +
                     fmt(o.force_amplitude_required_N) + " N)",
                 o.force_amplitude_planned_N / std::max(o.force_amplitude_required_N, 1e-12),
                 Compare::AtLeast, 1.0 - 1e-3);
    if (o.force_amplitude_planned_N < o.force_amplitude_required_N)
      claims.note(
          "The quenching condition asks for a force swing of " + fmt(o.force_amplitude_required_N) +
          " N against the measured a0; feed modulation between S_min and S_max can swing the "
          "radial "
          "force by " +
          fmt(o.force_amplitude_planned_N) +
          " N at most. A forced vibration of the size the condition wants (≈ a0) would itself be "
          "as large as the chatter: asynchronous quenching is not what a feed drive can do on this "
          "part.");
  }
  claims.note(
      "Van der Pol check: forced amplitude at which a small self-excited oscillation stops "
      "growing, measured " +
      fmt(vdp_B_ / 2.0, "%.4f") + "·a0; averaging theory a0/√2 = 0.7071·a0; the seed asks " +
      fmt(b_.module_coefficient()) + "·a0 (a " +
      fmt(b_.module_coefficient() * std::numbers::sqrt2, "%.2f") + "× margin).");
  if (!automatic_engaged()) return;
  const double c_seed = b_.seed_coefficient;
  const auto& q = quench_;
  claims.note("The seed's 1.41, read both ways (coefficient_reading = \"" +
              std::string(b_.seed_divides ? "divide" : "multiply") +
              "\" here). At the a0 the module planned on (just above the dead zone): required " +
              fmt(c_seed * q.k_planned) + " N multiplying, " + fmt(q.k_planned / c_seed) +
              " N dividing, against " + fmt(o.force_amplitude_planned_N) + " N planned (ratio " +
              fmt(o.force_amplitude_planned_N / (c_seed * q.k_planned), "%.2f") + " or " +
              fmt(o.force_amplitude_planned_N * c_seed / q.k_planned, "%.2f") + ")." +
              (std::isfinite(q.k_steady)
                   ? " At the document's a0, the steady amplitude without modulation (" +
                         fmt(q.a0_steady_um, "%.0f") + " µm): " + fmt(c_seed * q.k_steady, "%.0f") +
                         " N or " + fmt(q.k_steady / c_seed, "%.0f") + " N (ratio " +
                         fmt(o.force_amplitude_planned_N / (c_seed * q.k_steady), "%.3f") + " or " +
                         fmt(o.force_amplitude_planned_N * c_seed / q.k_steady, "%.3f") +
                         "): the document's rule, read either way, asks a feed drive for a force "
                         "swing it cannot make once chatter is developed."
                   : std::string()));
}

// What the set-up adds: the inter-tool delay, process damping, the linear limits, the turrets.
void ChatterStudy::setup_notes(Claims& claims) const {
  const Run& m = main();
  if (b_.setup == TwinSetup::DepthDivision &&
      b_.inter_tool_delay == dynamics::InterToolDelay::AxialPositions)
    claims.note(
        "Inter-tool delay from the tools' axial positions: tool 2 met the surface tool 1 "
        "left " +
        fmt(m.delay_min_rev, "%.2f") + " … " + fmt(m.delay_max_rev, "%.2f") +
        " revolutions earlier over the steady window (frozen model: round(lag/s) + ½ = " +
        fmt(std::round(b_.tool2_lag_mm / b_.feed_mm_per_rev) + 0.5, "%.1f") + ").");
  if (b_.process_damping.on())
    claims.note("Process damping (flank indentation, K_sp = " +
                fmt(b_.process_damping.k_sp_N_per_m3 * 1e-9, "%.3g") +
                " N/mm³, VB = " + fmt(b_.process_damping.wear_land_mm) + " mm, γ = " +
                fmt(b_.process_damping.clearance_deg) + "°) is on: beyond the seed's model.");
  if (b_.setup == TwinSetup::FeedDivision)
    claims.note("Linear limits at z = " + fmt(lim_x_) + " mm, " + fmt(b_.rpm) +
                " rpm: feed division chatters above s = " + fmt(lim_.twin_feed, "%.3f") +
                " mm/rev (each tool s/2 of the surface the other left half a turn earlier); one "
                "tool alone above s = " +
                fmt(lim_.single_feed, "%.3f") +
                " mm/rev. Programmed s = " + fmt(b_.feed_mm_per_rev, "%.3f") + " mm/rev.");
  else
    claims.note("Linear limit at z = " + fmt(lim_x_) + " mm, " + fmt(b_.rpm) +
                " rpm, one tool's own regeneration: s = " + fmt(lim_.single_feed, "%.3f") +
                " mm/rev; programmed s = " + fmt(b_.feed_mm_per_rev, "%.3f") + " mm/rev.");
  if (modulated_ && twin_)
    claims.note(
        "With modulation one turret was out of the cut for " +
        fmt(100.0 * m.one_out_share, "%.0f") + " % of the steady window (without: " +
        (off_ ? fmt(100.0 * off_->one_out_share, "%.0f") : std::string("—")) +
        " %): the modulated turret falls behind or runs ahead of the other by more than half "
        "the feed per revolution, the other takes the whole chip, and the summed "
        "regenerative gain drops from 2·g(s/2) to g(s) = 2^−(1−m)·2·g(s/2). Its price: the "
        "radial forces no longer balance — mean deflection " +
        fmt(m.static_um) + " µm with, " + (off_ ? fmt(off_->static_um) : std::string("—")) +
        " µm without (a diameter error of twice that), swinging ±" + fmt(m.forced_um) +
        " µm with the modulation. A fixed axial offset of the turrets by more than s/2 does the "
        "same without any modulation (b_twin_offset).");
}

void ChatterStudy::summary(json& s) {
  s["label"] = main().label;
  s["metrics"].update(run_metrics());
  model_metrics(s["metrics"]);
  // The user's cut is the main run's (with its modulation, if any).
  io::Acceptance acceptance(st_.acceptance);
  acceptance.judge("max_vibration_um", main().vibration_um);
  if (modulated_)
    acceptance.judge("min_mean_feed_pct", 100.0 * main().feed_mean[turret_] / s_prog_);
  s["acceptance"] = acceptance.json();
}

// What the runs measured, with and without modulation.
json ChatterStudy::run_metrics() const {
  const Run& m = main();
  // {"with", "without"} of one measure; without modulation in the scenario, "without" only.
  const auto both = [&](double Run::*v) {
    if (!modulated_) return json{{"without", json_number(m.*v)}};
    json j = {{"with", json_number(m.*v)}};
    if (off_) j["without"] = json_number(off_->*v);
    return j;
  };
  const Run& chat = off_ ? *off_ : m;
  const auto& o = mo();
  return {{"vibration_amplitude_um", both(&Run::vibration_um)},
          {"forced_deflection_um", both(&Run::forced_um)},
          {"static_deflection_um", both(&Run::static_um)},
          {"chatter_frequency_Hz", json_number(chat.chatter_Hz)},
          {"depth_swing",  // the user's cut (the main run): does its vibration grow?
           {{"first_fifth_um", json_number(m.swing_first_um)},
            {"last_fifth_um", json_number(m.swing_last_um)},
            {"growth", json_number(m.swing_growth)},
            {"frequency_Hz", json_number(m.swing_Hz)}}},
          {"modulation",
           {{"S_min_mm_per_min", o.plan.s_min_mm_per_min},
            {"dS_mm_per_min", o.plan.ds_mm_per_min},
            {"dl_mm", o.plan.dl_mm},
            {"n_s", o.plan.n_s},
            {"S_max_mm_per_min", o.plan.active() ? o.plan.s_max_mm_per_min() : 0.0},
            {"omega_m_Hz", o.omega_m_rad_per_s / (2.0 * std::numbers::pi)},
            {"turret", turret_ == 0 ? "right" : "left"},
            {"engaged", o.engaged},
            {"engaged_at_s", json_number(m.rig.engaged_at_s() >= 0 ? m.rig.engaged_at_s() : kNaN)},
            {"force_amplitude_required_N", o.force_amplitude_required_N},
            {"force_amplitude_planned_N", o.force_amplitude_planned_N},
            {"reason", std::string(control::reason_name(o.reason))}}},
          {"mean_feed_mm_per_min",
           {{"programmed", s_prog_},
            {"right", m.feed_mean[0]},
            {"left", twin_ ? json_number(m.feed_mean[1]) : json(nullptr)}}},
          {"surface", surface_metrics()},
          {"cutting_power_W", {{"true", m.cut_power_W}, {"measured", m.cut_power_measured_W}}},
          {"one_turret_out_of_cut_share",
           modulated_ ? json{{"with", m.one_out_share},
                             {"without", off_ ? json_number(off_->one_out_share) : json(nullptr)}}
                      : json{{"without", m.one_out_share}}},
          {"linear_limits",
           {{"at_mm", lim_x_},
            {"single_tool_feed_mm_per_rev", json_number(lim_.single_feed)},
            {"feed_division_feed_mm_per_rev", json_number(lim_.twin_feed)},
            {"chatter_Hz", json_number(lim_.chatter_Hz)},
            {"programmed_feed_mm_per_rev", b_.feed_mm_per_rev}}},
          {"quenching_check",
           {{"van_der_pol_threshold_B_over_a0", vdp_B_ / 2.0},
            {"averaging_theory", 1.0 / std::numbers::sqrt2},
            {"seed_coefficient", b_.seed_coefficient}}}};
}

// The surface the cut leaves (Surface in metrics.hpp: the feed marks, and the vibration added).
json ChatterStudy::surface_metrics() const {
  const auto one = [](const Run& r) {
    const Surface& f = r.surface;
    return json{{"length_mm", f.length_mm},
                {"Rz_mean_um", json_number(f.Rz_mean_um)},
                {"Rz_min_um", json_number(f.Rz_min_um)},
                {"Rz_max_um", json_number(f.Rz_max_um)},
                {"Ra_mean_um", json_number(f.Ra_mean_um)},
                {"Rz_with_vibration_um", json_number(f.Rz_mean_um + 2.0 * r.vibration_um)},
                {"Ra_with_vibration_um",
                 json_number(f.Ra_mean_um + 2.0 / std::numbers::pi * r.vibration_um)}};
  };
  const Run& m = main();
  json j = {{"model", "feed marks of the nose radius (Rz = p²/8r, Ra ≈ p²/32r) along the part; "
                      "with vibration: + 2a (Rz), + 2a/π (Ra)"},
            {"nose_radius_mm", b_.cutting.nose_radius_mm},
            {"Rz_programmed_um", json_number(m.surface.Rz_programmed_um)},
            {"Ra_programmed_um", json_number(m.surface.Ra_programmed_um)}};
  if (modulated_) {
    j["with"] = one(m);
    if (off_) j["without"] = one(*off_);
  } else {
    j["without"] = one(m);
  }
  return j;
}

// The quenching condition read both ways, the inter-tool delay, process damping.
void ChatterStudy::model_metrics(json& m) const {
  if (automatic_engaged()) {
    const double c_seed = b_.seed_coefficient;
    const double planned = mo().force_amplitude_planned_N;
    auto reading = [&](double k, double a0_um) {
      return json{{"a0_um", json_number(a0_um)},
                  {"required_multiply_N", json_number(c_seed * k)},
                  {"required_divide_N", json_number(k / c_seed)},
                  {"ratio_multiply", json_number(planned / (c_seed * k))},
                  {"ratio_divide", json_number(planned * c_seed / k)}};
    };
    m["quenching_condition"] = {
        {"reading", b_.seed_divides ? "divide" : "multiply"},
        {"planned_N", planned},
        {"at_planned_a0", reading(quench_.k_planned, quench_.a0_planned_um)},
        {"at_steady_a0", reading(quench_.k_steady, quench_.a0_steady_um)}};
  }
  if (b_.setup == TwinSetup::DepthDivision) {
    const auto& pc = main().rig.process();
    m["inter_tool_delay"] = {
        {"model",
         b_.inter_tool_delay == dynamics::InterToolDelay::Fixed ? "fixed" : "axial_positions"},
        {"min_rev", json_number(main().delay_min_rev)},
        {"max_rev", json_number(main().delay_max_rev)},
        {"uncut_reads", pc.uncut_reads()},
        {"clipped_reads", pc.clipped_reads()}};
  }
  if (b_.chip_law == dynamics::ChipLaw::Power)  // absent with the default linear law
    m["chip_law"] = {{"model", "power"},
                     {"m_Fc", b_.cutting.material.Fc.m},
                     {"m_Fp", b_.cutting.material.Fp.m}};
  if (b_.process_damping.on())
    m["process_damping"] = {{"model", "indentation"},
                            {"K_sp_N_per_mm3", b_.process_damping.k_sp_N_per_m3 * 1e-9},
                            {"wear_land_mm", b_.process_damping.wear_land_mm},
                            {"clearance_deg", b_.process_damping.clearance_deg},
                            {"linear_equivalent_N_s_per_m",
                             b_.process_damping.k_sp_N_per_m3 * b_.depth_mm[0] * 1e-3 *
                                 std::pow(b_.process_damping.wear_land_mm * 1e-3, 2) /
                                 (4.0 * std::numbers::pi * b_.part.diameter_m * b_.rpm / 60.0)}};
}

void ChatterStudy::finish(io::RunOutput& out) {
  const Run& m = main();
  // In memory only without a stage (library callers, tests); else on disk already.
  out.channels_csv = m.csv->take_text();
  out.channels_values = m.csv->take_values();
  if (compared_) out.compare_csv = without_->csv->take_text();
  out.headline =
      (off_ ? "no modulation " + fmt(off_->vibration_um, "%.3g") + " µm" : std::string()) +
      (modulated_
           ? (off_ ? "; " : "") + m.label + " " + fmt(m.vibration_um, "%.3g") + " µm, mean feed " +
                 fmt(m.feed_mean[turret_] / s_prog_, "%.3f") + "× programmed"
           : std::string());
}
}  // namespace detail

io::RunOutput run(const io::Scenario& sc) {
  return detail::ChatterStudy(sc).run();
}

}  // namespace lathectl::systems::b_chatter
