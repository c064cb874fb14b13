#include "systems/c_tracer/study.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "lathectl/io/channel_stream.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/study.hpp"
#include "lathectl/io/verdict.hpp"
#include "systems/c_tracer/metrics.hpp"
#include "systems/c_tracer/settings.hpp"

namespace lathectl::systems::c_tracer {

namespace {
using namespace io;
using nlohmann::json;

struct Run {
  Rig rig;
  std::unique_ptr<TracerMetrics> acc;        // fed as the rig records
  std::unique_ptr<io::ChannelStream> csv;    // channels.csv / channels_compare.csv
  std::string label;
  double max_dx_um = 0.0, max_dy_um = 0.0, steady_lag_um = std::nan(""), waviness_um = 0.0;
  json features = json::array();
};

// The rig records streamed (its memory bounded whatever the template's length, the feed and the
// record interval): the metrics are accumulated row by row, the result file `csv` is written into
// `stage` as the rows come (in memory without one). kept_rows: TracerMetrics' budget of cone rows.
void run_one(const io::Scenario& sc, RigConfig cfg, bool nonlinear, Run& r, std::size_t kept_rows,
             const char* csv, io::OutputStage* stage) {
  cfg.nonlinear = nonlinear;
  r.rig.set_streamed(true);
  configure_rig(sc, r.rig, cfg);
  r.acc = std::make_unique<TracerMetrics>(r.rig.recorder(), cfg.features, kept_rows);
  r.rig.attach(r.acc.get());
  r.csv = io::open_channel_stream(sc, stage, csv, r.rig.recorder().channels(),
                                  static_cast<double>(r.rig.max_rows()), "run.record_interval_s",
                                  "raise run.record_interval_s, machine.feed_mm_per_rev or "
                                  "machine.spindle_rpm, shorten the template");
  r.rig.attach(r.csv.get());
  run_rig(sc, r.rig);
  r.csv->finish();
  if (!r.acc->finish()) {
    // More rows in a cone's window than were kept: the residuals from a second, identical run.
    Rig again;
    again.set_streamed(true);
    configure_rig(sc, again, cfg);
    again.attach(&r.acc->residuals());
    run_rig(sc, again);
  }
  r.label = nonlinear ? "nonlinear servo" : "linear model (8)-(9)";
  const TracerMetrics& m = *r.acc;
  r.max_dx_um = m.max_dx_um();
  r.max_dy_um = m.max_dy_um();
  bool first_cone = true;
  for (std::size_t i = 0; i < cfg.features.size(); ++i) {
    const auto& f = cfg.features[i];
    json fj = {{"type", f.kind},
               {"x_start_mm", f.x_start_m * 1e3},
               {"x_end_mm", f.x_end_m * 1e3},
               {"max_dx_um", m.features()[i].max_dx_um},
               {"max_dy_um", m.features()[i].max_dy_um}};
    for (const ConeWindow& w : m.cones()) {
      if (w.feature != i) continue;
      // Waviness: peak-to-peak of δy about its straight-line trend (a load that falls along the
      // cone tilts δy; that drift is not waviness).
      const double wav = w.waviness_um();
      fj["waviness_um"] = wav;
      fj["lag_end_um"] = json_number(w.last_lag_um);
      r.waviness_um = std::max(r.waviness_um, wav);
      if (first_cone) r.steady_lag_um = w.last_lag_um;
      first_cone = false;
    }
    r.features.push_back(fj);
  }
}

// A recorded channel against time, decimated to a bounded number of points (sim::Recorder).
Series along_time(const Run& r, const char* channel, std::string name, std::string color) {
  Series s{std::move(name), {}, {}, std::move(color), false, false};
  r.rig.recorder().plot_points(channel, s.x, s.y);
  s.pyramid = r.rig.recorder().plot_pyramid(channel);
  return s;
}

// δy or δx against the tool's x, from its pyramid.
Series along_x(const sim::PlotPyramid& p, std::string name, std::string color) {
  Series s{std::move(name), {}, {}, std::move(color), false, false};
  s.pyramid = p.finished();
  s.pyramid->points(s.x, s.y);
  return s;
}

const char* const kColors[] = {"#1f77b4", "#d62728"};

// The template copied by the slide (the scenario's model and, to compare, the other one), the
// closed-form lag on the first cone beside it.
class TracerStudy final : public io::Study {
 public:
  TracerStudy(const io::Scenario& sc, std::size_t kept_rows)
      : Study(sc), st_(sc.get<Settings>()), kept_rows_(kept_rows) {}

