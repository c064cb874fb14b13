#include "lathectl/io/runner.hpp"

#include <cstdlib>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/study.hpp"
#include "lathectl/io/toml_reader.hpp"

namespace lathectl::io {

namespace {
// A settings row is a key, not a table heading; the description is the report's introduction,
// demonstrates_failure a note to lathectl demo, not what the run used.
bool is_setting(const ParamRecord& p) {
  return p.kind != "table" && p.kind != "array of tables" && p.key != "description" &&
         p.key != "demonstrates_failure";
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

// The report's first section: the acceptance criteria as a table (each with its value, limit,
// where the limit came from and ✔/✘), then the alarms and the parts not finished, which decide
// the verdict too; the model checks in a section of their own after it.
void add_verdict(RunOutput& out) {
  const nlohmann::json& s = out.summary;
  const Verdict& v = out.verdict;
  Report& rep = out.report;
  rep.verdict = v.acceptance_line(false);
  rep.verdict_ok = v.ok();
  Table& t = rep.verdict_table;
  t.title = "Verdict: acceptance criteria";
  t.header = {"criterion", "value", "limit", "", "limit from"};
  const auto with_unit = [](const nlohmann::json& c, const char* key) {
    const nlohmann::json& x = c.contains(key) ? c[key] : nlohmann::json(nullptr);
    const std::string n = x.is_number() ? fmt(x.get<double>()) : std::string("—");
    const std::string unit = c.value("unit", std::string());
    return unit.empty() || n == "—" ? n : n + " " + unit;
  };
  if (s.contains("acceptance") && s["acceptance"].contains("criteria"))
    for (const auto& c : s["acceptance"]["criteria"])
      t.rows.push_back({c.value("criterion", std::string()), with_unit(c, "value"),
                        c.value("comparison", std::string()) + " " + with_unit(c, "limit"),
                        c.value("met", false) ? "✔" : "✘",
                        c.value("source", std::string()) == "scenario"
                            ? "[acceptance] " + c.value("key", std::string())
                            : "default (" + c.value("key", std::string()) + ")"});
  t.rows.push_back({"alarms raised", std::to_string(v.alarms.size()), "= 0",
                    v.alarms.empty() ? "✔" : "✘", "always"});
  if (s.contains("metrics") && s["metrics"].contains("finished"))
    t.rows.push_back({"parts not finished within run.duration_s",
                      std::to_string(v.unfinished.size()), "= 0", v.unfinished.empty() ? "✔" : "✘",
                      "always"});
  for (const auto& a : v.alarms) rep.verdict_items.push_back({"alarm: " + a, ""});
  for (const auto& l : v.unfinished)
    rep.verdict_items.push_back({"part not finished within run.duration_s: " + l, ""});
  rep.model_checks = v.model_checks_line(false);
  if (!rep.model_checks.empty())
    rep.model_checks +=
        ". They say whether the model reproduces what the seed document states, not whether "
        "this part is good; they do not decide --strict.";
  rep.model_checks_ok = v.model_checks_ok();
  for (const auto& u : v.unmet)
    rep.model_check_items.push_back({"✘ " + u.text, "#claim-" + std::to_string(u.index)});
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

void finish_run(const Scenario& sc, RunOutput& out) {
  add_settings(sc, out);
  // The seed's claims are the model checks; "claims" stays for the readers that know it.
  if (out.summary.contains("claims")) out.summary["model_checks"] = out.summary["claims"];
  out.verdict = verdict_of(out.summary);
  out.summary["verdict"] = out.verdict.json();
  add_verdict(out);
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
