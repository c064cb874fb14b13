// `lathectl check SCENARIO`: read and validate a scenario without running it.
#include <iostream>
#include <memory>
#include <string>

#include "cli.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::cli {

void add_check(CLI::App& app, Commands& out) {
  auto scenario = std::make_shared<std::string>();
  auto* sub = app.add_subcommand("check", "Validate a scenario file without running it");
  sub->add_option("scenario", *scenario, "scenario file (TOML)")->required();
  sub->footer("Scenario files: " + doc("scenario-reference.md") + ".");
  out.push_back({sub, [scenario] {
                   const auto lib = io::MaterialLibrary::load_default();
                   const auto sc = io::load_scenario(*scenario, lib);
                   std::cout << *scenario << ": OK (system " << sc.system << ", \"" << sc.name
                             << "\", " << sc.run.duration_s << " s at step " << sc.run.step_s
                             << " s)\n";
                   return 0;
                 }});
}

}  // namespace lathectl::cli
