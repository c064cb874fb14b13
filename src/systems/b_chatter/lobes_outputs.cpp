#include "systems/b_chatter/lobes_outputs.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "lathectl/io/format.hpp"
#include "lathectl/io/output.hpp"
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

using nlohmann::json;

// lobes.json: the modes at the tool and the measured FRFs, the lobes and what the envelope cannot
// say, the recommendation, semi-discretization and its chart, the part.
json modes_json(const LobesInput& in) {
  json modes = json::array();
  for (const auto& m : in.modal.modes)
    modes.push_back({{"stiffness_N_per_m", m.stiffness_N_per_m},
                     {"damping_ratio", m.damping_ratio},
                     {"natural_frequency_Hz", m.natural_frequency_Hz},
                     {"angle_deg", m.angle_rad * 180.0 / std::numbers::pi}});
  return modes;
}

json measured_json(const LobesInput& in) {
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
  return {{"files", files},
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

json closed_form_sdof(const LobesInput& in) {
  const auto& m = in.system.modes[0];
  const double c2 = std::cos(m.angle_rad) * std::cos(m.angle_rad);
  return {
      {"depth_mm", 2.0 * m.stiffness_N_per_m * m.damping_ratio * (1.0 + m.damping_ratio) /
                       (in.system.kf_N_per_m2 * c2) * 1e3},
      {"chatter_frequency_Hz", m.natural_frequency_Hz * std::sqrt(1.0 + 2.0 * m.damping_ratio)}};
}

// The lobes and the number with a minimum inside the speed range.
int lobes_list(const LobesInput& in, const dynamics::FrequencyDomainResult& fd, json& j) {
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
  return inside;
}

// What the envelope cannot say, said: speeds no lobe reaches (empty cells in lobes.csv) and
// lobes listed at a range edge rather than at a minimum.
json envelope_warnings(const LobesInput& in, const dynamics::FrequencyDomainResult& fd, int inside,
                       json& j) {
  json warnings = json::array();
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
  return warnings;
}

json recommendation_json(const LobesInput& in, const std::vector<Pocket>& pockets) {
  const auto& rc = in.recommend;
  const double kc = rc.kc_N_per_m2 > 0.0 ? rc.kc_N_per_m2 : in.system.kf_N_per_m2;
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
  const double none = std::numeric_limits<double>::infinity();
  return {{"safety_factor", rc.safety_factor},
          {"feed_mm_per_rev", rc.feed_m * 1e3},
          {"diameter_mm", recommend_diameter_m(in) * 1e3},
          {"kc_N_per_mm2", kc * 1e-6},
          {"power_limit_kW", json_number(rc.power_W > 0.0 ? rc.power_W * 1e-3 : none)},
          {"torque_limit_Nm", json_number(rc.torque_Nm > 0.0 ? rc.torque_Nm : none)},
          {"pockets", list}};
}

void sd_json(const LobesInput& in, const LobesRun& r, json& j) {
  json sd = json::array();
  for (std::size_t k = 0; k < r.sd_speed.size(); ++k)
    sd.push_back({{"speed_rpm", r.sd_speed[k]},
                  {"depth_mm", json_number(r.sd_depth[k] * 1e3)},
                  {"frequency_domain_depth_mm", json_number(r.fd_depth[k] * 1e3)}});
  j["semi_discretization"] = sd;
  j["semi_discretization_max_rel_difference"] =
      in.process_damping_C > 0.0 ? json(nullptr) : json(r.worst);  // (not computed then)
  if (in.process_damping_C > 0.0)
    j["process_damping"] = {{"k_sp_N_per_mm3", in.process_damping_k_sp_N_per_m3 * 1e-9},
                            {"wear_land_mm", in.process_damping_vb_m * 1e3},
                            {"approach_angle_deg",
                             in.process_damping_kappa_rad * 180.0 / std::numbers::pi},
                            {"C_N_s_per_m_per_m_per_rpm", in.process_damping_C}};
  if (!r.chart) return;
  const auto& chart = r.chart;
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
                   {"compared_speeds", r.chart_compared},
                   {"max_rel_difference_vs_frequency_domain", r.chart_worst}};
}

json part_json(const LobesInput& in, const std::vector<AlongPart>& along) {
  const auto& b = in.part->beam;
  json pos = json::array();
  for (const auto& a : along)
    pos.push_back({{"position_mm", a.x_m * 1e3},
                   {"critical_depth_mm", a.critical_m * 1e3},
                   {"chatter_frequency_Hz", a.chatter_Hz},
                   {"lowest_depth_in_speed_range_mm", json_number(a.lowest_in_range_m * 1e3)},
                   {"first_mode_Hz", a.f1_Hz},
                   {"static_stiffness_N_per_m", a.k_static}});
  return {{"length_mm", b.length_m * 1e3},
          {"diameter_mm", b.diameter_m * 1e3},
          {"position_mm", in.part->position_m * 1e3},
          {"modes", in.part->modes},
          {"support", in.part->support},
          {"steady_rest_mm", in.part->supports.steady_rest_m * 1e3},
          {"static_stiffness_N_per_m", part_static_stiffness(*in.part, in.part->position_m)},
          {"along_part", pos}};
}

// The curves of lobe_curves as the diagram's series.
struct LobeSeries {
  Series env{"frequency domain: lower envelope", {}, {}, "#1f77b4", false, false};
  Series sdp{"semi-discretization (bisection)", {}, {}, "#d62728", false, true};
  Series sdc{"semi-discretization chart: ρ = 1", {}, {}, "#2ca02c", true, false};
};

LobeSeries lobe_series(const LobeCurves& c) {
  LobeSeries s;
  s.env.x = c.envelope.speed_rpm;
  s.env.y = c.envelope.depth_mm;
  s.sdp.x = c.sd.speed_rpm;
  s.sdp.y = c.sd.depth_mm;
  s.sdc.x = c.chart.speed_rpm;
  s.sdc.y = c.chart.depth_mm;
  return s;
}

void csv_series(std::string& csv, const Series& s) {
  for (std::size_t k = 0; k < s.x.size(); ++k) csv_row(csv, s.x[k], s.y[k]);
}

// lobes.csv: the curves, the SD chart's every cell, the measured FRF against its smoothing and
// its fit, the critical depth along the part.
std::string lobes_csv(const LobesInput& in, const LobesRun& r, const LobeSeries& c) {
  std::string csv = "speed_rpm,frequency_domain_depth_mm\n";
  csv_series(csv, c.env);
  csv += "\nspeed_rpm,semi_discretization_depth_mm\n";
  csv_series(csv, c.sdp);
  if (const auto& chart = r.chart) {
    csv += "\nspeed_rpm,sd_chart_boundary_depth_mm\n";
    csv_series(csv, c.sdc);
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
  if (!r.along.empty()) {
    csv += "\nposition_mm,critical_depth_mm\n";
    for (const auto& a : r.along) csv_row(csv, a.x_m * 1e3, a.critical_m * 1e3);
  }
  return csv;
}

// lobes.html: the recommendation first (what a machinist came for), the metrics, the lobe diagram
// and its tables, the measured FRF against its fit, the critical depth along the part.
void report_recommendation(const LobesInput& in, const std::vector<Pocket>& pockets, Report& rep) {
  const auto& rc = in.recommend;
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

void report_metrics(const LobesInput& in, const LobesRun& r, const json& j, Report& rep) {
  const auto& fd = r.fd;
  const auto& chart = r.chart;
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
                             fmt(r.worst, "%.3g"));
  if (chart)
    rep.metrics.emplace_back("SD chart (" + std::to_string(chart->speed_rpm.size()) + " × " +
                                 std::to_string(chart->depth_m.size()) +
                                 ") boundary vs frequency domain, max "
                                 "relative difference over " +
                                 std::to_string(r.chart_compared) + " speeds",
                             fmt(r.chart_worst, "%.3g"));
}

// Minima only where a lobe has one inside the speed range; the lobes the range cuts off (their
// lowest point is at an edge, not a minimum) in a table of their own.
void report_lobes(const LobesInput& in, const LobesRun& r, const LobeSeries& c, const json& j,
                  Report& rep) {
  const auto& fd = r.fd;
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
  for (const auto& w : j["warnings"]) rep.notes.push_back("⚠ " + w.get<std::string>());
  Plot p{"Stability lobe diagram", "spindle speed [rpm]", "limit depth of cut [mm]",
         {c.env, c.sdp}, {}};
  if (r.chart) p.series.push_back(c.sdc);
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
}

void report_measured(const LobesMeasured& m, Report& rep) {
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

void report_along(const std::vector<AlongPart>& along, Report& rep) {
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

Report lobes_report(const LobesInput& in, const LobesRun& r, const LobeSeries& c, const json& j) {
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
  report_recommendation(in, r.pockets, rep);
  report_metrics(in, r, j, rep);
  // The chart first: the tables under it run to dozens of rows.
  rep.plots_first = true;
  rep.links = {{"lobes.csv", "lobes.csv"}, {"lobes.json", "lobes.json"}};
  report_lobes(in, r, c, j, rep);
  if (in.measured) report_measured(*in.measured, rep);
  if (!r.along.empty()) report_along(r.along, rep);
  return rep;
}
}  // namespace

namespace {
void push_depth_mm(LobeCurve& c, double speed_rpm, double depth_m) {
  c.speed_rpm.push_back(speed_rpm);
  c.depth_mm.push_back(std::isfinite(depth_m) ? depth_m * 1e3 : std::nan(""));
}
}  // namespace

LobeCurves lobe_curves(const LobesInput& in, const LobesRun& r) {
  LobeCurves c;
  for (int k = 0; k <= 1000; ++k) {
    const double n = in.min_rpm + (in.max_rpm - in.min_rpm) * k / 1000.0;
    push_depth_mm(c.envelope, n, dynamics::envelope_depth(r.fd, n));
  }
  for (std::size_t k = 0; k < r.sd_speed.size(); ++k)
    push_depth_mm(c.sd, r.sd_speed[k], r.sd_depth[k]);
  if (r.chart)
    for (std::size_t i = 0; i < r.chart->speed_rpm.size(); ++i)
      push_depth_mm(c.chart, r.chart->speed_rpm[i], r.chart->boundary_depth_m[i]);
  return c;
}

json lobes_json(const LobesInput& in, const LobesRun& r) {
  const auto& fd = r.fd;
  json j;
  j["critical_depth_mm"] = fd.critical_depth_m * 1e3;
  j["chatter_frequency_Hz"] = fd.critical_chatter_Hz;
  j["modes_at_tool"] = modes_json(in);
  if (in.measured) j["measured_frf"] = measured_json(in);
  if (in.system.modes.size() == 1 && in.system.frfs.empty())
    j["closed_form_sdof"] = closed_form_sdof(in);
  const int inside = lobes_list(in, fd, j);
  j["warnings"] = envelope_warnings(in, fd, inside, j);
  for (const auto& f : in.frfs)
    for (const auto& n : f.notes) j["warnings"].push_back(n);
  j["recommendation"] = recommendation_json(in, r.pockets);
  sd_json(in, r, j);
  if (in.part) j["part"] = part_json(in, r.along);
  return j;
}


void write_lobes_outputs(const LobesInput& in, const LobesRun& r, const json& j,
                         const std::filesystem::path& out_dir) {
  const LobeSeries curves = lobe_series(lobe_curves(in, r));
  // One set: lobes.json never stands beside another machine's lobes.csv.
  io::write_output_set(out_dir,
                       {{"lobes.csv", lobes_csv(in, r, curves)},
                        {"lobes.html", io::render_html(lobes_report(in, r, curves, j))},
                        {"lobes.json", j.dump(2) + "\n"}});
}

}  // namespace lathectl::systems::b_chatter
