#include "lathectl/io/verdict.hpp"

#include <cstdio>

namespace lathectl::io {

namespace {
using nlohmann::json;

std::string alarm_text(const json& a) {
  char t[32];
  std::snprintf(t, sizeof t, "%.4g", a.value("time_s", 0.0));
  return a.value("reason", std::string("alarm")) + " (code " + std::to_string(a.value("code", 0)) +
         ") at " + t + " s";
}

bool not_finished(const json& metrics) {
  return metrics.is_object() && metrics.contains("finished") && metrics["finished"].is_boolean() &&
         !metrics["finished"].get<bool>();
}
}  // namespace

std::string claim_name(const std::string& text) {
  // After the run's label ("force by feed (prior art): …"), up to the claim's own bracket.
  const auto colon = text.find(": ");
  const auto p = text.find(" (", colon == std::string::npos ? 0 : colon);
  return p == std::string::npos ? text : text.substr(0, p);
}

Verdict verdict_of(const json& s) {
  Verdict v;
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

std::string Verdict::line(bool names) const {
  const std::string n = std::to_string(claims);
  if (ok())
    return claims == 0 ? std::string("✔ no claims to check, no alarms")
                       : "✔ " + n + " of " + n + (claims == 1 ? " claim met" : " claims met");
  std::string out = "✘";
  std::string sep = " ";
  if (!unmet.empty()) {
    out += sep + std::to_string(unmet.size()) + " of " + n + " claims not met";
    if (names) {
      out += ": ";
      for (std::size_t i = 0; i < unmet.size(); ++i)
        out += (i ? "; " : "") + claim_name(unmet[i].text);
    }
    sep = " · ";
  }
  if (!names && !alarms.empty()) {
    out += sep + std::to_string(alarms.size()) + (alarms.size() == 1 ? " alarm" : " alarms");
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

nlohmann::json Verdict::json() const {
  nlohmann::json unmet_j = nlohmann::json::array();
  for (const auto& u : unmet) unmet_j.push_back(u.text);
  return nlohmann::json{{"ok", ok()},
          {"claims", claims},
          {"claims_met", claims - unmet.size()},
          {"unmet_claims", unmet_j},
          {"alarms", alarms},
          {"unfinished", unfinished}};
}

}  // namespace lathectl::io
