// `lathectl run SCENARIO`: one scenario closed-loop → summary.json, channels.csv, report.html.
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "cli.hpp"
#include "lathectl/io/channel_stream.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/progress.hpp"
#include "lathectl/io/runner.hpp"
#include "lathectl/io/scenario.hpp"
#include "systems/estimate.hpp"
#include "systems/registry.hpp"

namespace fs = std::filesystem;

namespace lathectl::cli {
namespace {

int run(const std::string& scenario, const std::string& out, bool strict) {
  const auto lib = io::MaterialLibrary::load_default();
  const auto sc = systems::load_scenario(scenario, lib);
  io::prepare_output_dir(out, "--out", true, {scenario});  // before the simulation, not after it
  // A long run says up front what it will cost (the progress line then says how far it is).
  if (const auto e = systems::estimate(sc); e.wall_s > 30.0)
    std::cerr << "run " << sc.name << ": " << systems::summary_text(e) << "\n";
  io::RunOutput result;
  try {
    // The set's staging directory exists during the run: channels.csv streams into it.
    io::OutputStage stage(out);
    {
      io::Progress progress("run " + sc.name);
      io::ProgressScope scope(progress);
      io::StreamScope streams(stage);
      result = systems::run_scenario(sc);
    }
    io::write_outputs(result, stage);
  } catch (const fs::filesystem_error& e) {
    throw io::InputError("--out " + out + ": cannot write the results there (" +
                         e.code().message() + ")");
  }
  std::cout << sc.name << ": " << result.headline << " — " << result.verdict.line() << "\n  → "
            << (fs::path(out) / "report.html").string() << "\n";
  return strict && !result.verdict.ok() ? kStrictFailure : 0;
}

}  // namespace

void add_run(CLI::App& app, Commands& out) {
  struct Args {
    std::string scenario, out = "out";
    bool strict = false;
  };
  auto a = std::make_shared<Args>();
  auto* sub = app.add_subcommand(
      "run", "Run a scenario closed-loop and write summary.json, channels.csv, report.html");
  sub->add_option("scenario", a->scenario, "scenario file (TOML)")->required();
  sub->add_option("--out", a->out, "output directory")->capture_default_str();
  sub->add_flag("--strict", a->strict,
                "exit 3 when an acceptance criterion ([acceptance], or the system's defaults) is "
                "not met, an alarm fired (expected or not) or the part was not finished; the "
                "model checks (the seeds' claims) do not count");
  sub->footer("Scenario files: " + doc("scenario-reference.md") + ".");
  out.push_back({sub, [a] { return run(a->scenario, a->out, a->strict); }});
}

}  // namespace lathectl::cli
