#include "lathectl/io/verdict.hpp"

#include <cmath>
#include <cstdio>

namespace lathectl::io {

namespace {
using nlohmann::json;

std::string num(double v) {
  if (!std::isfinite(v)) return "—";
  char t[32];
  std::snprintf(t, sizeof t, "%.4g", v);
  return t;
}

std::string alarm_text(const json& a) {
  return a.value("reason", std::string("alarm")) + " (code " + std::to_string(a.value("code", 0)) +
         ") at " + num(a.value("time_s", 0.0)) + " s";
}

bool not_finished(const json& metrics) {
  return metrics.is_object() && metrics.contains("finished") && metrics["finished"].is_boolean() &&
         !metrics["finished"].get<bool>();
}

std::string plural(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}
}  // namespace

bool Acceptance::judge(std::string_view key, double value) {
  const CriterionKey* k = nullptr;
  for (const auto& c : limits_.keys())
    if (c.key == key) k = &c;
  if (!k) return true;
  const double limit = limits_.limit(key);
  if (limit == 0.0 || std::isnan(limit)) return true;              // not judged
  const bool met = k->at_least ? value >= limit : value <= limit;  // NaN meets neither
  criteria_.push_back(
      {{"key", std::string(key)},
       {"criterion", std::string(k->label)},
       {"value", std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr)},
       {"limit", limit},
       {"comparison", k->at_least ? "≥" : "≤"},
       {"unit", unit_of_key(key)},
       {"source", limits_.stated(key) ? "scenario" : "default"},
       {"met", met}});
  return met;
}

nlohmann::json Acceptance::json() const {
  bool ok = true;
  for (const auto& c : criteria_) ok = ok && c["met"].get<bool>();
  return nlohmann::json{{"ok", ok}, {"criteria", criteria_}};
}

std::string claim_name(const std::string& text) {
  // After the run's label ("force by feed (prior art): …"), up to the claim's own bracket.
  const auto colon = text.find(": ");
  const auto p = text.find(" (", colon == std::string::npos ? 0 : colon);
  return p == std::string::npos ? text : text.substr(0, p);
}

std::string criterion_text(const json& c) {
  const std::string unit = c.value("unit", std::string());
  const auto with_unit = [&](const json& v) {
    const std::string n = v.is_number() ? num(v.get<double>()) : std::string("—");
    return unit.empty() || n == "—" ? n : n + " " + unit;
  };
  return c.value("criterion", c.value("key", std::string("criterion"))) + " " +
         with_unit(c.contains("value") ? c["value"] : json(nullptr)) + " (limit " +
         c.value("comparison", std::string("≤")) + " " +
         with_unit(c.contains("limit") ? c["limit"] : json(nullptr)) + ", " +
         (c.value("source", std::string()) == "scenario" ? "the scenario's" : "default") + ")";
}

Verdict verdict_of(const json& s) {
  Verdict v;
  if (s.contains("acceptance") && s["acceptance"].is_object() &&
      s["acceptance"].contains("criteria") && s["acceptance"]["criteria"].is_array())
    for (const auto& c : s["acceptance"]["criteria"])
      v.criteria.push_back({criterion_text(c), c.value("met", false)});
  if (s.contains("claims") && s["claims"].is_array()) {
    const auto& c = s["claims"];
    v.claims = c.size();
    for (std::size_t i = 0; i < c.size(); ++i)
      if (!c[i].value("met", false)) v.unmet.push_back({i, c[i].value("claim", std::string())});
  }
  if (s.contains("metrics") && s["metrics"].is_object()) {
    const auto& m = s["metrics"];
    if (m.contains("alarms") && m["alarms"].is_array())
      for (const auto& a : m["alarms"]) v.alarms.push_back(alarm_text(a));
    if (not_finished(m)) v.unfinished.push_back(s.value("label", std::string("main run")));
  }
  if (s.contains("comparisons") && s["comparisons"].is_array())
    for (const auto& c : s["comparisons"])
      if (c.contains("metrics") && not_finished(c["metrics"]))
        v.unfinished.push_back(c.value("label", std::string("comparison")));
  return v;
}

std::size_t Verdict::criteria_met() const {
  std::size_t n = 0;
  for (const auto& c : criteria) n += c.met ? 1 : 0;
  return n;
}

bool Verdict::ok() const {
  return criteria_met() == criteria.size() && alarms.empty() && unfinished.empty();
}

std::string Verdict::acceptance_line(bool names) const {
  const std::size_t n = criteria.size(), met = criteria_met();
  if (ok())
    return n == 0 ? std::string("✔ no acceptance criteria, no alarms")
                  : "✔ " + std::to_string(met) + " of " +
                        plural(n, "acceptance criterion met", "acceptance criteria met");
  std::string out = "✘";
  std::string sep = " ";
  if (met < n) {
    out += sep + std::to_string(n - met) + " of " +
           plural(n, "acceptance criterion not met", "acceptance criteria not met");
    if (names) {
      out += ": ";
      bool first = true;
      for (const auto& c : criteria)
        if (!c.met) {
          out += (first ? "" : "; ") + c.text;
          first = false;
        }
    }
    sep = " · ";
  }
  if (!names && !alarms.empty()) {
    out += sep + plural(alarms.size(), "alarm", "alarms");
    sep = " · ";
  }
  for (std::size_t i = 0; names && i < alarms.size(); ++i) {
    out += sep + "alarm " + alarms[i];
    sep = " · ";
  }
  if (!unfinished.empty()) {
    out += sep + "part not finished";
    if (names) {
      out += " (";
      for (std::size_t i = 0; i < unfinished.size(); ++i) out += (i ? ", " : "") + unfinished[i];
      out += ")";
    }
  }
  return out;
}

std::string Verdict::model_checks_line(bool names) const {
  if (claims == 0) return {};
  std::string out = "model checks: " + std::to_string(claims - unmet.size()) + " of " +
                    std::to_string(claims) + " met";
  if (names && !unmet.empty()) {
    out += " (not met: ";
    for (std::size_t i = 0; i < unmet.size(); ++i)
      out += (i ? "; " : "") + claim_name(unmet[i].text);
    out += ")";
  }
  return out;
}

std::string Verdict::line(bool names) const {
  const std::string m = model_checks_line(names);
  return acceptance_line(names) + (m.empty() ? "" : " · " + m);
}

nlohmann::json Verdict::json() const {
  nlohmann::json unmet_j = nlohmann::json::array(), unmet_c = nlohmann::json::array();
  for (const auto& u : unmet) unmet_j.push_back(u.text);
  for (const auto& c : criteria)
    if (!c.met) unmet_c.push_back(c.text);
  return nlohmann::json{{"ok", ok()},
                        {"criteria", criteria.size()},
                        {"criteria_met", criteria_met()},
                        {"unmet_criteria", unmet_c},
                        {"alarms", alarms},
                        {"unfinished", unfinished},
                        {"model_checks_ok", model_checks_ok()},
                        {"claims", claims},
                        {"claims_met", claims - unmet.size()},
                        {"unmet_claims", unmet_j}};
}

}  // namespace lathectl::io