 private:
  void run_controllers() override;
  void check_claims(Claims& claims) override;
  void summary(json& s) override;
  void report(Report& rep) override;
  void finish(RunOutput& out) override;

  void closed_form();
  void comparison_claims(Claims& claims) const;
  [[nodiscard]] json metrics(const Run& r) const;
  void report_metrics(Report& rep) const;
  void feature_tables(Report& rep) const;
  void profile_plot(Report& rep, double x_lo, double x_hi) const;
  void error_plots(Report& rep, double x_lo, double x_hi) const;
  [[nodiscard]] const Run& main() const { return *runs_.front(); }

  const Settings& st_;
  std::size_t kept_rows_;
  std::vector<std::unique_ptr<Run>> runs_;  // the scenario's model, then the other one
  hydraulics::TracerLinear lin_;            // the main run's linear(ised) slide
  double v_pr_ = 0.0;                       // carriage speed
  double alpha_ = std::nan("");             // the first cone's angle
  double q_dyn_ = 0.0;  // its closed-form steady lag beyond the setup offset, (V_k/C0)/i
  hydraulics::TracerLinear::Transient tr_;  // at the cylinder→cone corner
};

void TracerStudy::run_controllers() {
  OutputStage* stage = StreamScope::current();
  runs_.push_back(std::make_unique<Run>());
  run_one(sc_, st_.rig, st_.rig.nonlinear, *runs_.back(), kept_rows_, "channels.csv", stage);
  if (!st_.compare.empty() && (st_.compare == "nonlinear") != st_.rig.nonlinear) {
    auto cfg = st_.rig;
    if (st_.rig.nonlinear) {  // compare with the nonlinear servo's own linearisation
      cfg.linear = main().rig.linearisation();
      cfg.linear.P0_N =
          st_.rig.coulomb_N + (st_.rig.blank_diameter_m > 0.0 ? main().acc->first_load_N() : 0.0);
    }
    runs_.push_back(std::make_unique<Run>());
    run_one(sc_, cfg, st_.compare == "nonlinear", *runs_.back(), kept_rows_, "channels_compare.csv",
            stage);
  }
  closed_form();
}

// The first cone's closed-form steady lag (on the linear(ised) model).
void TracerStudy::closed_form() {
  lin_ = main().rig.linearisation();
  v_pr_ = main().rig.carriage_speed();
  for (const auto& f : st_.rig.features)
    if (f.kind == "cone") {
      const double y0 = st_.rig.profile.y_at(f.x_start_m + 1e-12),
                   y1 = st_.rig.profile.y_at(f.x_end_m - 1e-12);
      alpha_ = std::atan2(y1 - y0, f.x_end_m - f.x_start_m);
      break;
    }
  const double v_t =
      std::isnan(alpha_) ? 0.0 : v_pr_ * std::sin(alpha_) / std::sin(alpha_ + st_.rig.beta_rad);
  q_dyn_ = v_t / (lin_.C0_per_s * lin_.lever_ratio);  // the part beyond the setup offset
  tr_ = lin_.transient(0.0, v_t, v_t);
}

void TracerStudy::check_claims(Claims& claims) {
  if (!std::isnan(alpha_) && !st_.rig.nonlinear) {
    // Steady error on the cone = (P0/E0 + V_k/C0)/i; with the setup on the first cylinder the
    // P0/E0 part is tuned out, leaving V_k/(C0·i).
    claims.check("linear: steady lag on the first cone, simulated / (V_k/C0)/i",
                 main().steady_lag_um / (q_dyn_ * 1e6), Compare::RatioWithin, 1e-3);
  }
  if (runs_.size() > 1) comparison_claims(claims);
  claims.note("Linear(ised) slide: ζ = " + fmt(lin_.zeta(), "%.3f") +
              (lin_.aperiodic() ? " (aperiodic)" : " (oscillatory)") +
              ", f_n = " + fmt(lin_.omega_n() / (2.0 * std::numbers::pi)) +
              " Hz; at the cylinder→cone corner the lag peaks at " + fmt(tr_.peak_m * 1e6) +
              " µm and settles (2 %) in " + fmt(tr_.settling_s, "%.3f") + " s.");
}

// The nonlinear servo against the linear model.
void TracerStudy::comparison_claims(Claims& claims) const {
  const Run& nl = st_.rig.nonlinear ? main() : *runs_[1];
  const Run& li = st_.rig.nonlinear ? *runs_[1] : main();
  claims.note(
      "Cone waviness (peak-to-peak δy over each cone's second half): nonlinear " +
      fmt(nl.waviness_um) + " µm, linear " + fmt(li.waviness_um, "%.3g") + " µm" +
      (nl.waviness_um > 5.0 * std::max(li.waviness_um, 0.01)
           ? " — the falling friction makes the slide stick and slip; the linear model cannot."
           : "."));
  if (st_.rig.static_N > st_.rig.coulomb_N)
    claims.add(
        "falling friction: cone waviness nonlinear / linear model (stick-slip the linearisation "
        "misses: > 5 and > 1 µm)",
        nl.waviness_um / std::max(li.waviness_um, 1e-3),
        nl.waviness_um > 1.0 && nl.waviness_um > 5.0 * li.waviness_um);
  if (st_.rig.overlap_m > 0.0 && !std::isnan(alpha_)) {
    // An extra lag u/i along d shows as δy = −(u/i)·sin(α+β)/cos α at equal x.
    const double expect = st_.rig.overlap_m / st_.rig.linear.lever_ratio *
                          std::sin(alpha_ + st_.rig.beta_rad) / std::cos(alpha_) * 1e6;
    claims.check("dead zone: extra |δy| on the slow cone against (u/i)·sin(α+β)/cos α = " +
                     fmt(expect) + " µm (ratio)",
                 (nl.max_dy_um - li.max_dy_um) / expect, Compare::RatioWithin, 0.1);
  }
  claims.note("Largest errors: nonlinear δx " + fmt(nl.max_dx_um) + " µm, δy " + fmt(nl.max_dy_um) +
              " µm; linear δx " + fmt(li.max_dx_um) + " µm, δy " + fmt(li.max_dy_um) + " µm.");
}

json TracerStudy::metrics(const Run& r) const {
  const auto l = r.rig.linearisation();
  return json{{"steady_error_um", json_number(r.steady_lag_um)},
              {"steady_error_formula_um", json_number(q_dyn_ * 1e6)},
              {"static_offset_um", json_number(r.rig.static_offset_m() * 1e6)},
              {"max_dx_um", json_number(r.max_dx_um)},
              {"max_dy_um", json_number(r.max_dy_um)},
              {"cone_waviness_um", json_number(r.waviness_um)},
              {"damping_ratio", json_number(l.zeta())},
              {"natural_frequency_Hz", json_number(l.omega_n() / (2.0 * std::numbers::pi))},
              {"aperiodic", l.aperiodic()},
              {"E0_N_per_mm", json_number(l.E0_N_per_m * 1e-3)},
              {"C0_per_s", json_number(l.C0_per_s)},
              {"transient_peak_lag_um", json_number(tr_.peak_m * 1e6)},
              {"settling_time_s", json_number(tr_.settling_s)},
              {"features", r.features}};
}

void TracerStudy::summary(json& s) {
  s["label"] = main().label;
  s["metrics"] = metrics(main());
  if (runs_.size() > 1)
    s["comparison"] = {{"label", runs_[1]->label}, {"metrics", metrics(*runs_[1])}};
  // The user's part is the main run's.
  Acceptance acceptance(st_.acceptance);
  acceptance.judge("max_profile_error_um", main().max_dy_um);
  acceptance.judge("max_axial_error_um", main().max_dx_um);
  acceptance.judge("max_waviness_um", main().waviness_um);
  s["acceptance"] = acceptance.json();
}

void TracerStudy::report(Report& rep) {
  rep.title = "System C — " + sc_.name;
  rep.doc_page = "system-c-tracer.md";
  rep.subtitle =
      sc_.file + " · " + main().label + (runs_.size() > 1 ? " against " + runs_[1]->label : "");
  report_metrics(rep);
  feature_tables(rep);
  // The plots along x share the template's x range, so they line up one under the other.
  const double x_lo = st_.rig.profile.xs().front() * 1e3, x_hi = st_.rig.profile.xs().back() * 1e3;
  profile_plot(rep, x_lo, x_hi);
  error_plots(rep, x_lo, x_hi);
}

void TracerStudy::report_metrics(Report& rep) const {
  auto add = [&](const std::string& k, double v, const char* f = "%.4g") {
    rep.metrics.emplace_back(k, fmt(v, f));
  };
  add("carriage speed V_pr [mm/s]", v_pr_ * 1e3);
  add("steady lag on the first cone, simulated [µm]", main().steady_lag_um);
  add("steady lag, (V_k/C0)/i [µm]", q_dyn_ * 1e6);
  add("static offset P0/(E0·i), set up on the first cylinder [µm]",
      main().rig.static_offset_m() * 1e6);
  add("max |δx| [µm]", main().max_dx_um);
  add("max |δy| [µm]", main().max_dy_um);
  add("damping ratio ζ", lin_.zeta(), "%.3f");
  add("natural frequency [Hz]", lin_.omega_n() / (2.0 * std::numbers::pi));
  add("peak lag at cylinder→cone [µm]", tr_.peak_m * 1e6);
  add("settling time [s]", tr_.settling_s, "%.3f");
  if (runs_.size() > 1) {
    add("max |δx|, " + runs_[1]->label + " [µm]", runs_[1]->max_dx_um);
    add("max |δy|, " + runs_[1]->label + " [µm]", runs_[1]->max_dy_um);
  }
}

void TracerStudy::feature_tables(Report& rep) const {
  for (const auto& r : runs_) {
    Table t{"Errors per feature — " + r->label,
            {"feature", "from [mm]", "to [mm]", "max |δx| [µm]", "max |δy| [µm]", "waviness [µm]"},
            {}};
    // δx is defined only where the template is steeper than 10° (or at a shoulder): elsewhere
    // the table says so instead of showing the 0 of an empty maximum.
    for (std::size_t i = 0; i < r->features.size(); ++i) {
      const auto& f = r->features[i];
      t.rows.push_back(
          {f["type"].get<std::string>(), fmt(f["x_start_mm"].get<double>()),
           fmt(f["x_end_mm"].get<double>()),
           r->acc->features()[i].dx_defined ? fmt(f["max_dx_um"].get<double>(), "%.2f")
                                            : "— (under 10°)",
           fmt(f["max_dy_um"].get<double>(), "%.2f"),
           f.contains("waviness_um") ? fmt(f["waviness_um"].get<double>(), "%.2f") : "—"});
    }
    rep.tables.push_back(t);
  }
}

// Profiles with the error magnified so it shows at the scale of the part.
void TracerStudy::profile_plot(Report& rep, double x_lo, double x_hi) const {
  const auto& profile = st_.rig.profile;
  double ymin = 1e300, ymax = -1e300;
  for (double y : profile.ys()) {
    ymin = std::min(ymin, y);
    ymax = std::max(ymax, y);
  }
  const double err = std::max(main().max_dy_um, 1e-3) * 1e-6;
  const double k =
      std::max(1.0, std::pow(10.0, std::floor(std::log10(0.1 * (ymax - ymin + 1e-3) / err))));
  Plot pp{"Template and part profile (radius), error magnified ×" + fmt(k, "%.0f"),
          "x [mm]",
          "radius [mm]",
          {},
          {}};
  Series tpl{"template", {}, {}, "#555", true, false};
  for (std::size_t i = 0; i < profile.xs().size(); ++i) {
    tpl.x.push_back(profile.xs()[i] * 1e3);
    tpl.y.push_back(profile.ys()[i] * 1e3);
  }
  pp.series.push_back(tpl);
  for (std::size_t j = 0; j < runs_.size(); ++j) {
    // The template under the tool plus the magnified δy, at δy's decimated points (its
    // pyramid's extremes: the template changes little within a bucket).
    Series part{"part, " + runs_[j]->label + " (error ×" + fmt(k, "%.0f") + ")",
                {},
                {},
                kColors[j % 2],
                false,
                false};
    runs_[j]->acc->dy_along_x().points(part.x, part.y);
    for (std::size_t i = 0; i < part.y.size(); ++i)
      part.y[i] = profile.y_at(part.x[i] * 1e-3) * 1e3 + k * part.y[i] * 1e-3;
    pp.series.push_back(part);
  }
  for (const auto& f : st_.rig.features) pp.markers.push_back({f.x_start_m * 1e3, f.kind});
  pp.x_min = x_lo;
  pp.x_max = x_hi;
  rep.plots.push_back(pp);
}

void TracerStudy::error_plots(Report& rep, double x_lo, double x_hi) const {
  Plot pdy{"Radial error δy(x) at equal x", "x [mm]", "δy [µm]", {}, {}};
  Plot pdx{"Axial error δx(y) at equal y (on sloped features)", "x [mm]", "δx [µm]", {}, {}};
  Plot plag{"Following lag along the slide, s_T − s (setup offset removed)",
            "time [s]",
            "lag [µm]",
            {},
            {}};
  Plot pv{"Slide speed", "time [s]", "speed [mm/s]", {}, {}};
  bool any_dx = false;
  for (std::size_t j = 0; j < runs_.size(); ++j) {
    const Run& r = *runs_[j];
    pdy.series.push_back(along_x(r.acc->dy_along_x(), r.label, kColors[j % 2]));
    pdx.series.push_back(along_x(r.acc->dx_along_x(), r.label, kColors[j % 2]));
    plag.series.push_back(along_time(r, "lag_um", r.label, kColors[j % 2]));
    pv.series.push_back(along_time(r, "slide_speed_mm_per_s", r.label, kColors[j % 2]));
    any_dx = any_dx || r.acc->any_dx();
  }
  for (const auto& f : st_.rig.features) {
    pdy.markers.push_back({f.x_start_m * 1e3, f.kind});
    pdx.markers.push_back({f.x_start_m * 1e3, f.kind});
  }
  if (!any_dx) pdy.title += " (no feature steeper than 10°: δx at equal y not defined)";
  for (Plot* p : {&pdy, &pdx}) {
    p->x_min = x_lo;
    p->x_max = x_hi;
  }
  rep.plots.push_back(pdy);
  if (any_dx) rep.plots.push_back(pdx);
  rep.plots.push_back(plag);
  rep.plots.push_back(pv);
}

void TracerStudy::finish(RunOutput& out) {
  // channels.csv (and channels_compare.csv) were streamed into the stage; without one (a
  // library caller) they were collected in memory.
  out.channels_csv = main().csv->take_text();
  out.channels_values = main().csv->take_values();
  if (runs_.size() > 1) out.compare_csv = runs_[1]->csv->take_text();
  out.headline =
      main().label + ": max δx " + fmt(main().max_dx_um) + " µm, δy " + fmt(main().max_dy_um) +
      " µm, ζ " + fmt(lin_.zeta(), "%.2f") +
      (runs_.size() > 1 ? "; " + runs_[1]->label + " δy " + fmt(runs_[1]->max_dy_um) + " µm" : "");
}
}  // namespace

io::RunOutput run(const io::Scenario& sc) {
  return run(sc, TracerMetrics::kKeptRows);
}

io::RunOutput run(const io::Scenario& sc, std::size_t kept_rows) {
  return TracerStudy(sc, kept_rows).run();
}

}  // namespace lathectl::systems::c_tracer
