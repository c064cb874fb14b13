#include "lathectl/io/operation_log.hpp"

#include <cmath>
#include <limits>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/input_file.hpp"

namespace lathectl::io {

using nlohmann::json;

namespace {

// The document's own keys (the rows are read after them).
OperationLog read_head(const JsonFile& f) {
  const json& doc = f.doc();
  if (!doc.is_object()) f.fail("", "expected an object with the key 'rows'");
  const auto rows = doc.find("rows");
  if (rows == doc.end() || !rows->is_array()) f.fail("rows", "expected an array of operations");
  OperationLog log;
  if (doc.contains("unit")) log.unit = f.text(doc, "", "unit");
  if (log.unit != "N" && log.unit != "W") f.fail("unit", "expected N or W");
  if (const auto p = doc.find("program"); p != doc.end() && p->is_string())
    log.program = p->get<std::string>();
  if (const auto m = doc.find("missed_rows"); m != doc.end() && m->is_number()) {
    log.missed_rows = m->get<double>();
    if (!(std::isfinite(log.missed_rows) && log.missed_rows >= 0.0))
      f.fail("missed_rows", "expected a count ≥ 0");
  }
  return log;
}

// The taught references and the messages (read after the rows).
void read_tail(const JsonFile& f, OperationLog& log) {
  const json& doc = f.doc();
  if (const auto t = doc.find("taught"); t != doc.end() && t->is_array()) {
    std::size_t i = 0;
    for (const json& e : *t) {
      const std::string k = JsonFile::element("taught", i++);
      log.taught.push_back({f.number(e, k, "tool"), f.number(e, k, "operation"),
                            f.number(e, k, "reference"), f.text(e, k, "unit")});
    }
  }
  if (const auto m = doc.find("messages"); m != doc.end() && m->is_array()) {
    std::size_t i = 0;
    for (const json& e : *m) {
      const std::string k = JsonFile::element("messages", i++);
      log.messages.push_back({f.number(e, k, "time_s"), f.text(e, k, "text")});
    }
  }
}

}  // namespace

OperationLog::Operation read_operation(const JsonFile& f, const json& row, const std::string& k) {
  OperationLog::Operation o;
  o.line = f.number(row, k, "line");
  o.limit = f.number(row, k, "limit");
  o.load_mean = f.number(row, k, "load_mean");
  o.load_peak = f.number(row, k, "load_peak");
  o.feed_min = f.number(row, k, "feed_min");
  o.feed_mean = f.number(row, k, "feed_mean");
  o.time_in_cut_s = f.number(row, k, "time_in_cut_s");
  o.operation = f.number(row, k, "operation");
  // LinuxCNC's tool numbers (iocontrol.0.tool-number, s32): whole, ≥ 0.
  const double tool = f.number(row, k, "tool");
  if (!(tool >= 0.0 && tool <= std::numeric_limits<int>::max() && tool == std::floor(tool)))
    f.fail(JsonFile::member(k, "tool"), "expected a tool number (a whole number ≥ 0)");
  o.tool = static_cast<int>(tool);
  o.mode = f.text(row, k, "mode");
  o.reasons = f.text(row, k, "reasons");
  o.alarm = f.text(row, k, "alarm");
  return o;
}

OperationLog read_operation_log(const JsonFile& f) {
  OperationLog log = read_head(f);
  std::size_t i = 0;
  for (const json& row : f.doc().at("rows"))
    log.rows.push_back(read_operation(f, row, JsonFile::element("rows", i++)));
  read_tail(f, log);
  return log;
}

OperationLog read_operation_log(const std::filesystem::path& file,
                                const std::function<void(const OperationLog::Operation&)>& each,
                                std::size_t chunk) {
  std::string wrong_row;  // the first, reported after the document's keys as above
  const JsonFile::Element row = [&](const JsonFile& f, const json& r, const std::string& key) {
    if (!wrong_row.empty()) return;
    OperationLog::Operation o;
    try {
      o = read_operation(f, r, key);
    } catch (const InputError& e) {
      wrong_row = e.what();
      return;
    }
    each(o);
  };
  const JsonFile f = JsonFile::read_streamed(file, "the operation log", kMaxOperationLogBytes,
                                             "rows", row, {"taught", "messages"}, chunk);
  OperationLog log = read_head(f);
  if (!wrong_row.empty()) throw InputError(wrong_row);
  read_tail(f, log);
  return log;
}

}  // namespace lathectl::io
