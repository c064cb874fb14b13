#include "systems/c_tracer/study.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <span>
#include <stdexcept>
#include <vector>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/study.hpp"
#include "systems/c_tracer/settings.hpp"

namespace lathectl::systems::c_tracer {

namespace {
using namespace io;
using nlohmann::json;

struct Run {
  sim::RigC rig;
  std::string label;
  double max_dx_um = 0.0, max_dy_um = 0.0, steady_lag_um = std::nan(""), waviness_um = 0.0;
  json features = json::array();
};

// The zone around a shoulder (a vertical step) where the rig masks δy and δx belongs to the
// shoulder: ±0.5 mm of the tool's x (rig.cpp, near_step).
constexpr double kShoulderZone_mm = 0.5;

// Largest |v| over the samples with x in [x0, x1], leaving out those within the zone of any
// shoulder in `shoulders` (their error is the shoulder's, not its neighbours').
double nan_max_abs(std::span<const double> v, std::span<const double> x, double x0, double x1,
                   const std::vector<double>& shoulders = {}) {
  double m = 0.0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!(x[i] >= x0 && x[i] <= x1 && std::isfinite(v[i]))) continue;
    const bool at_shoulder = std::any_of(shoulders.begin(), shoulders.end(), [&](double s) {
      return std::abs(x[i] - s) <= kShoulderZone_mm;
    });
    if (!at_shoulder) m = std::max(m, std::abs(v[i]));
  }
  return m;
}

void run_one(const io::Scenario& sc, sim::RigCConfig cfg, bool nonlinear, Run& r) {
  cfg.nonlinear = nonlinear;
  configure_and_run(sc, r.rig, cfg);
  r.label = nonlinear ? "nonlinear servo" : "linear model (8)-(9)";
  const auto& rec = r.rig.recorder();
  const auto tx = rec.column("tool_x_mm");
  const auto dx = rec.column("dx_um");
  const auto dy = rec.column("dy_um");
  const auto lag = rec.column("lag_um");
  const auto cx = rec.column("carriage_mm");
  r.max_dx_um = nan_max_abs(dx, tx, -1e300, 1e300);
  r.max_dy_um = nan_max_abs(dy, tx, -1e300, 1e300);
  bool first_cone = true;
  // A shoulder has no length (x_start = x_end): the tool climbs it within its zone, which starts
  // the next feature's x range; without this the shoulder's δx was booked to the next line.
  std::vector<double> shoulders;
  for (const auto& f : cfg.features)
    if (f.x_end_m <= f.x_start_m) shoulders.push_back(f.x_start_m * 1e3);
  for (const auto& f : cfg.features) {
    const double a = f.x_start_m * 1e3, b = f.x_end_m * 1e3;
    const bool shoulder = b <= a;
    const double mdx = shoulder ? nan_max_abs(dx, tx, a - kShoulderZone_mm, a + kShoulderZone_mm)
                                : nan_max_abs(dx, tx, a, b, shoulders);
    const double mdy = shoulder ? nan_max_abs(dy, tx, a - kShoulderZone_mm, a + kShoulderZone_mm)
                                : nan_max_abs(dy, tx, a, b, shoulders);
    json fj = {{"type", f.kind},
               {"x_start_mm", a},
               {"x_end_mm", b},
               {"max_dx_um", mdx},
               {"max_dy_um", mdy}};
    if (f.kind == "cone" && b - a > 0.0) {
      // Steady lag and waviness over the cone's second half (after the transient).
      // Waviness: peak-to-peak of δy about its straight-line trend (a load that falls along the
      // cone tilts δy; that drift is not waviness).
      double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0, last = std::nan("");
      for (std::size_t i = 0; i < cx.size(); ++i)
        if (cx[i] >= 0.5 * (a + b) && cx[i] <= b && std::isfinite(dy[i])) {
          sx += cx[i];
          sy += dy[i];
          sxx += cx[i] * cx[i];
          sxy += cx[i] * dy[i];
          n += 1;
          last = lag[i];
        }
      double wav = 0.0;
      if (n > 2) {
        const double k1 = (n * sxy - sx * sy) / (n * sxx - sx * sx), k0 = (sy - k1 * sx) / n;
        double lo = 1e300, hi = -1e300;
        for (std::size_t i = 0; i < cx.size(); ++i)
          if (cx[i] >= 0.5 * (a + b) && cx[i] <= b && std::isfinite(dy[i])) {
            const double res = dy[i] - (k0 + k1 * cx[i]);
            lo = std::min(lo, res);
            hi = std::max(hi, res);
          }
        wav = hi - lo;
      }
      fj["waviness_um"] = wav;
      fj["lag_end_um"] = json_number(last);
      r.waviness_um = std::max(r.waviness_um, wav);
      if (first_cone) r.steady_lag_um = last;
      first_cone = false;
    }
    r.features.push_back(fj);
  }
}
}  // namespace

