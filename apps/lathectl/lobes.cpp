// `lathectl lobes MACHINE`: stability lobes of a chatter model → lobes.json, lobes.csv, lobes.html.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "cli.hpp"
#include "lathectl/io/errors.hpp"
#include "systems/b_chatter/lobes.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/progress.hpp"

namespace lathectl::cli {
namespace {

constexpr double kAnnounceSeconds = 5.0;  // estimated runs longer than this are announced

// The best pockets, one line each, as lobes.json's "recommendation" holds them.
void print_recommendation(const nlohmann::json& r) {
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "recommendation (depth = stability limit / %.3g; feed %.3g mm/rev, diameter "
                "%.4g mm):\n",
                r["safety_factor"].get<double>(), r["feed_mm_per_rev"].get<double>(),
                r["diameter_mm"].get<double>());
  std::cout << buf;
  if (r["pockets"].empty()) std::cout << "  no pocket bounded by chatter or the machine's limits\n";
  int k = 0;
  for (const auto& p : r["pockets"]) {
    auto margin = [&](const char* side) {
      const bool end = p[std::string("margin_") + side + "_reaches_range_end"].get<bool>();
      char m[60];
      std::snprintf(m, sizeof m, "%s%.0f rpm%s", end ? ">= " : "",
                    p[std::string("margin_") + side + "_rpm"].get<double>(),
                    end ? " (to the range's end)" : "");
      return std::string(m);
    };
    const auto& lim = p["pocket_top_depth_mm"];
    char limit[40] = "unbounded";
    if (lim.is_number()) std::snprintf(limit, sizeof limit, "%.3g mm", lim.get<double>());
    std::snprintf(buf, sizeof buf,
                  "  %d. %.0f rpm, depth %.3g mm (%s-limited; pocket top %s at %.0f rpm), "
                  "%.3g cm3/min, %.3g kW, %.3g N.m; margin below %s, above %s\n",
                  ++k, p["speed_rpm"].get<double>(), p["depth_mm"].get<double>(),
                  p["limited_by"].get<std::string>().c_str(), limit,
                  p["pocket_top_rpm"].get<double>(),
                  p["removal_rate_cm3_per_min"].get<double>(), p["power_kW"].get<double>(),
                  p["torque_Nm"].get<double>(), margin("below").c_str(), margin("above").c_str());
    std::cout << buf;
  }
}

int lobes(const std::string& file, const std::string& out, bool recommend) {
  const auto in = systems::b_chatter::load_lobes_input(file);  // refuses work over its bounds
  std::vector<std::filesystem::path> inputs{file};
  for (const auto& f : in.frfs) inputs.emplace_back(f.path);
  io::prepare_output_dir(out, "--out", true, inputs);
  // A run longer than a few seconds says first what it will cost (estimated before computing),
  // then shows its progress: a bar on a terminal, a line every 10 s in a pipe or a log.
  const auto cost = systems::b_chatter::lobes_cost(in);
  if (cost.seconds > kAnnounceSeconds) {
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "lobes: estimated %.0f s on %u threads and %.0f MB (%.3g frequency-domain "
                  "points, %.3g semi-discretization cells up to %d steps per revolution)\n",
                  cost.seconds, cost.threads, cost.bytes / 1e6, cost.fd_points,
                  cost.sd_cells + cost.chart_cells, cost.max_steps);
    std::cerr << buf << std::flush;
  }
  nlohmann::json j;
  {
    io::Progress progress("lobes");  // a line every 10 s in a pipe or a log (kPlainInterval)
    j = systems::b_chatter::run_lobes(in, out, &progress);
  }
  for (const auto& w : j["warnings"])
    std::cerr << "warning: " << io::error_line(w.get<std::string>()) << "\n";
  // No lobe at all (every mode across the chip thickness): JSON null, said in words.
  const auto& crit = j["critical_depth_mm"];
  if (crit.is_number() && std::isfinite(crit.get<double>()))
    std::cout << "critical depth " << crit.get<double>() << " mm at "
              << j["chatter_frequency_Hz"].get<double>() << " Hz; ";
  else
    std::cout << "no critical depth (no mode can chatter); ";
  std::cout << j["lobes"].size()
            << " lobes (" << j["lobes_with_minimum_in_range"].get<int>()
            << " with their minimum inside the speed range) → "
            << (std::filesystem::path(out) / "lobes.html").string() << "\n";
  if (recommend) print_recommendation(j["recommendation"]);
  return 0;
}

}  // namespace

void add_lobes(CLI::App& app, Commands& out) {
  struct Args {
    std::string file, out = "lobes-out";
    bool recommend = false;
  };
  auto a = std::make_shared<Args>();
  auto* sub = app.add_subcommand(
      "lobes", "Stability lobes of a chatter model (frequency domain and semi-discretization)");
  sub->add_option("machine", a->file,
                  "machine file (TOML): [cutting], [[mode]] and/or [part], [speed], [lobes]")
      ->required();
  sub->add_option("--out", a->out, "output directory")->capture_default_str();
  sub->add_flag("--recommend", a->recommend,
                "also print the best pockets: speed, depth with the safety factor, removal rate, "
                "margin to the nearest lobe");
  sub->footer("Machine files: " + doc("machine-file-reference.md") + ".");
  out.push_back({sub, [a] { return lobes(a->file, a->out, a->recommend); }});
}

}  // namespace lathectl::cli
