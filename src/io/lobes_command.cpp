#include "lathectl/io/lobes_command.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <thread>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/report.hpp"
#include "lathectl/io/study.hpp"
#include "lathectl/io/toml_reader.hpp"

namespace lathectl::io {

LobesInput load_lobes_input(const std::string& path) {
  const TomlDocument doc = TomlDocument::parse_file(path);
  TableReader root(doc.root(), path, "");
  LobesInput in;
  auto c = root.table("cutting", true);
  in.system.kf_N_per_m2 = c->number("kf_N_per_mm2", {0.0, 1e6, true, false}) * 1e6;
  c->finish();
  for (auto& m : root.tables("mode")) {
    dynamics::Mode md;
    md.stiffness_N_per_m = m.number("stiffness_N_per_m", {0.0, 1e13, true, false});
    md.damping_ratio = m.number("damping_ratio", {0.0, 1.0, true, true});
    md.natural_frequency_Hz = m.number("natural_frequency_Hz", {0.0, 1e6, true, false});
    md.angle_rad = m.number("angle_deg", Range::closed(-90, 90), 0.0) * std::numbers::pi / 180.0;
    m.finish();
    in.system.modes.push_back(md);
  }
  if (in.system.modes.empty()) root.fail("mode", "at least one [[mode]] expected");
  auto s = root.table("speed", true);
  in.min_rpm = s->number("min_rpm", {0.0, 1e6, true, false});
  in.max_rpm = s->number("max_rpm", {0.0, 1e6, true, false});
  if (!(in.max_rpm > in.min_rpm)) s->fail("max_rpm", "must exceed min_rpm");
  s->finish();
  if (auto l = root.table("lobes")) {
    in.max_lobes = static_cast<int>(l->integer("max_lobes", 1, 500, 40));
    in.sd_speeds = static_cast<int>(l->integer("sd_speeds", 0, 2000, 40));
    l->finish();
  }
  root.finish();
  return in;
}

nlohmann::json run_lobes(const LobesInput& in, const std::filesystem::path& out_dir) {
  using nlohmann::json;
  const auto fd =
      dynamics::frequency_domain_lobes(in.system, in.min_rpm, in.max_rpm, in.max_lobes, 4000);
  double f_max = 0.0;
  for (const auto& m : in.system.modes) f_max = std::max(f_max, m.natural_frequency_Hz);

  // Semi-discretization at sd_speeds speeds, in parallel; ≥ 20 steps per vibration period.
  std::vector<double> sd_speed(static_cast<std::size_t>(in.sd_speeds)), sd_depth(sd_speed.size()),
      fd_depth(sd_speed.size());
  for (std::size_t k = 0; k < sd_speed.size(); ++k) {
    sd_speed[k] = in.min_rpm + (in.max_rpm - in.min_rpm) * (static_cast<double>(k) + 0.5) /
                                   static_cast<double>(sd_speed.size());
    fd_depth[k] = dynamics::envelope_depth(fd, sd_speed[k]);
  }
  {
    std::vector<std::thread> pool;
    const unsigned n = std::max(1u, std::thread::hardware_concurrency());
    for (unsigned w = 0; w < n; ++w)
      pool.emplace_back([&, w] {
        for (std::size_t k = w; k < sd_speed.size(); k += n) {
          const double tau = 60.0 / sd_speed[k];
          const int m = std::clamp(static_cast<int>(std::ceil(tau * f_max * 20.0)), 20, 160);
          const double hi =
              std::isfinite(fd_depth[k]) ? 3.0 * fd_depth[k] : 100.0 * fd.critical_depth_m;
          sd_depth[k] = dynamics::sd_limit_depth(in.system, sd_speed[k], hi, m, 1e-3);
        }
      });
    for (auto& t : pool) t.join();
  }
  double worst = 0.0;
  for (std::size_t k = 0; k < sd_speed.size(); ++k)
    if (std::isfinite(sd_depth[k]) && std::isfinite(fd_depth[k]))
      worst = std::max(worst, std::abs(sd_depth[k] / fd_depth[k] - 1.0));

  json j;
  j["critical_depth_mm"] = fd.critical_depth_m * 1e3;
  j["chatter_frequency_Hz"] = fd.critical_chatter_Hz;
  if (in.system.modes.size() == 1) {
    const auto& m = in.system.modes[0];
    const double c2 = std::cos(m.angle_rad) * std::cos(m.angle_rad);
    j["closed_form_sdof"] = {
        {"depth_mm", 2.0 * m.stiffness_N_per_m * m.damping_ratio * (1.0 + m.damping_ratio) /
                         (in.system.kf_N_per_m2 * c2) * 1e3},
        {"chatter_frequency_Hz", m.natural_frequency_Hz * std::sqrt(1.0 + 2.0 * m.damping_ratio)}};
  }
  json lobes = json::array();
  for (const auto& l : fd.lobes)
    lobes.push_back({{"N", l.N},
                     {"min_speed_rpm", l.minimum.speed_rpm},
                     {"depth_mm", l.minimum.depth_m * 1e3},
                     {"chatter_frequency_Hz", l.minimum.chatter_Hz}});
  j["lobes"] = lobes;
  json sd = json::array();
  for (std::size_t k = 0; k < sd_speed.size(); ++k)
    sd.push_back({{"speed_rpm", sd_speed[k]},
                  {"depth_mm", json_number(sd_depth[k] * 1e3)},
                  {"frequency_domain_depth_mm", json_number(fd_depth[k] * 1e3)}});
  j["semi_discretization"] = sd;
  j["semi_discretization_max_rel_difference"] = worst;

  // CSV: the frequency-domain envelope on a fine speed grid, and the SD points.
  std::string csv = "speed_rpm,frequency_domain_depth_mm\n";
  Series env{"frequency domain: lower envelope", {}, {}, "#1f77b4", false, false};
  for (int k = 0; k <= 1000; ++k) {
    const double n = in.min_rpm + (in.max_rpm - in.min_rpm) * k / 1000.0;
    const double b = dynamics::envelope_depth(fd, n);
    char buf[96];
    std::snprintf(buf, sizeof buf, "%.6g,%.9g\n", n, b * 1e3);
    csv += buf;
    env.x.push_back(n);
    env.y.push_back(std::isfinite(b) ? b * 1e3 : std::nan(""));
  }
  csv += "\nspeed_rpm,semi_discretization_depth_mm\n";
  Series sdp{"semi-discretization", {}, {}, "#d62728", false, true};
  for (std::size_t k = 0; k < sd_speed.size(); ++k) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%.6g,%.9g\n", sd_speed[k], sd_depth[k] * 1e3);
    csv += buf;
    sdp.x.push_back(sd_speed[k]);
    sdp.y.push_back(std::isfinite(sd_depth[k]) ? sd_depth[k] * 1e3 : std::nan(""));
  }
  Report rep;
  rep.title = "Stability lobes";
  rep.subtitle = std::to_string(in.system.modes.size()) +
                 " mode(s), K_f = " + fmt(in.system.kf_N_per_m2 * 1e-6) + " N/mm²";
  rep.description =
      "Frequency-domain lobes (Tlusty/Tobias/Altintas) and, independently, semi-discretization "
      "(Insperger–Stépán). "
      "Below the envelope the cut is stable; the lobe minima are the absolute stability limit.";
  rep.metrics.emplace_back("absolute stability limit [mm]", fmt(fd.critical_depth_m * 1e3));
  rep.metrics.emplace_back("chatter frequency there [Hz]", fmt(fd.critical_chatter_Hz));
  if (j.contains("closed_form_sdof"))
    rep.metrics.emplace_back("SDOF closed form 2kζ(1+ζ)/(K_f cos²θ) [mm]",
                             fmt(j["closed_form_sdof"]["depth_mm"].get<double>()));
  rep.metrics.emplace_back("semi-discretization vs frequency domain, max relative difference",
                           fmt(worst, "%.3g"));
  Table t{"Lobes", {"N", "speed at the minimum [rpm]", "depth [mm]", "chatter [Hz]"}, {}};
  for (const auto& l : fd.lobes)
    t.rows.push_back({std::to_string(l.N), fmt(l.minimum.speed_rpm, "%.1f"),
                      fmt(l.minimum.depth_m * 1e3), fmt(l.minimum.chatter_Hz)});
  rep.tables.push_back(t);
  double ymax = 0.0;
  for (double y : env.y)
    if (std::isfinite(y)) ymax = std::max(ymax, y);
  Plot p{
      "Stability lobe diagram", "spindle speed [rpm]", "limit depth of cut [mm]", {env, sdp}, {}};
  (void)ymax;
  rep.plots.push_back(p);

  std::filesystem::create_directories(out_dir);
  write_file_atomic(out_dir / "lobes.csv", csv);
  write_file_atomic(out_dir / "lobes.html", render_html(rep));
  write_file_atomic(out_dir / "lobes.json", j.dump(2) + "\n");
  return j;
}

}  // namespace lathectl::io
