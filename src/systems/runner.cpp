#include "lathectl/io/runner.hpp"

#include "lathectl/io/errors.hpp"
#include "lathectl/io/output.hpp"
#include "systems/registry.hpp"

namespace lathectl::io {

namespace {
RunOutput run_system(const Scenario& sc) {
  const systems::System* s = systems::find(sc.system);
  if (!s) throw InputError(sc.file + ": system '" + sc.system + "' is not implemented");
  return s->run(sc);
}
}  // namespace

RunOutput run_scenario(const Scenario& sc) {
  RunOutput out = run_system(sc);
  out.verdict = verdict_of(out.summary);
  out.summary["verdict"] = out.verdict.json();
  Report& rep = out.report;
  rep.verdict = out.verdict.line(false);
  rep.verdict_ok = out.verdict.ok();
  for (const auto& u : out.verdict.unmet)
    rep.verdict_items.push_back({"✘ " + u.text, "#claim-" + std::to_string(u.index)});
  for (const auto& a : out.verdict.alarms) rep.verdict_items.push_back({"alarm: " + a, ""});
  for (const auto& l : out.verdict.unfinished)
    rep.verdict_items.push_back({"part not finished within run.duration_s: " + l, ""});
  return out;
}

// One set, appearing as a whole (see write_output_set): never a new channels.csv beside an old
// summary.json.
void write_outputs(const RunOutput& out, const std::filesystem::path& dir) {
  std::vector<std::pair<std::string, std::string>> files;
  files.emplace_back("channels.csv", out.channels_csv);
  if (!out.compare_csv.empty()) files.emplace_back("channels_compare.csv", out.compare_csv);
  files.emplace_back("report.html", render_html(out.report));
  files.emplace_back("summary.json", out.summary.dump(2) + "\n");
  write_output_set(dir, files);
}

}  // namespace lathectl::io
