// `lathectl systems`: the systems lathectl knows, from the one list (src/systems/registry.cpp):
// each one's letter, title and docs page, and on LinuxCNC its runner, configuration and HAL
// components. --tsv is the same for the build and the scripts: hal/systems.tsv is this output
// (hal/CMakeLists.txt builds and installs the components it lists, scripts/linuxcnc-sim hands a
// scenario to its system's runner, tests/package/package_test.sh checks the package holds them);
// --check FILE fails when FILE is not (the test systems_table).
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>

#include "cli.hpp"
#include "systems/registry.hpp"

namespace lathectl::cli {
namespace {

int systems_command(bool tsv, const std::string& check) {
  const std::string table = systems::table_tsv();
  if (!check.empty()) {
    std::ifstream in(check, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    if (in && text.str() == table) return 0;
    std::cerr << "systems: " << check << " is not the registry's table: lathectl systems --tsv > "
              << check << "\n";
    return 1;
  }
  if (tsv) {
    std::cout << table;
    return 0;
  }
  for (const auto& s : systems::all()) {
    std::cout << s.id << "  " << s.title << "\n   docs/" << s.docs << "\n";
    const auto& l = s.linuxcnc;
    if (l.runner.empty()) continue;
    std::cout << "   on LinuxCNC: scripts/" << l.runner << ", hal/config/" << l.config
              << ".ini; components";
    for (const auto& c : l.hal_components) std::cout << " " << c.name;
    std::cout << "\n";
  }
  return 0;
}

}  // namespace

void add_systems(CLI::App& app, Commands& out) {
  struct Args {
    bool tsv = false;
    std::string check;
  };
  auto a = std::make_shared<Args>();
  auto* sub = app.add_subcommand(
      "systems",
      "The systems: each one's letter, title, docs page, and its LinuxCNC runner, "
      "configuration and HAL components");
  sub->add_flag("--tsv", a->tsv,
                "tab-separated, as hal/systems.tsv (what the build and the "
                "scripts read)");
  sub->add_option("--check", a->check, "exit 1 unless FILE is the --tsv output");
  sub->footer("Adding a system: " + doc("code-layout.md") + ".");
  out.push_back({sub, [a] { return systems_command(a->tsv, a->check); }});
}

}  // namespace lathectl::cli
