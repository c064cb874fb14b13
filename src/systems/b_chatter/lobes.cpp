#include "systems/b_chatter/lobes.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <optional>
#include <thread>

#include "lathectl/core/parallel.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/progress.hpp"
#include "lathectl/io/report.hpp"
#include "lathectl/io/study.hpp"

namespace lathectl::systems::b_chatter {

namespace {
using io::fmt;
using io::json_number;
using io::Plot;
using io::Report;
using io::Series;
using io::Table;

// A depth no lobe bounds (+inf) is an empty cell: spreadsheets and pandas read it as missing,
// where "inf" was read as text or as a number larger than any depth (docs/machine-file-reference.md).
void csv_row(std::string& csv, double a, double b) {
  io::append_general(csv, a, 6);
  csv += ',';
  if (std::isfinite(b)) io::append_general(csv, b, 9);
  csv += '\n';
}
}  // namespace

nlohmann::json run_lobes(const LobesInput& in, const std::filesystem::path& out_dir,
                         io::Progress* progress) {
  using nlohmann::json;
  // Progress: the bisection speeds, then the chart's speeds (each speed about as costly).
  const double total_work =
      static_cast<double>(in.sd_speeds) +
      (in.chart_speeds >= 2 && in.chart_depths >= 2 ? static_cast<double>(in.chart_speeds) : 0.0);
  std::atomic<std::size_t> work_done{0};
  auto tick = [&](const char* phase) {
    const std::size_t k = ++work_done;
    if (progress && total_work > 0) progress->update(static_cast<double>(k) / total_work, phase);
  };
  const auto fd = dynamics::frequency_domain_lobes(in.system, in.min_rpm, in.max_rpm, in.max_lobes,
                                                   kFrequencyPoints);

  // Semi-discretization at sd_speeds speeds by bisection, in parallel, with the chart's scheme
  // (quintic interpolation, 7 steps per period of the modes that can chatter below `hi`).
  std::vector<double> sd_speed(static_cast<std::size_t>(in.sd_speeds)), sd_depth(sd_speed.size()),
      fd_depth(sd_speed.size());
  for (std::size_t k = 0; k < sd_speed.size(); ++k) {
    sd_speed[k] = in.min_rpm + (in.max_rpm - in.min_rpm) * (static_cast<double>(k) + 0.5) /
                                   static_cast<double>(sd_speed.size());
    fd_depth[k] = dynamics::envelope_depth(fd, sd_speed[k]);
  }
  core::parallel_for(sd_speed.size(), [&](std::size_t k) {
    const double hi = std::isfinite(fd_depth[k]) ? 3.0 * fd_depth[k] : 100.0 * fd.critical_depth_m;
    if (!std::isfinite(hi)) {  // no lobe anywhere (every mode across the chip): nothing to bisect
      sd_depth[k] = std::numeric_limits<double>::infinity();
      tick("semi-discretization limits");
      return;
    }
    const dynamics::SdChartOptions o;
    const int m = dynamics::sd_steps_per_delay(in.modal, sd_speed[k], hi, o);
    sd_depth[k] =
        dynamics::sd_limit_depth(in.modal, sd_speed[k], hi, m, 1e-3, o.interpolation_order);
    tick("semi-discretization limits");
  });
  double worst = 0.0;
  for (std::size_t k = 0; k < sd_speed.size(); ++k)
    if (std::isfinite(sd_depth[k]) && std::isfinite(fd_depth[k]))
      worst = std::max(worst, std::abs(sd_depth[k] / fd_depth[k] - 1.0));

  // The SD stability chart: the SD map's unstable roots on a speed × depth grid, and its boundary
  // against the frequency-domain envelope where that lies inside the chart.
  std::optional<dynamics::SdChart> chart;
  double chart_worst = 0.0;
  int chart_compared = 0;
  if (in.chart_speeds >= 2 && in.chart_depths >= 2 && std::isfinite(fd.critical_depth_m)) {
    dynamics::SdChartOptions o;
    o.steps_per_period = in.chart_steps_per_period;
    o.on_speed_done = [&](std::size_t, std::size_t) { tick("semi-discretization chart"); };
    const double top =
        in.chart_max_depth_m > 0.0 ? in.chart_max_depth_m : 4.0 * fd.critical_depth_m;
    chart = dynamics::sd_stability_chart(in.modal, in.min_rpm, in.max_rpm, in.chart_speeds, top,
                                         in.chart_depths, o);
    for (std::size_t i = 0; i < chart->speed_rpm.size(); ++i) {
      const double b_fd = dynamics::envelope_depth(fd, chart->speed_rpm[i]);
      const double b_sd = chart->boundary_depth_m[i];
      if (!std::isfinite(b_fd) || !std::isfinite(b_sd) || b_fd > 0.98 * top) continue;
      chart_worst = std::max(chart_worst, std::abs(b_sd / b_fd - 1.0));
      ++chart_compared;
    }
  }

  // The critical depth along the part, frequency domain at each position.
  struct AlongPart {
    double x_m, critical_m, chatter_Hz, lowest_in_range_m, f1_Hz, k_static;
  };
  std::vector<AlongPart> along;
  if (in.part)
    for (double x : in.part->positions_m) {
      const auto sys = lobes_system_at(in, x);
      const auto r = dynamics::frequency_domain_lobes(sys, in.min_rpm, in.max_rpm, in.max_lobes,
                                                      kFrequencyPoints);
      double lowest = std::numeric_limits<double>::infinity();
      for (const auto& l : r.lobes) lowest = std::min(lowest, l.minimum.depth_m);
      along.push_back({x, r.critical_depth_m, r.critical_chatter_Hz, lowest,
                       part_first_mode_Hz(*in.part, x), part_static_stiffness(*in.part, x)});
    }

  json j;
  j["critical_depth_mm"] = fd.critical_depth_m * 1e3;
  j["chatter_frequency_Hz"] = fd.critical_chatter_Hz;
  json modes = json::array();
  for (const auto& m : in.modal.modes)
    modes.push_back({{"stiffness_N_per_m", m.stiffness_N_per_m},
                     {"damping_ratio", m.damping_ratio},
                     {"natural_frequency_Hz", m.natural_frequency_Hz},
                     {"angle_deg", m.angle_rad * 180.0 / std::numbers::pi}});
  j["modes_at_tool"] = modes;
  if (in.measured) {
    json files = json::array();
    for (const auto& f : in.frfs)
      files.push_back({{"file", f.file},
                       {"direction", f.direction},
                       {"of", f.of},
                       {"weight", f.weight},
                       {"points", f.frf.frequency_Hz.size()},
                       {"min_Hz", f.frf.frequency_Hz.front()},
                       {"max_Hz", f.frf.frequency_Hz.back()}});
    json fitted = json::array();
    for (const auto& m : in.measured->fit.modes)
      fitted.push_back({{"stiffness_N_per_m", m.stiffness_N_per_m},
                        {"damping_ratio", m.damping_ratio},
                        {"natural_frequency_Hz", m.natural_frequency_Hz}});
    j["measured_frf"] = {{"files", files},
                         {"chip_direction_deg", in.chip_direction_rad * 180.0 / std::numbers::pi},
                         {"band_Hz", {in.measured->oriented.frequency_Hz.front(),
                                      in.measured->oriented.frequency_Hz.back()}},
                         {"fitted_modes", fitted},
                         {"fit_relative_residual", in.measured->fit.residual},
                         {"smoothing_half_window_Hz", in.measured->smoothing_half_window_Hz},
                         {"samples_per_bandwidth", in.measured->samples_per_bandwidth},
                         {"frequency_domain_reads",
                          in.measured->read_directly
                              ? "the measured FRF against its fit"
                              : "the fit and its residual's slow part (sampled too coarsely)"}};
  }
  if (in.system.modes.size() == 1 && in.system.frfs.empty()) {
    const auto& m = in.system.modes[0];
    const double c2 = std::cos(m.angle_rad) * std::cos(m.angle_rad);
    j["closed_form_sdof"] = {
        {"depth_mm", 2.0 * m.stiffness_N_per_m * m.damping_ratio * (1.0 + m.damping_ratio) /
                         (in.system.kf_N_per_m2 * c2) * 1e3},
        {"chatter_frequency_Hz", m.natural_frequency_Hz * std::sqrt(1.0 + 2.0 * m.damping_ratio)}};
  }
  json lobes = json::array();
  int inside = 0;
  for (const auto& l : fd.lobes) {
    inside += l.minimum_inside ? 1 : 0;
    lobes.push_back({{"N", l.N},
                     {"min_speed_rpm", l.minimum.speed_rpm},
                     {"depth_mm", l.minimum.depth_m * 1e3},
                     {"chatter_frequency_Hz", l.minimum.chatter_Hz},
                     {"minimum_inside_range", l.minimum_inside}});
  }
  j["lobes"] = lobes;
  j["max_lobes"] = in.max_lobes;
  j["lobes_with_minimum_in_range"] = inside;
  // What the envelope cannot say, said: speeds no lobe reaches (empty cells in lobes.csv) and
  // lobes listed at a range edge rather than at a minimum.
  json warnings = json::array();
  {
    int undefined = 0, inner = 0;
    double lo = 0.0, hi = 0.0;
    std::string ends;
    for (int k = 0; k <= 1000; ++k) {
      const double n = in.min_rpm + (in.max_rpm - in.min_rpm) * k / 1000.0;
      if (std::isfinite(dynamics::envelope_depth(fd, n))) continue;
      ++undefined;
      if (k == 0 || k == 1000) {
        ends += (ends.empty() ? "" : " and ") + fmt(n, "%.0f");
        continue;
      }
      if (inner++ == 0) lo = n;
      hi = n;
    }
    j["envelope_undefined_speeds"] = undefined;
    if (!ends.empty())
      warnings.push_back("the envelope is undefined exactly at the range's end " + ends +
                         " rpm (an empty cell in lobes.csv): the lobes' grid points lie inside the range");
    if (inner > 0)
      warnings.push_back("no lobe reaches " + std::to_string(inner) +
                         " of the 1001 envelope speeds between " + fmt(lo, "%.0f") + " and " +
                         fmt(hi, "%.0f") + " rpm (empty cells in lobes.csv): no limit is known there");
    const int edge = static_cast<int>(fd.lobes.size()) - inside;
    if (edge > 0)
      warnings.push_back(std::to_string(edge) +
                         " lobe(s) have their minimum outside the speed range; their rows give the "
                         "lowest point at the range's edge, marked \"edge\", not a minimum");
  }
  j["warnings"] = warnings;
  const auto pockets = recommend_pockets(fd, in);
  const auto& rc = in.recommend;
  const double kc = rc.kc_N_per_m2 > 0.0 ? rc.kc_N_per_m2 : in.system.kf_N_per_m2;
  {
    json list = json::array();
    for (const auto& p : pockets)
      list.push_back({{"speed_rpm", p.speed_rpm},
                      {"pocket_top_rpm", p.pocket_top_rpm},
                      {"pocket_top_depth_mm", json_number(p.pocket_top_depth_m * 1e3)},
                      {"limit_depth_mm", json_number(p.limit_depth_m * 1e3)},
                      {"depth_mm", p.depth_m * 1e3},
                      {"limited_by", p.limited_by},
                      {"removal_rate_cm3_per_min", p.mrr_m3_per_s * 6e7},
                      {"power_kW", p.power_W * 1e-3},
                      {"torque_Nm", p.torque_Nm},
                      {"margin_below_rpm", p.margin_below_rpm},
                      {"margin_above_rpm", p.margin_above_rpm},
                      {"margin_below_reaches_range_end", p.below_reaches_range_end},
                      {"margin_above_reaches_range_end", p.above_reaches_range_end}});
    j["recommendation"] = {{"safety_factor", rc.safety_factor},
                           {"feed_mm_per_rev", rc.feed_m * 1e3},
                           {"diameter_mm", recommend_diameter_m(in) * 1e3},
                           {"kc_N_per_mm2", kc * 1e-6},
                           {"power_limit_kW", json_number(rc.power_W > 0.0 ? rc.power_W * 1e-3
                                                          : std::numeric_limits<double>::infinity())},
                           {"torque_limit_Nm", json_number(rc.torque_Nm > 0.0 ? rc.torque_Nm
                                                           : std::numeric_limits<double>::infinity())},
                           {"pockets", list}};
  }
  json sd = json::array();
  for (std::size_t k = 0; k < sd_speed.size(); ++k)
    sd.push_back({{"speed_rpm", sd_speed[k]},
                  {"depth_mm", json_number(sd_depth[k] * 1e3)},
                  {"frequency_domain_depth_mm", json_number(fd_depth[k] * 1e3)}});
  j["semi_discretization"] = sd;
  j["semi_discretization_max_rel_difference"] =
      in.process_damping_C > 0.0 ? json(nullptr) : json(worst);  // (not computed then)
  if (in.process_damping_C > 0.0)
    j["process_damping"] = {{"k_sp_N_per_mm3", in.process_damping_k_sp_N_per_m3 * 1e-9},
                            {"wear_land_mm", in.process_damping_vb_m * 1e3},
                            {"approach_angle_deg",
                             in.process_damping_kappa_rad * 180.0 / std::numbers::pi},
                            {"C_N_s_per_m_per_m_per_rpm", in.process_damping_C}};
  if (chart) {
    json boundary = json::array();
    for (double b : chart->boundary_depth_m) boundary.push_back(json_number(b * 1e3));
    const auto [m_lo, m_hi] = std::minmax_element(chart->steps.begin(), chart->steps.end());
    j["sd_chart"] = {{"speeds", chart->speed_rpm.size()},
                     {"depths", chart->depth_m.size()},
                     {"min_rpm", in.min_rpm},
                     {"max_rpm", in.max_rpm},
                     {"max_depth_mm", chart->depth_m.back() * 1e3},
                     {"steps_per_delay_min", *m_lo},
                     {"steps_per_delay_max", *m_hi},
                     {"interpolation_order", dynamics::SdChartOptions{}.interpolation_order},
                     {"boundary_depth_mm", boundary},
                     {"compared_speeds", chart_compared},
                     {"max_rel_difference_vs_frequency_domain", chart_worst}};
  }
  if (in.part) {
    const auto& b = in.part->beam;
    json pos = json::array();
    for (const auto& a : along)
      pos.push_back({{"position_mm", a.x_m * 1e3},
                     {"critical_depth_mm", a.critical_m * 1e3},
                     {"chatter_frequency_Hz", a.chatter_Hz},
                     {"lowest_depth_in_speed_range_mm", json_number(a.lowest_in_range_m * 1e3)},
                     {"first_mode_Hz", a.f1_Hz},
                     {"static_stiffness_N_per_m", a.k_static}});
    j["part"] = {
        {"length_mm", b.length_m * 1e3},
        {"diameter_mm", b.diameter_m * 1e3},
        {"position_mm", in.part->position_m * 1e3},
        {"modes", in.part->modes},
        {"support", in.part->support},
        {"steady_rest_mm", in.part->supports.steady_rest_m * 1e3},
        {"static_stiffness_N_per_m", part_static_stiffness(*in.part, in.part->position_m)},
        {"along_part", pos}};
  }

  // CSV: the frequency-domain envelope on a fine speed grid, the SD points, the SD chart (its
  // boundary, then every cell) and the critical depth along the part.
  std::string csv = "speed_rpm,frequency_domain_depth_mm\n";
  Series env{"frequency domain: lower envelope", {}, {}, "#1f77b4", false, false};
  for (int k = 0; k <= 1000; ++k) {
    const double n = in.min_rpm + (in.max_rpm - in.min_rpm) * k / 1000.0;
    const double b = dynamics::envelope_depth(fd, n);
    csv_row(csv, n, b * 1e3);
    env.x.push_back(n);
    env.y.push_back(std::isfinite(b) ? b * 1e3 : std::nan(""));
  }
  csv += "\nspeed_rpm,semi_discretization_depth_mm\n";
  Series sdp{"semi-discretization (bisection)", {}, {}, "#d62728", false, true};
  for (std::size_t k = 0; k < sd_speed.size(); ++k) {
    csv_row(csv, sd_speed[k], sd_depth[k] * 1e3);
    sdp.x.push_back(sd_speed[k]);
    sdp.y.push_back(std::isfinite(sd_depth[k]) ? sd_depth[k] * 1e3 : std::nan(""));
  }
  Series sdc{"semi-discretization chart: ρ = 1", {}, {}, "#2ca02c", true, false};
  if (chart) {
    csv += "\nspeed_rpm,sd_chart_boundary_depth_mm\n";
    for (std::size_t i = 0; i < chart->speed_rpm.size(); ++i) {
      const double b = chart->boundary_depth_m[i];
      csv_row(csv, chart->speed_rpm[i], b * 1e3);
      sdc.x.push_back(chart->speed_rpm[i]);
      sdc.y.push_back(std::isfinite(b) ? b * 1e3 : std::nan(""));
    }
    csv += "\nspeed_rpm,depth_mm,sd_unstable_roots\n";
    for (std::size_t i = 0; i < chart->speed_rpm.size(); ++i)
      for (std::size_t k = 0; k < chart->depth_m.size(); ++k) {
        io::append_general(csv, chart->speed_rpm[i], 6);
        csv += ',';
        io::append_general(csv, chart->depth_m[k] * 1e3, 6);
        csv += ',';
        csv += std::to_string(chart->unstable(i, k));
        csv += '\n';
      }
  }
  if (in.measured) {
    csv += "\nfrequency_Hz,measured_real_m_per_N,measured_imag_m_per_N,smoothed_real_m_per_N,"
           "smoothed_imag_m_per_N,fitted_real_m_per_N,fitted_imag_m_per_N\n";
    const auto& m = *in.measured;
    for (std::size_t k = 0; k < m.oriented.frequency_Hz.size(); ++k) {
      const double f = m.oriented.frequency_Hz[k];
      const auto fit = dynamics::modal_frf(m.fit.modes, f);
      io::append_general(csv, f, 9);
      for (const auto v : {m.oriented.receptance_m_per_N[k], m.smoothed.receptance_m_per_N[k], fit}) {
        csv += ',';
        io::append_general(csv, v.real(), 9);
        csv += ',';
        io::append_general(csv, v.imag(), 9);
      }
      csv += '\n';
    }
  }
  if (!along.empty()) {
    csv += "\nposition_mm,critical_depth_mm\n";
    for (const auto& a : along) csv_row(csv, a.x_m * 1e3, a.critical_m * 1e3);
  }

  Report rep;
  rep.title = "Stability lobes";
  rep.doc_page = "system-b-chatter.md";  // the lobes are system B's chatter model
  rep.subtitle = std::to_string(in.system.modes.size()) + " mode(s)" +
                 (in.frfs.empty() ? std::string()
                                  : " and " + std::to_string(in.frfs.size()) + " measured FRF(s)") +
                 ", K_f = " + fmt(in.system.kf_N_per_m2 * 1e-6) + " N/mm²";
  if (in.part)
    rep.subtitle += "; part Ø" + fmt(in.part->beam.diameter_m * 1e3) + " × " +
                    fmt(in.part->beam.length_m * 1e3) + " mm " +
                    (in.part->support == "chuck"             ? "in a chuck"
                     : in.part->support == "chuck_tailstock" ? "in a chuck with the tailstock"
                                                             : "between centres") +
                    (in.part->supports.steady_rest_m > 0.0
                         ? ", steady rest at " + fmt(in.part->supports.steady_rest_m * 1e3) + " mm"
                         : std::string()) +
                    ", tool at " + fmt(in.part->position_m * 1e3) + " mm";
  rep.description =
      "Frequency-domain lobes (Tlusty/Tobias/Altintas) and, independently, semi-discretization "
      "(Insperger–Stépán): limit depths by bisection at a few speeds, and the SD map's eigenvalues "
      "outside the unit circle counted on a speed × depth grid (argument principle), whose "
      "boundary, bisected between grid depths, is the chart's ρ = 1 line. "
      "Below the envelope the cut is stable; the lobe minima are the absolute stability limit.";
  // The recommendation first: what a machinist came for.
  {
    auto margin = [](double rpm, bool to_end) {
      return to_end ? "≥ " + fmt(rpm, "%.0f") + " (range end)" : fmt(rpm, "%.0f");
    };
    Table t{"Recommendation",
            {"speed [rpm]", "depth [mm]", "limited by", "pocket top [rpm, mm]",
             "removal rate [cm³/min]", "power [kW]", "torque [N·m]", "margin below [rpm]",
             "margin above [rpm]"},
            {}};
    for (const auto& p : pockets)
      t.rows.push_back({fmt(p.speed_rpm, "%.0f"), fmt(p.depth_m * 1e3, "%.3g"), p.limited_by,
                        fmt(p.pocket_top_rpm, "%.0f") + ", " +
                            (std::isfinite(p.pocket_top_depth_m)
                                 ? fmt(p.pocket_top_depth_m * 1e3, "%.3g")
                                 : std::string("unbounded")),
                        fmt(p.mrr_m3_per_s * 6e7, "%.3g"), fmt(p.power_W * 1e-3, "%.3g"),
                        fmt(p.torque_Nm, "%.3g"),
                        margin(p.margin_below_rpm, p.below_reaches_range_end),
                        margin(p.margin_above_rpm, p.above_reaches_range_end)});
    rep.verdict_table = t;
    rep.verdict =
        pockets.empty()
            ? "No pocket: no depth is bounded by chatter or by the machine's limits in the range"
            : "Run " + fmt(pockets[0].speed_rpm, "%.0f") + " rpm at " +
                  fmt(pockets[0].depth_m * 1e3, "%.3g") + " mm depth (feed " +
                  fmt(rc.feed_m * 1e3) + " mm/rev, Ø" + fmt(recommend_diameter_m(in) * 1e3) +
                  " mm): the pocket's top depth divided by the safety factor " +
                  fmt(rc.safety_factor) + ", within the spindle's power and torque" +
                  (rc.power_W > 0.0 || rc.torque_Nm > 0.0 ? "" : " (none given)") +
                  ", at the middle of the speeds where that depth is stable; the speed may drift "
                  "by the margins below before a lobe reaches it.";
  }
  rep.metrics.emplace_back("absolute stability limit [mm]", fmt(fd.critical_depth_m * 1e3));
  rep.metrics.emplace_back("chatter frequency there [Hz]", fmt(fd.critical_chatter_Hz));
  if (j.contains("closed_form_sdof"))
    rep.metrics.emplace_back("SDOF closed form 2kζ(1+ζ)/(K_f cos²θ) [mm]",
                             fmt(j["closed_form_sdof"]["depth_mm"].get<double>()));
  if (in.process_damping_C > 0.0)
    rep.metrics.emplace_back(
        "process damping (flank indentation)",
        "K_sp " + fmt(in.process_damping_k_sp_N_per_m3 * 1e-9, "%.3g") + " N/mm³, VB " +
            fmt(in.process_damping_vb_m * 1e3) + " mm, κ " +
            fmt(in.process_damping_kappa_rad * 180.0 / std::numbers::pi, "%.0f") +
            "°: c = C·b/n, C = " + fmt(in.process_damping_C, "%.3g") +
            " N·s/m per m/rpm; the frequency domain only (no semi-discretization limits or chart)");
  else
    rep.metrics.emplace_back("semi-discretization vs frequency domain, max relative difference",
                             fmt(worst, "%.3g"));
  if (chart)
    rep.metrics.emplace_back("SD chart (" + std::to_string(chart->speed_rpm.size()) + " × " +
                                 std::to_string(chart->depth_m.size()) +
                                 ") boundary vs frequency domain, max "
                                 "relative difference over " +
                                 std::to_string(chart_compared) + " speeds",
                             fmt(chart_worst, "%.3g"));
  // The chart first: the tables under it run to dozens of rows.
  rep.plots_first = true;
  rep.links = {{"lobes.csv", "lobes.csv"}, {"lobes.json", "lobes.json"}};
  // Minima only where a lobe has one inside the speed range; the lobes the range cuts off (their
  // lowest point is at an edge, not a minimum) in a table of their own.
  Table t{"Lobe minima inside the speed range (max_lobes " + std::to_string(in.max_lobes) + ")",
          {"N", "speed at the minimum [rpm]", "depth [mm]", "chatter [Hz]"},
          {}};
  Table te{"Lobes cut off by the speed range (no minimum inside; lowest point at the edge)",
           {"N", "speed at the edge [rpm]", "depth there [mm]", "chatter [Hz]"},
           {}};
  for (const auto& l : fd.lobes)
    (l.minimum_inside ? t : te)
        .rows.push_back({std::to_string(l.N), fmt(l.minimum.speed_rpm, "%.1f"),
                         fmt(l.minimum.depth_m * 1e3), fmt(l.minimum.chatter_Hz)});
  if (!t.rows.empty()) rep.tables.push_back(t);
  if (!te.rows.empty()) rep.tables.push_back(te);
  for (const auto& w : warnings) rep.notes.push_back("⚠ " + w.get<std::string>());
  Plot p{
      "Stability lobe diagram", "spindle speed [rpm]", "limit depth of cut [mm]", {env, sdp}, {}};
  if (chart) p.series.push_back(sdc);
  // Lobe tops far above the absolute limit would squash the minima, where the choice of speed
  // is made: the depth axis stops at five times the limit (lobes.csv has every value).
  const double top = 5.0 * fd.critical_depth_m * 1e3;
  double data_top = 0.0;
  for (const Series& sr : p.series)
    for (const double v : sr.y)
      if (std::isfinite(v)) data_top = std::max(data_top, v);
  p.y_min = 0.0;  // a depth axis from zero: a pocket's height is read against no depth at all
  if (std::isfinite(top) && top > 0.0 && data_top > top) {
    p.y_max = top;
    p.title += " (depth axis clipped at 5 × the absolute limit)";
  }
  rep.plots.push_back(p);
  if (in.measured) {
    const auto& m = *in.measured;
    rep.metrics.emplace_back("measured FRF: modal fit's relative residual √(Σ|H−Ĥ|²/Σ|H|²)",
                             fmt(m.fit.residual, "%.3g"));
    rep.metrics.emplace_back("measured FRF: smoothing half-window of its residual from the fit "
                             "[Hz]",
                             fmt(m.smoothing_half_window_Hz, "%.3g"));
    rep.metrics.emplace_back(
        "measured FRF: samples across the sharpest peak's half-power band",
        fmt(m.samples_per_bandwidth, "%.3g") +
            (m.read_directly ? " — the frequency-domain lobes read the FRF against its fit"
                             : " — below " + fmt(dynamics::kMinSamplesPerBandwidth, "%.0f") +
                                   ": the residual's window is widened, the frequency-domain "
                                   "lobes read the fit and the residual's slow part (a "
                                   "coarsely sampled peak read directly leaves its noise in "
                                   "the limit)"));
    Table tf{"Modes fitted to the measured FRF (semi-discretization and the chart use these; the "
             "frequency-domain lobes read the FRF against them)",
             {"natural frequency [Hz]", "damping ratio", "stiffness [N/µm]"},
             {}};
    for (const auto& md : m.fit.modes)
      tf.rows.push_back({fmt(md.natural_frequency_Hz), fmt(md.damping_ratio, "%.4g"),
                         fmt(md.stiffness_N_per_m * 1e-6)});
    rep.tables.push_back(tf);
    Series meas{"measured (oriented to the chip thickness)", {}, {}, "#7f7f7f", false, true};
    Series fitted{"fitted modes", {}, {}, "#d62728", false, false};
    Series re_m{"measured, real part", {}, {}, "#7f7f7f", false, true};
    Series re_f{"fitted, real part", {}, {}, "#d62728", false, false};
    for (std::size_t k = 0; k < m.oriented.frequency_Hz.size(); ++k) {
      const double f = m.oriented.frequency_Hz[k];
      const auto h = m.oriented.receptance_m_per_N[k];
      const auto g = dynamics::modal_frf(m.fit.modes, f);
      meas.x.push_back(f);
      meas.y.push_back(std::abs(h) * 1e6);
      fitted.x.push_back(f);
      fitted.y.push_back(std::abs(g) * 1e6);
      re_m.x.push_back(f);
      re_m.y.push_back(h.real() * 1e6);
      re_f.x.push_back(f);
      re_f.y.push_back(g.real() * 1e6);
    }
    Plot pm{"Measured against fitted FRF: magnitude", "frequency [Hz]", "|H| [µm/N]",
            {meas, fitted}, {}};
    pm.log_y = true;
    rep.plots.push_back(pm);
    rep.plots.push_back({"Measured against fitted FRF: real part (its negative lobes set the "
                         "limit depth)",
                         "frequency [Hz]", "Re H [µm/N]", {re_m, re_f}, {}});
  }
  if (!along.empty()) {
    Table ta{"Critical depth along the part",
             {"position [mm]", "absolute limit [mm]", "chatter [Hz]",
              "lowest in the speed range [mm]", "first mode [Hz]", "static stiffness [N/µm]"},
             {}};
    Series crit{"absolute stability limit", {}, {}, "#9467bd", false, false};
    for (const auto& a : along) {
      ta.rows.push_back({fmt(a.x_m * 1e3), fmt(a.critical_m * 1e3), fmt(a.chatter_Hz),
                         fmt(a.lowest_in_range_m * 1e3), fmt(a.f1_Hz), fmt(a.k_static * 1e-6)});
      crit.x.push_back(a.x_m * 1e3);
      crit.y.push_back(a.critical_m * 1e3);
    }
    rep.tables.push_back(ta);
    Plot along_plot{
        "Critical depth along the part", "position [mm]", "depth of cut [mm]", {crit}, {}};
    along_plot.y_min = 0.0;
    rep.plots.push_back(along_plot);
  }

  // One set: lobes.json never stands beside another machine's lobes.csv.
  io::write_output_set(
      out_dir,
      {{"lobes.csv", csv}, {"lobes.html", io::render_html(rep)}, {"lobes.json", j.dump(2) + "\n"}});
  return j;
}

}  // namespace lathectl::systems::b_chatter
