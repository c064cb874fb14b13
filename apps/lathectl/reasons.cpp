// `lathectl reasons`: the reason codes a controller writes to its reason pins, channels.csv and
// the operation log, from the one table in control/types.hpp: code, operation-log bit, name,
// alarm or not, the systems that set it and what it means. --json is the same for tools
// (hal/reasons.json is this output, read by lathectl_oplog.py and the headless display).
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "cli.hpp"
#include "lathectl/control/types.hpp"

namespace lathectl::cli {
namespace {

nlohmann::json reasons_json() {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& e : control::kReasons)
    rows.push_back({{"code", static_cast<int>(e.code)},
                    {"bit", control::reason_index(e.code)},
                    {"name", std::string(e.name)},
                    {"alarm", e.alarm},
                    {"systems", std::string(e.systems)},
                    {"meaning", std::string(e.meaning)}});
  return {{"about",
           "lathectl reason codes: `code` is what the reason and alarm-reason pins and "
           "channels.csv carry; the operation log's op-reasons sets bit `bit` (1 << bit) "
           "for every reason seen in the cut. Written by `lathectl reasons --json`."},
          {"reasons", rows}};
}

int reasons(bool as_json) {
  if (as_json) {
    std::cout << reasons_json().dump(1) << "\n";
    return 0;
  }
  std::size_t width = 4;
  for (const auto& e : control::kReasons) width = std::max(width, e.name.size());
  char line[160];
  std::snprintf(line, sizeof line, "%4s %3s  %-*s  %-5s  %-7s  %s\n", "code", "bit",
                static_cast<int>(width), "name", "alarm", "systems", "meaning");
  std::cout << line;
  for (const auto& e : control::kReasons) {
    std::snprintf(line, sizeof line, "%4d %3d  %-*s  %-5s  %-7s  ", static_cast<int>(e.code),
                  control::reason_index(e.code), static_cast<int>(width),
                  std::string(e.name).c_str(), e.alarm ? "yes" : "no",
                  std::string(e.systems).c_str());
    std::cout << line << e.meaning << "\n";
  }
  return 0;
}

}  // namespace

void add_reasons(CLI::App& app, Commands& out) {
  auto json = std::make_shared<bool>(false);
  auto* sub = app.add_subcommand(
      "reasons",
      "The reason codes on the reason pins, in channels.csv and the operation log: "
      "code, operation-log bit, name, alarm, systems, meaning");
  sub->add_flag("--json", *json, "the same as JSON, for tools (hal/reasons.json is this output)");
  sub->footer(
      "An alarm latches: the feed is held until the alarm is reset. The operation log's "
      "op-reasons pin sets bit `bit` (1 << bit) for every reason seen in the cut.");
  out.push_back({sub, [json] { return reasons(*json); }});
}

}  // namespace lathectl::cli
