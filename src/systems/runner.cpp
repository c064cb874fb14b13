#include "lathectl/io/runner.hpp"

#include <cstdlib>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/study.hpp"
#include "lathectl/io/toml_reader.hpp"
#include "systems/registry.hpp"

namespace lathectl::io {

namespace {
RunOutput run_system(const Scenario& sc) {
  const systems::System* s = systems::find(sc.system);
  if (!s) throw InputError(sc.file + ": system '" + sc.system + "' is not implemented");
  return s->run(sc);
}

// A settings row is a key, not a table heading; the description is the report's introduction.
bool is_setting(const ParamRecord& p) {
  return p.kind != "table" && p.kind != "array of tables" && p.key != "description";
}

// Every key the scenario's reader read (defaults included), in the file's units: summary.json's
// "settings" and the report's last table, so a user sees what a run really used. The scenario's
// warnings (values a shop would not mean) go to the summary and the report's notes.
void add_settings(const Scenario& sc, RunOutput& out) {
  if (!sc.warnings.empty()) {
    out.summary["warnings"] = sc.warnings;
    for (const auto& w : sc.warnings) out.report.notes.push_back("⚠ warning: " + w);
  }
  if (!sc.params || sc.params->empty()) return;
  nlohmann::json js = nlohmann::json::object();
  for (const auto& p : *sc.params) {
    if (!is_setting(p)) continue;
    char* end = nullptr;
    const double v = std::strtod(p.value.c_str(), &end);
    const bool numeric = !p.value.empty() && end && *end == '\0' && p.kind != "string";
    if (p.kind == "boolean")
      js[p.key] = p.value == "true";
    else if (numeric && p.kind == "integer")
      js[p.key] = static_cast<long long>(v);
    else if (numeric)
      js[p.key] = json_number(v);
    else
      js[p.key] = p.value;
  }
  out.summary["settings"] = std::move(js);
  out.report.tables.push_back(settings_table(sc));
}
}  // namespace

Table settings_table(const Scenario& sc) {
  Table t{"Settings: every key the run used (defaults included), in the file's units",
          {"key", "value", "unit", "default", "meaning"},
          {}};
  if (sc.params)
    for (const auto& p : *sc.params)
      if (is_setting(p))
        t.rows.push_back({p.key, p.value, p.unit, p.required ? "required" : p.fallback, p.doc});
  return t;
}

RunOutput run_scenario(const Scenario& sc) {
  RunOutput out = run_system(sc);
  add_settings(sc, out);
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

// One set, appearing as a whole (see OutputStage): never a new channels.csv beside an old
// summary.json. Files the runs streamed into the stage already (channels.csv) are not in `out`.
void write_outputs(const RunOutput& out, OutputStage& stage, const std::string& index_href) {
  std::vector<std::pair<std::string, std::string>> files;
  if (!stage.streamed("channels.csv")) files.emplace_back("channels.csv", out.channels_csv);
  const bool has_compare = !out.compare_csv.empty() || stage.streamed("channels_compare.csv");
  if (!out.compare_csv.empty() && !stage.streamed("channels_compare.csv"))
    files.emplace_back("channels_compare.csv", out.compare_csv);
  // The report's header links to the files beside it (and back to the demo's index).
  Report rep = out.report;
  if (!index_href.empty()) rep.links.push_back({"← all reports", index_href});
  rep.links.push_back({"channels.csv", "channels.csv"});
  if (has_compare)
    rep.links.push_back({"channels_compare.csv (the comparison run)", "channels_compare.csv"});
  rep.links.push_back({"summary.json", "summary.json"});
  files.emplace_back("report.html", render_html(rep));
  files.emplace_back("summary.json", out.summary.dump(2) + "\n");
  stage.commit(files);
}

void write_outputs(const RunOutput& out, const std::filesystem::path& dir,
                   const std::string& index_href) {
  OutputStage stage(dir);
  write_outputs(out, stage, index_href);
}

}  // namespace lathectl::io
