#include "lathectl/io/scenario.hpp"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/input_file.hpp"
#include "lathectl/io/sections.hpp"
#include "lathectl/io/toml_reader.hpp"
#include "lathectl/sim/config_error.hpp"

namespace lathectl::io {

std::string read_scenario_text(const std::string& path) {
  return read_input_file(path, "a scenario file (.toml)", kMaxTomlBytes);
}

namespace {
// The part every scenario has: system, name, description, [run].
void read_common(TableReader& root, Scenario& sc, const std::vector<const Section*>& sections) {
  std::vector<std::string> ids;
  for (const auto* s : sections) ids.emplace_back(s->system);
  sc.system = root.pick({"system", {}, "the system the scenario runs: selects everything else"},
                        ids);
  sc.name = root.string("name");
  root.document("name", "the run's name in reports and summary.json");
  root.check(!sc.name.empty(), "name", "must not be empty");
  // It names the demo's directory of the run and heads the console's lines: one path component
  // of printable text (a "../x" wrote outside the demo's --out; an escape reached the terminal).
  root.check(sc.name != "." && sc.name != ".." &&
                 sc.name.find_first_of("/\\") == std::string::npos &&
                 printable(sc.name, sc.name.size()) == sc.name,
             "name", "must be printable text without / or \\ and not . or .. (it names a directory)");
  sc.description = root.string("description", "");
  root.document("description", "free text; it becomes the report's introduction");
  sc.demonstrates_failure = root.boolean("demonstrates_failure", false);
  root.document("demonstrates_failure",
                "true: the scenario shows a failure on purpose (no control, a sensor fault, a "
                "set-up forced through); lathectl demo lists it as a demonstration of failure, "
                "not as not accepted, and --strict does not count it (its report's verdict is "
                "unchanged)");
  read_run(root, sc.run);
}
}  // namespace

Scenario parse_scenario(std::string_view text, const std::string& label,
                        const MaterialLibrary& lib, const std::vector<const Section*>& sections) {
  const TomlDocument doc = TomlDocument::parse(text, label);
  auto keys = std::make_shared<KeyLocations>(label);
  auto params = std::make_shared<ParamLog>();
  auto warnings = std::make_shared<std::vector<std::string>>();
  TableReader root(doc.root(), label, "", keys);
  root.record_into(params);
  root.warn_into(warnings);
  Scenario sc;
  sc.file = label;
  sc.keys = keys;
  sc.params = params;
  read_common(root, sc, sections);
  const Section* section = nullptr;
  for (const auto* s : sections)
    if (s->system == sc.system) section = s;
  sc.settings.reset(section->read(root, sc, lib));
  root.finish();
  if (section->validate) section->validate(sc);
  sc.warnings = *warnings;
  return sc;
}

Scenario parse_scenario(std::string_view text, const std::string& label,
                        const MaterialLibrary& lib, const Section& section) {
  return parse_scenario(text, label, lib, std::vector<const Section*>{&section});
}

Scenario load_scenario(const std::string& path, const MaterialLibrary& lib,
                       const Section& section) {
  Scenario sc = parse_scenario(read_scenario_text(path), path, lib, section);
  print_warnings(sc);
  return sc;
}

void print_warnings(const Scenario& sc) {
  for (const auto& w : sc.warnings) std::cerr << "warning: " << error_line(w) << "\n";
}

ParamLog describe_section(const Section& section, const MaterialLibrary& lib, int variant) {
  auto log = std::make_shared<ParamLog>();
  TableReader root = TableReader::describing("", log, variant);
  Scenario sc;
  sc.file = "(reference)";
  sc.keys = std::make_shared<KeyLocations>(sc.file);
  read_common(root, sc, {&section});
  sc.system = section.system;
  sc.settings.reset(section.read(root, sc, lib));
  return *log;
}

void throw_at_key(const Scenario& sc, const std::invalid_argument& e,
                  const std::string& fallback_key) {
  const auto* keyed = dynamic_cast<const sim::ConfigError*>(&e);
  const std::string key = keyed ? keyed->key() : fallback_key;
  if (sc.keys && !key.empty()) sc.keys->fail(key, e.what());
  throw InputError(located(sc.file, 0, 0, std::string("inconsistent scenario: ") + e.what()));
}


}  // namespace lathectl::io