io::RunOutput run(const io::Scenario& sc) {
  using namespace io;
  const Settings& st = sc.get<Settings>();
  std::vector<std::unique_ptr<Run>> runs;
  runs.push_back(std::make_unique<Run>());
  run_one(sc, st.rig, st.rig.nonlinear, *runs.back());
  if (!st.compare.empty() && (st.compare == "nonlinear") != st.rig.nonlinear) {
    auto cfg = st.rig;
    if (st.rig.nonlinear) {  // compare with the nonlinear servo's own linearisation
      cfg.linear = runs.front()->rig.linearisation();
      cfg.linear.P0_N =
          st.rig.coulomb_N +
          (st.rig.blank_diameter_m > 0.0 ? runs.front()->rig.recorder().column("load_N")[0] : 0.0);
    }
    runs.push_back(std::make_unique<Run>());
    run_one(sc, cfg, st.compare == "nonlinear", *runs.back());
  }
  const Run& main = *runs.front();
  const auto lin = main.rig.linearisation();
  const double v_pr = main.rig.carriage_speed();

  // The first cone's closed-form steady lag (on the linear(ised) model).
  double alpha = std::nan("");
  for (const auto& f : st.rig.features)
    if (f.kind == "cone") {
      const double y0 = st.rig.profile.y_at(f.x_start_m + 1e-12),
                   y1 = st.rig.profile.y_at(f.x_end_m - 1e-12);
      alpha = std::atan2(y1 - y0, f.x_end_m - f.x_start_m);
      break;
    }
  const double v_t =
      std::isnan(alpha) ? 0.0 : v_pr * std::sin(alpha) / std::sin(alpha + st.rig.beta_rad);
  const double q_dyn = v_t / (lin.C0_per_s * lin.lever_ratio);  // the part beyond the setup offset
  const auto tr = lin.transient(0.0, v_t, v_t);

  RunOutput out;
  json& s = out.summary;
  s["system"] = sc.system;
  s["scenario"] = sc.name;
  s["file"] = sc.file;
  s["label"] = main.label;
  auto metrics = [&](const Run& r) {
    const auto l = r.rig.linearisation();
    return json{{"steady_error_um", json_number(r.steady_lag_um)},
                {"steady_error_formula_um", json_number(q_dyn * 1e6)},
                {"static_offset_um", json_number(r.rig.static_offset_m() * 1e6)},
                {"max_dx_um", json_number(r.max_dx_um)},
                {"max_dy_um", json_number(r.max_dy_um)},
                {"cone_waviness_um", json_number(r.waviness_um)},
                {"damping_ratio", json_number(l.zeta())},
                {"natural_frequency_Hz", json_number(l.omega_n() / (2.0 * std::numbers::pi))},
                {"aperiodic", l.aperiodic()},
                {"E0_N_per_mm", json_number(l.E0_N_per_m * 1e-3)},
                {"C0_per_s", json_number(l.C0_per_s)},
                {"transient_peak_lag_um", json_number(tr.peak_m * 1e6)},
                {"settling_time_s", json_number(tr.settling_s)},
                {"features", r.features}};
  };
  s["metrics"] = metrics(main);
  if (runs.size() > 1)
    s["comparison"] = {{"label", runs[1]->label}, {"metrics", metrics(*runs[1])}};

  Claims claims;
  if (!std::isnan(alpha) && !st.rig.nonlinear) {
    // Steady error on the cone = (P0/E0 + V_k/C0)/i; with the setup on the first cylinder the
    // P0/E0 part is tuned out, leaving V_k/(C0·i).
    claims.check("linear: steady lag on the first cone, simulated / (V_k/C0)/i",
                 main.steady_lag_um / (q_dyn * 1e6), Compare::RatioWithin, 1e-3);
  }
  if (runs.size() > 1) {
    const Run& nl = st.rig.nonlinear ? main : *runs[1];
    const Run& li = st.rig.nonlinear ? *runs[1] : main;
    claims.note(
        "Cone waviness (peak-to-peak δy over each cone's second half): nonlinear " +
        fmt(nl.waviness_um) + " µm, linear " + fmt(li.waviness_um, "%.3g") + " µm" +
        (nl.waviness_um > 5.0 * std::max(li.waviness_um, 0.01)
             ? " — the falling friction makes the slide stick and slip; the linear model cannot."
             : "."));
    if (st.rig.static_N > st.rig.coulomb_N)
      claims.add(
          "falling friction: cone waviness nonlinear / linear model (stick-slip the linearisation "
          "misses: > 5 and > 1 µm)",
          nl.waviness_um / std::max(li.waviness_um, 1e-3),
          nl.waviness_um > 1.0 && nl.waviness_um > 5.0 * li.waviness_um);
    if (st.rig.overlap_m > 0.0 && !std::isnan(alpha)) {
      // An extra lag u/i along d shows as δy = −(u/i)·sin(α+β)/cos α at equal x.
      const double expect = st.rig.overlap_m / st.rig.linear.lever_ratio *
                            std::sin(alpha + st.rig.beta_rad) / std::cos(alpha) * 1e6;
      claims.check("dead zone: extra |δy| on the slow cone against (u/i)·sin(α+β)/cos α = " +
                       fmt(expect) + " µm (ratio)",
                   (nl.max_dy_um - li.max_dy_um) / expect, Compare::RatioWithin, 0.1);
    }
    claims.note("Largest errors: nonlinear δx " + fmt(nl.max_dx_um) + " µm, δy " +
                fmt(nl.max_dy_um) + " µm; linear δx " + fmt(li.max_dx_um) + " µm, δy " +
                fmt(li.max_dy_um) + " µm.");
  }
  claims.note("Linear(ised) slide: ζ = " + fmt(lin.zeta(), "%.3f") +
              (lin.aperiodic() ? " (aperiodic)" : " (oscillatory)") +
              ", f_n = " + fmt(lin.omega_n() / (2.0 * std::numbers::pi)) +
              " Hz; at the cylinder→cone corner the lag peaks at " + fmt(tr.peak_m * 1e6) +
              " µm and settles (2 %) in " + fmt(tr.settling_s, "%.3f") + " s.");
  s["claims"] = claims.json();

  Report& rep = out.report;
  rep.title = "System C — " + sc.name;
  rep.doc_page = "system-c-tracer.md";
  rep.subtitle =
      sc.file + " · " + main.label + (runs.size() > 1 ? " against " + runs[1]->label : "");
  rep.description = sc.description;
  auto add = [&](const std::string& k, double v, const char* f = "%.4g") {
    rep.metrics.emplace_back(k, fmt(v, f));
  };
  add("carriage speed V_pr [mm/s]", v_pr * 1e3);
  add("steady lag on the first cone, simulated [µm]", main.steady_lag_um);
  add("steady lag, (V_k/C0)/i [µm]", q_dyn * 1e6);
  add("static offset P0/(E0·i), set up on the first cylinder [µm]",
      main.rig.static_offset_m() * 1e6);
  add("max |δx| [µm]", main.max_dx_um);
  add("max |δy| [µm]", main.max_dy_um);
  add("damping ratio ζ", lin.zeta(), "%.3f");
  add("natural frequency [Hz]", lin.omega_n() / (2.0 * std::numbers::pi));
  add("peak lag at cylinder→cone [µm]", tr.peak_m * 1e6);
  add("settling time [s]", tr.settling_s, "%.3f");
  if (runs.size() > 1) {
    add("max |δx|, " + runs[1]->label + " [µm]", runs[1]->max_dx_um);
    add("max |δy|, " + runs[1]->label + " [µm]", runs[1]->max_dy_um);
  }
  rep.notes = claims.notes();
  rep.note_ids = claims.note_ids();
  for (const auto& r : runs) {
    Table t{"Errors per feature — " + r->label,
            {"feature", "from [mm]", "to [mm]", "max |δx| [µm]", "max |δy| [µm]", "waviness [µm]"},
            {}};
    // δx is defined only where the template is steeper than 10° (or at a shoulder): elsewhere
    // the table says so instead of showing the 0 of an empty maximum.
    const auto tx = r->rig.recorder().column("tool_x_mm");
    const auto dx = r->rig.recorder().column("dx_um");
    const auto dx_defined = [&](double a, double b) {
      if (b <= a) {  // a shoulder: its zone
        a -= kShoulderZone_mm;
        b += kShoulderZone_mm;
      }
      for (std::size_t i = 0; i < dx.size(); ++i)
        if (tx[i] >= a && tx[i] <= b && std::isfinite(dx[i])) return true;
      return false;
    };
    for (const auto& f : r->features)
      t.rows.push_back(
          {f["type"].get<std::string>(), fmt(f["x_start_mm"].get<double>()),
           fmt(f["x_end_mm"].get<double>()),
           dx_defined(f["x_start_mm"].get<double>(), f["x_end_mm"].get<double>())
               ? fmt(f["max_dx_um"].get<double>(), "%.2f")
               : "— (under 10°)",
           fmt(f["max_dy_um"].get<double>(), "%.2f"),
           f.contains("waviness_um") ? fmt(f["waviness_um"].get<double>(), "%.2f") : "—"});
    rep.tables.push_back(t);
  }
  const char* colors[] = {"#1f77b4", "#d62728"};
  // The plots along x share the template's x range, so they line up one under the other.
  const double x_lo = st.rig.profile.xs().front() * 1e3, x_hi = st.rig.profile.xs().back() * 1e3;
  // Profiles with the error magnified so it shows at the scale of the part.
  {
    double ymin = 1e300, ymax = -1e300;
    for (double y : st.rig.profile.ys()) {
      ymin = std::min(ymin, y);
      ymax = std::max(ymax, y);
    }
    const double err = std::max(main.max_dy_um, 1e-3) * 1e-6;
    const double k =
        std::max(1.0, std::pow(10.0, std::floor(std::log10(0.1 * (ymax - ymin + 1e-3) / err))));
    Plot pp{"Template and part profile (radius), error magnified ×" + fmt(k, "%.0f"),
            "x [mm]",
            "radius [mm]",
            {},
            {}};
    Series tpl{"template", {}, {}, "#555", true, false};
    for (std::size_t i = 0; i < st.rig.profile.xs().size(); ++i) {
      tpl.x.push_back(st.rig.profile.xs()[i] * 1e3);
      tpl.y.push_back(st.rig.profile.ys()[i] * 1e3);
    }
    pp.series.push_back(tpl);
    for (std::size_t j = 0; j < runs.size(); ++j) {
      const auto& rec = runs[j]->rig.recorder();
      Series part{"part, " + runs[j]->label + " (error ×" + fmt(k, "%.0f") + ")",
                  column(rec, "tool_x_mm"),
                  column(rec, "template_y_mm"),
                  colors[j % 2],
                  false,
                  false};
      const auto dy = rec.column("dy_um");
      for (std::size_t i = 0; i < part.y.size(); ++i) part.y[i] += k * dy[i] * 1e-3;
      pp.series.push_back(part);
    }
    for (const auto& f : st.rig.features) pp.markers.push_back({f.x_start_m * 1e3, f.kind});
    pp.x_min = x_lo;
    pp.x_max = x_hi;
    rep.plots.push_back(pp);
  }
  Plot pdy{"Radial error δy(x) at equal x", "x [mm]", "δy [µm]", {}, {}};
  Plot pdx{"Axial error δx(y) at equal y (on sloped features)", "x [mm]", "δx [µm]", {}, {}};
  Plot plag{"Following lag along the slide, s_T − s (setup offset removed)",
            "time [s]",
            "lag [µm]",
            {},
            {}};
  Plot pv{"Slide speed", "time [s]", "speed [mm/s]", {}, {}};
  for (std::size_t j = 0; j < runs.size(); ++j) {
    const auto& rec = runs[j]->rig.recorder();
    pdy.series.push_back({runs[j]->label, column(rec, "tool_x_mm"), column(rec, "dy_um"),
                          colors[j % 2], false, false});
    pdx.series.push_back({runs[j]->label, column(rec, "tool_x_mm"), column(rec, "dx_um"),
                          colors[j % 2], false, false});
    plag.series.push_back({runs[j]->label, column(rec, "time_s"), column(rec, "lag_um"),
                           colors[j % 2], false, false});
    pv.series.push_back({runs[j]->label, column(rec, "time_s"), column(rec, "slide_speed_mm_per_s"),
                         colors[j % 2], false, false});
  }
  for (const auto& f : st.rig.features) {
    pdy.markers.push_back({f.x_start_m * 1e3, f.kind});
    pdx.markers.push_back({f.x_start_m * 1e3, f.kind});
  }
  bool any_dx = false;
  for (const Series& sr : pdx.series)
    any_dx = any_dx ||
             std::any_of(sr.y.begin(), sr.y.end(), [](double v) { return std::isfinite(v); });
  if (!any_dx) pdy.title += " (no feature steeper than 10°: δx at equal y not defined)";
  for (Plot* p : {&pdy, &pdx}) {
    p->x_min = x_lo;
    p->x_max = x_hi;
  }
  rep.plots.push_back(pdy);
  if (any_dx) rep.plots.push_back(pdx);
  rep.plots.push_back(plag);
  rep.plots.push_back(pv);

  out.channels_csv = channels_csv(main.rig.recorder());
  if (runs.size() > 1) out.compare_csv = channels_csv(runs[1]->rig.recorder());
  out.headline =
      main.label + ": max δx " + fmt(main.max_dx_um) + " µm, δy " + fmt(main.max_dy_um) +
      " µm, ζ " + fmt(lin.zeta(), "%.2f") +
      (runs.size() > 1 ? "; " + runs[1]->label + " δy " + fmt(runs[1]->max_dy_um) + " µm" : "");
  return out;
}

}  // namespace lathectl::systems::c_tracer
