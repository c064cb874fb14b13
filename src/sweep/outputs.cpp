// cases.csv and results.csv (docs/sweep.md), and the metrics of a case's summary.json.
#include <map>
#include <nlohmann/json.hpp>

#include "lathectl/io/output.hpp"
#include "sweep/engine.hpp"

namespace lathectl::sweep {
namespace {

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

// A value as the CSV shows it: a number as the spec's JSON writes it (shortest round trip), a
// string bare.
std::string csv_value(const Value& v) {
  if (const auto* s = std::get_if<std::string>(&v)) return csv_field(*s);
  return to_text(v);
}

void flatten(const nlohmann::ordered_json& j, const std::string& prefix,
             std::vector<std::pair<std::string, double>>& out) {
  for (const auto& [k, v] : j.items()) {
    const std::string name = prefix.empty() ? k : prefix + "." + k;
    if (v.is_object())
      flatten(v, name, out);
    else if (v.is_number())
      out.emplace_back(name, v.get<double>());
  }
}

// The metrics' columns: `chosen` when the spec names them, else every metric that occurs, in
// the order of first occurrence.
std::vector<std::string> metric_columns(const std::vector<std::string>& chosen,
                                        const std::vector<Result>& results) {
  if (!chosen.empty()) return chosen;
  std::vector<std::string> cols;
  std::map<std::string, bool> seen;
  for (const auto& r : results)
    if (r.summary)
      for (const auto& [name, v] : metrics_of(*r.summary))
        if (seen.emplace(name, true).second) cols.push_back(name);
  return cols;
}

}  // namespace

std::vector<std::pair<std::string, double>> metrics_of(const std::string& summary_json) {
  std::vector<std::pair<std::string, double>> out;
  const auto j = nlohmann::ordered_json::parse(summary_json, nullptr, false);
  if (j.is_object() && j.contains("metrics") && j["metrics"].is_object())
    flatten(j["metrics"], "", out);
  return out;
}

void write_cases_csv(const std::filesystem::path& dir, const Spec& spec,
                     const std::vector<std::vector<Value>>& values) {
  std::string t = "case";
  for (const auto& k : spec.varied_keys()) t += "," + csv_field(k);
  t += "\n";
  for (std::size_t i = 0; i < values.size(); ++i) {
    t += std::to_string(i);
    for (const auto& v : values[i]) t += "," + csv_value(v);
    t += "\n";
  }
  io::write_file_atomic(dir / "cases.csv", t);
}

void write_results(const std::filesystem::path& dir, const Spec& spec,
                   const std::vector<std::vector<Value>>& values,
                   const std::vector<Result>& results) {
  const auto metrics = metric_columns(spec.metrics, results);
  std::string t = "case";
  for (const auto& k : spec.varied_keys()) t += "," + csv_field(k);
  t += ",status,message,elapsed_s";
  for (const auto& m : metrics) t += "," + csv_field(m);
  t += "\n";
  for (const auto& r : results) {
    t += std::to_string(r.case_id);
    for (const auto& v : values.at(static_cast<std::size_t>(r.case_id))) t += "," + csv_value(v);
    t += "," + r.status + "," + csv_field(r.message) + "," + to_text(r.elapsed_s);
    std::map<std::string, double> m;
    if (r.summary)
      for (const auto& [name, v] : metrics_of(*r.summary)) m.emplace(name, v);
    for (const auto& name : metrics) {
      t += ",";
      if (const auto it = m.find(name); it != m.end()) t += to_text(it->second);
    }
    t += "\n";
  }
  io::write_file_atomic(dir / "results.csv", t);
  io::write_file_atomic(dir / "report.html", report_html(spec, values, results, metrics));
}

}  // namespace lathectl::sweep
