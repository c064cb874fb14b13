// System B's report (io::Study::report): its metrics, the time plots and the stability chart.
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

namespace lathectl::systems::b_chatter::detail {

void ChatterStudy::report(io::Report& rep) {
  rep.title = "System B — " + sc_.name;
  rep.doc_page = "system-b-chatter.md";
  rep.subtitle = sc_.file + " · " + main().label +
                 (b_.setup == TwinSetup::FeedDivision    ? " · feed division"
                  : b_.setup == TwinSetup::DepthDivision ? " · depth division"
                                                         : " · one tool");
  report_metrics(rep);
  time_plots(rep);
  rep.plots.push_back(stability_plot());
}

void ChatterStudy::report_metrics(io::Report& rep) const {
  const Run& m = main();
  auto add = [&](const std::string& k, double v, const char* f = "%.4g") {
    rep.metrics.emplace_back(k, fmt(v, f));
  };
  if (off_) add("vibration, no modulation [µm]", off_->vibration_um);
  if (modulated_) add("vibration, " + m.label + " [µm]", m.vibration_um);
  add("dead zone [µm]", dead_zone_um_);
  add("chatter frequency [Hz]", (off_ ? *off_ : m).chatter_Hz);
  add("programmed feed per turret [mm/min]", s_prog_);
  if (modulated_) {
    const auto& o = mo();
    add("mean feed, modulated turret [mm/min]", m.feed_mean[turret_]);
    add("S_min [mm/min]", o.plan.s_min_mm_per_min);
    add("ΔS [mm/min]", o.plan.ds_mm_per_min);
    add("Δl [mm]", o.plan.dl_mm);
    add("n_s", o.plan.n_s, "%.0f");
    add("ω_m/2π [Hz]", o.omega_m_rad_per_s / (2.0 * std::numbers::pi));
    add("A_P required [N]", o.force_amplitude_required_N);
    add("A_P planned [N]", o.force_amplitude_planned_N);
  }
  add("forced deflection (below the chatter band) [µm]", m.forced_um);
  add("static deflection (mean y) [µm]", m.static_um);
  add("cutting power (true) [W]", m.cut_power_W);
  add("cutting power measured N_c [W]", m.cut_power_measured_W);
  // The surface: the feed marks along the part, then with the vibration's 2a added.
  add("Rz at the programmed feed (marks) [µm]", m.surface.Rz_programmed_um);
  const auto surface = [&](const Run& r, const std::string& label) {
    rep.metrics.emplace_back("Rz along the part, " + label + ": min / mean / max [µm]",
                             fmt(r.surface.Rz_min_um, "%.3g") + " / " +
                                 fmt(r.surface.Rz_mean_um, "%.3g") + " / " +
                                 fmt(r.surface.Rz_max_um, "%.3g"));
    add("Ra along the part (mean), " + label + " [µm]", r.surface.Ra_mean_um, "%.3g");
    add("Rz with the vibration (+2a), " + label + " [µm]",
        r.surface.Rz_mean_um + 2.0 * r.vibration_um, "%.3g");
  };
  if (off_) surface(*off_, "no modulation");
  surface(m, m.label);
}

void ChatterStudy::time_plots(io::Report& rep) const {
  const Run& m = main();
  auto series = [&](const Run& r, const char* col, const std::string& name, const char* color,
                    bool dashed = false) {
    return io::recorded_series(r.rig.recorder(), col, name, color, dashed);
  };
  // The unmodulated run chatters at hundreds of µm, the modulated one stays near 0.1 µm: each
  // gets its own panel (same time axis), or the smaller would be a flat line beside the other.
  const std::vector<const Run*> panels =
      off_ && off_ != &m ? std::vector<const Run*>{off_, &m} : std::vector<const Run*>{&m};
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
    Plot p = panel("Part displacement at the tool, " + r.label, "y [µm]");
    p.series.push_back(series(r, "y_um", r.label, kColors[panels.size() == 2 ? k : 1]));
    if (r.rig.engaged_at_s() >= 0.0) p.markers.push_back({r.rig.engaged_at_s(), "engaged"});
    p.markers.push_back({r.t0, "steady window"});
    rep.plots.push_back(p);
  }
  for (std::size_t k = 0; k < panels.size(); ++k) {
    const Run& r = *panels[k];
    Plot p = panel("Chatter band (high-pass " + fmt(b_.vibration.highpass_Hz) + " Hz), " + r.label,
                   "y_hp [µm]");
    p.series.push_back(series(r, "y_highpass_um", r.label, kColors[panels.size() == 2 ? k : 1]));
    rep.plots.push_back(p);
  }
  if (modulated_) {
    Plot p{"Feed rates (" + m.label + ")", "time [s]", "feed [mm/min]", {}, {}};
    p.series.push_back(series(m, "feed1_mm_per_min", "right turret", "#2ca02c"));
    if (twin_) p.series.push_back(series(m, "feed2_mm_per_min", "left turret", "#9467bd"));
    rep.plots.push_back(p);
    Plot c{"Chip per tool (" + m.label + ")", "time [s]", "chip [mm]", {}, {}};
    c.series.push_back(series(m, "chip1_mm", "right", "#2ca02c"));
    if (twin_) c.series.push_back(series(m, "chip2_mm", "left", "#9467bd"));
    rep.plots.push_back(c);
  }
  // Two panels: the amplitude in µm and the detected frequency in Hz share no axis.
  const Run& r = off_ && off_ != &m ? *off_ : m;
  Plot a0 = panel("Measurement chain: amplitude a0 (ADC 19), " + r.label, "a0 [µm]");
  a0.series.push_back(series(r, "a0_um", "a0, " + r.label, "#ff7f0e"));
  rep.plots.push_back(a0);
  Plot wd = panel("Measurement chain: frequency ω_d/2π (detector 20), " + r.label, "f [Hz]");
  wd.series.push_back(series(r, "omega_d_Hz", "ω_d/2π, " + r.label, "#8c564b"));
  rep.plots.push_back(wd);
  Plot p{"Cutting power: true and measured (N_m − N_idle)", "time [s]", "power [W]", {}, {}};
  p.series.push_back(series(m, "cut_power_W", "true", "#555"));
  p.series.push_back(series(m, "cut_power_measured_W", "measured N_c", "#17becf"));
  rep.plots.push_back(p);
}

// The machine's own stability chart at the softest position of the cut: the feed per revolution
// above which the regenerative loop is unstable, against the spindle speed.
Plot ChatterStudy::stability_plot() const {
  Plot p{"Stability limits at z = " + fmt(lim_x_) + " mm (linear, the set-up's delay equation)",
         "spindle speed [rpm]",
         "feed per revolution [mm/rev]",
         {},
         {}};
  Series one{"one tool (τ, +μ)", {}, {}, "#1f77b4", false, false};
  Series two{"feed division (τ/2, −μ)", {}, {}, "#d62728", false, false};
  for (int k = 0; k <= 160; ++k) {
    const double n = b_.rpm * (0.7 + 0.6 * k / 160.0);
    const Limits l = linear_limits(b_, lim_x_, n, 6000);
    one.x.push_back(n);
    one.y.push_back(l.single_feed);
    if (std::isfinite(l.twin_feed)) {
      two.x.push_back(n);
      two.y.push_back(l.twin_feed);
    }
  }
  p.series.push_back(one);
  if (!two.x.empty()) p.series.push_back(two);
  p.series.push_back({"programmed", {b_.rpm}, {b_.feed_mm_per_rev}, "#000", false, true});
  p.markers.push_back({b_.rpm, "programmed speed"});
  return p;
}

}  // namespace lathectl::systems::b_chatter::detail
