// `lathectl lobes MACHINE`: stability lobes of a chatter model → lobes.json, lobes.csv, lobes.html.
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "cli.hpp"
#include "systems/b_chatter/lobes.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/progress.hpp"

namespace lathectl::cli {
namespace {

int lobes(const std::string& file, const std::string& out) {
  const auto in = b_chatter::load_lobes_input(file);
  io::prepare_output_dir(out, "--out");
  nlohmann::json j;
  {
    io::Progress progress("lobes");
    j = b_chatter::run_lobes(in, out, &progress);
  }
  for (const auto& w : j["warnings"]) std::cerr << "warning: " << w.get<std::string>() << "\n";
  std::cout << "critical depth " << j["critical_depth_mm"].get<double>() << " mm at "
            << j["chatter_frequency_Hz"].get<double>() << " Hz; " << j["lobes"].size()
            << " lobes (" << j["lobes_with_minimum_in_range"].get<int>()
            << " with their minimum inside the speed range) → "
            << (std::filesystem::path(out) / "lobes.html").string() << "\n";
  return 0;
}

}  // namespace

void add_lobes(CLI::App& app, Commands& out) {
  struct Args {
    std::string file, out = "lobes-out";
  };
  auto a = std::make_shared<Args>();
  auto* sub = app.add_subcommand(
      "lobes", "Stability lobes of a chatter model (frequency domain and semi-discretization)");
  sub->add_option("machine", a->file,
                  "machine file (TOML): [cutting], [[mode]] and/or [part], [speed], [lobes]")
      ->required();
  sub->add_option("--out", a->out, "output directory")->capture_default_str();
  sub->footer("Machine files: " + doc("machine-file-reference.md") + ".");
  out.push_back({sub, [a] { return lobes(a->file, a->out); }});
}

}  // namespace lathectl::cli
