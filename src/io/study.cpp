#include "lathectl/io/study.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "lathectl/control/types.hpp"

namespace lathectl::io {

nlohmann::json json_number(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

std::vector<double> column(const sim::Recorder& rec, const char* name) {
  const auto c = rec.column(name);
  return {c.begin(), c.end()};
}

Series recorded_series(const sim::Recorder& rec, const char* channel, std::string name,
                       std::string color, bool dashed) {
  Series s;
  s.name = std::move(name);
  rec.plot_points(channel, s.x, s.y);
  s.pyramid = rec.plot_pyramid(channel);  // streamed: the zoomable record
  s.color = std::move(color);
  s.dashed = dashed;
  return s;
}

nlohmann::json alarms_json(const std::vector<sim::AlarmEvent>& alarms) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& e : alarms)
    a.push_back(
        {{"time_s", e.time_s},
         {"code", e.code},
         {"reason", std::string(control::reason_name(static_cast<control::Reason>(e.code)))}});
  return a;
}

const char* compare_symbol(Compare c) {
  switch (c) {
    case Compare::AtMost:
      return "≤";
    case Compare::Below:
      return "<";
    case Compare::AtLeast:
      return "≥";
    case Compare::Above:
      return ">";
    case Compare::Within:
      return "|·| ≤";
    case Compare::Outside:
      return "|·| >";
    case Compare::RatioWithin:
      return "|· − 1| ≤";
  }
  return "?";
}

bool Claims::check(const std::string& text, double value, Compare cmp, double threshold) {
  bool met = false;
  switch (cmp) {
    case Compare::AtMost:
      met = value <= threshold;
      break;
    case Compare::Below:
      met = value < threshold;
      break;
    case Compare::AtLeast:
      met = value >= threshold;
      break;
    case Compare::Above:
      met = value > threshold;
      break;
    case Compare::Within:
      met = std::abs(value) <= threshold;
      break;
    case Compare::Outside:
      met = std::abs(value) > threshold;
      break;
    case Compare::RatioWithin:
      met = std::abs(value - 1.0) <= threshold;
      break;
  }
  add(text, value, met);
  json_.back()["threshold"] = json_number(threshold);
  json_.back()["comparison"] = compare_symbol(cmp);
  return met;
}

void Claims::add(const std::string& text, double value, bool met) {
  ids_.push_back("claim-" + std::to_string(json_.size()));
  json_.push_back({{"claim", text}, {"value", json_number(value)}, {"met", met}});
  notes_.push_back(std::string(met ? "✔ " : "✘ ") + text + ": " + fmt(value));
}

}  // namespace lathectl::io

namespace lathectl::io {

namespace {
thread_local int summary_only_depth = 0;
}  // namespace

SummaryOnly::SummaryOnly() { ++summary_only_depth; }
SummaryOnly::~SummaryOnly() { --summary_only_depth; }
bool SummaryOnly::active() { return summary_only_depth > 0; }

RunOutput Study::run() {
  RunOutput out;
  Claims claims;
  run_controllers();
  check_claims(claims);
  extra_studies(out, claims);
  const auto extra_tables = static_cast<std::ptrdiff_t>(out.report.tables.size());
  const auto extra_plots = static_cast<std::ptrdiff_t>(out.report.plots.size());
  out.summary["system"] = sc_.system;
  out.summary["scenario"] = sc_.name;
  out.summary["file"] = sc_.file;
  summary(out.summary);
  out.summary["claims"] = claims.json();
  out.report.description = sc_.description;
  if (!SummaryOnly::active()) report(out.report);
  out.report.notes = claims.notes();
  out.report.note_ids = claims.note_ids();
  auto& tables = out.report.tables;
  auto& plots = out.report.plots;
  std::rotate(tables.begin(), tables.begin() + extra_tables, tables.end());
  std::rotate(plots.begin(), plots.begin() + extra_plots, plots.end());
  finish(out);
  return out;
}

}  // namespace lathectl::io
