// `lathectl check FILE`: read and validate an input without running it. FILE is a scenario, or
// one of lathectl_adaptive's two files beside it on a LinuxCNC machine — the per-tool limits
// (tools=) or the teach-in references (taught=) — told apart by what the file holds, so a shop
// checks them before loading LinuxCNC.
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "cli.hpp"
#include "lathectl/io/input_file.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/scenario.hpp"
#include "lathectl/io/toml_reader.hpp"
#include "systems/e_adaptive/tool_limits.hpp"
#include "systems/estimate.hpp"
#include "systems/registry.hpp"

namespace lathectl::cli {
namespace {

enum class Kind { Scenario, Tools, Taught };

std::string fmt_g(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

// A file without `system` that writes [machine] or [[tool]] is a tools file, one that writes
// [[taught]] a taught file; anything else is read as a scenario (and its errors say what a
// scenario lacks).
Kind kind_of(const io::TomlDocument& doc) {
  const io::TableReader root(doc.root(), doc.file(), "");
  if (root.has("system")) return Kind::Scenario;
  if (root.has("taught")) return Kind::Taught;
  if (root.has("tool") || root.has("machine")) return Kind::Tools;
  return Kind::Scenario;
}

int check(const std::string& file) {
  const std::string text = io::read_input_file(file, "a TOML file", io::kMaxTomlBytes);
  switch (kind_of(io::TomlDocument::parse(text, file))) {
    case Kind::Tools: {
      const auto t = systems::e_adaptive::read_tool_table(text, file);
      std::cout << file << ": OK (lathectl_adaptive tools file: " << t.tools.size() << " tools"
                << (t.limit_max > 0.0 ? ", machine limit_max " + fmt_g(t.limit_max) : "")
                << ")\n";
      return 0;
    }
    case Kind::Taught: {
      const auto t = systems::e_adaptive::read_taught(text, file);
      std::cout << file << ": OK (lathectl_adaptive taught file: " << t.size()
                << " references)\n";
      return 0;
    }
    case Kind::Scenario:
      break;
  }
  const auto lib = io::MaterialLibrary::load_default();
  const auto sc = systems::load_scenario(file, lib);
  std::cout << file << ": OK (system " << sc.system << ", \"" << sc.name << "\", "
            << sc.run.duration_s << " s at step " << sc.run.step_s << " s)\n";
  std::cout << "  cost: " << systems::summary_text(systems::estimate(sc)) << "\n";
  return 0;
}

}  // namespace

void add_check(CLI::App& app, Commands& out) {
  auto file = std::make_shared<std::string>();
  auto* sub = app.add_subcommand(
      "check", "Validate a scenario, or lathectl_adaptive's tools or taught file, without running it");
  sub->add_option("file", *file,
                  "scenario file (TOML), or a tools= / taught= file of lathectl_adaptive")
      ->required();
  sub->footer("Scenario files: " + doc("scenario-reference.md") + "; tools and taught files: " +
              doc("linuxcnc.md") + ".");
  out.push_back({sub, [file] { return check(*file); }});
}

}  // namespace lathectl::cli
