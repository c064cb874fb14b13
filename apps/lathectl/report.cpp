// `lathectl report PATH`: the report of a LinuxCNC session's output, as the same kind of HTML
// report as `lathectl run`'s. Which system's session PATH is, and its report, the registry says
// (src/systems/registry.cpp: each system's entry, `session`): system E's operation log
// (lathectl_oplog's operations.json, with scripts/linuxcnc-sim's signals.csv beside it), system
// D's series (scripts/linuxcnc-sim-gauge), system B's session (scripts/linuxcnc-sim-twin).
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include "cli.hpp"
#include "systems/registry.hpp"

namespace lathectl::cli {
namespace {

// The first system whose session PATH is (the registry's order) writes its report.
int report(const std::string& path, const std::string& out) {
  for (const auto& s : systems::all())
    if (s.linuxcnc.session.is_session && s.linuxcnc.session.is_session(path))
      return s.linuxcnc.session.report(path, out);
  throw std::logic_error("lathectl report: no system reads " + path);
}

}  // namespace

void add_report(CLI::App& app, Commands& out) {
  struct Args {
    std::string log, out;
  };
  auto a = std::make_shared<Args>();
  auto* sub = app.add_subcommand(
      "report", "HTML report of a LinuxCNC operation log (lathectl_oplog's operations.json)");
  sub->add_option("log", a->log,
                  "operations.json, or the directory holding it (scripts/linuxcnc-sim --out DIR); a "
                  "system-D series' directory (summary.json and parts.csv): the series' report; a "
                  "system-B session's (summary.json, signals.csv, report.txt): the session's")
      ->required();
  sub->add_option("--out", a->out, "the report (default: report.html beside the log)");
  sub->footer("The operation log and its columns: " + doc("linuxcnc.md") + ".");
  out.push_back({sub, [a] { return report(a->log, a->out); }});
}

}  // namespace lathectl::cli
