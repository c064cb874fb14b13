#include "lathectl/io/toml_reader.hpp"

#include "lathectl/io/input_file.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#define TOML_EXCEPTIONS 1
#include <toml++/toml.h>

#include "lathectl/io/errors.hpp"

namespace lathectl::io {

namespace {
std::string fmt_num(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}
std::string type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a number";
    case toml::node_type::boolean:
      return "a boolean";
    default:
      return "a date/time";
  }
}
// A value inside `r` for a required key while describing (the reference never shows it).
double neutral(const Range& r) {
  const bool has_lo = r.lo > -1e299, has_hi = r.hi < 1e299;
  if (has_lo && has_hi) return r.lo_open || r.hi_open ? 0.5 * (r.lo + r.hi) : r.lo;
  if (has_lo) return r.lo_open ? r.lo + 1.0 : r.lo;
  if (has_hi) return r.hi_open ? r.hi - 1.0 : r.hi;
  return 0.0;
}
std::string quoted_list(const std::vector<std::string>& choices) {
  std::string list;
  for (const auto& c : choices) list += (list.empty() ? "\"" : ", \"") + c + "\"";
  return list;
}
}  // namespace

bool Range::contains(double v) const noexcept {
  if (!std::isfinite(v)) return false;
  if (lo_open ? !(v > lo) : !(v >= lo)) return false;
  if (hi_open ? !(v < hi) : !(v <= hi)) return false;
  return true;
}

std::string Range::describe() const {
  const bool has_lo = lo > -1e299;
  const bool has_hi = hi < 1e299;
  if (has_lo && has_hi)
    return std::string(lo_open ? "(" : "[") + fmt_num(lo) + ", " + fmt_num(hi) +
           (hi_open ? ")" : "]");
  if (has_lo) return std::string(lo_open ? "> " : "≥ ") + fmt_num(lo);
  if (has_hi) return std::string(hi_open ? "< " : "≤ ") + fmt_num(hi);
  return "finite";
}

std::string unit_of_key(std::string_view key) {
  struct Token {
    std::string_view in, out;
  };
  static constexpr Token kUnits[] = {
      {"mm", "mm"},   {"um", "µm"},   {"m", "m"},       {"m2", "m²"},     {"m3", "m³"},
      {"cm2", "cm²"}, {"cm3", "cm³"}, {"s", "s"},       {"ms", "ms"},     {"min", "min"},
      {"Hz", "Hz"},   {"N", "N"},     {"kN", "kN"},     {"W", "W"},       {"kW", "kW"},
      {"V", "V"},     {"mV", "mV"},   {"Pa", "Pa"},     {"MPa", "MPa"},   {"GPa", "GPa"},
      {"deg", "°"},   {"rpm", "rpm"}, {"rpm2", "rpm²"}, {"rev", "rev"},   {"kg", "kg"},
      {"g", "g"},     {"J", "J"},     {"A", "A"},       {"percent", "%"}, {"pct", "%"},
      {"km", "km"},   {"us", "µs"},   {"kHz", "kHz"},   {"bar", "bar"},   {"rad", "rad"},
      {"ohm", "Ω"},   {"H", "H"},     {"mm2", "mm²"},   {"mm3", "mm³"},   {"Nm", "N·m"},
      {"K", "K"},     {"dB", "dB"},   {"Wb", "Wb"},     {"Wb2", "Wb²"},   {"L", "L"},
      {"per", "/"}};
  auto unit = [&](std::string_view t) -> std::string_view {
    for (const auto& u : kUnits)
      if (u.in == t) return u.out;
    return {};
  };
  // The first '_' after which every token is a unit (and the name before it is a word).
  for (std::size_t i = key.find('_'); i != std::string_view::npos; i = key.find('_', i + 1)) {
    if (i < 2) continue;  // "n_s" is a count, not seconds
    std::string out;
    bool all = true, after_per = true;
    for (std::size_t a = i + 1; a <= key.size();) {
      std::size_t b = key.find('_', a);
      if (b == std::string_view::npos) b = key.size();
      const auto u = unit(key.substr(a, b - a));
      if (u.empty()) {
        all = false;
        break;
      }
      if (u == "/") {
        out += out.empty() ? "1/" : "/";
        after_per = true;
      } else {
        out += (after_per ? "" : "·") + std::string(u);
        after_per = false;
      }
      a = b + 1;
    }
    if (all && !after_per) return out;
  }
  return "";
}

TomlDocument TomlDocument::parse(std::string_view text, const std::string& file_label) {
  TomlDocument d;
  d.file_ = file_label;
  try {
    d.root_ = std::make_shared<toml::table>(toml::parse(text, file_label));
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw InputError(located(file_label, static_cast<int>(b.line), static_cast<int>(b.column),
                             "TOML syntax error: " + std::string(e.description())));
  }
  return d;
}

TomlDocument TomlDocument::parse_file(const std::string& path) {
  return parse(read_input_file(path, "a TOML file", kMaxTomlBytes), path);
}

TableReader::TableReader(const toml::table& table, std::string file, std::string prefix,
                         std::shared_ptr<KeyLocations> locations)
    : table_(&table),
      file_(std::move(file)),
      prefix_(std::move(prefix)),
      locations_(std::move(locations)) {}

TableReader TableReader::describing(std::string prefix, std::shared_ptr<ParamLog> log) {
  TableReader r;
  r.file_ = "(reference)";
  r.prefix_ = std::move(prefix);
  r.log_ = std::move(log);
  return r;
}

void TableReader::log(std::string_view key, std::string kind, std::string range,
                      std::string fallback, bool required, std::string_view doc,
                      std::string value) const {
  if (!log_) return;
  const std::string k = full_key(key);
  for (auto& r : *log_)
    if (r.key == k) {  // read twice, or documented after reading: complete the first row
      if (r.doc.empty()) r.doc = doc;
      if (r.kind.empty()) r.kind = std::move(kind);
      return;
    }
  log_->push_back({k, std::move(kind), std::move(range), std::move(fallback), required,
                   std::string(doc), std::move(value), {}});
}

void TableReader::check(bool ok, std::string_view key, const std::string& message) const {
  if (is_describing()) {  // every rule goes into the reference, whatever the neutral values say
    if (log_)
      for (auto& r : *log_)
        if (r.key == full_key(key)) {
          r.rules += (r.rules.empty() ? "" : "; ") + message;
          return;
        }
    return;
  }
  if (!ok) fail(key, message);
}

void TableReader::read(const Param& p, double& field) {
  const double shop = field / p.scale;
  const double v = number(p.key, p.range, shop);
  log(p.key, "number", p.range.describe(), fmt_num(shop), false, p.doc, fmt_num(v));
  if (has(p.key)) field = v * p.scale;  // absent: the default's exact bits, not ÷ and × scale
}

void TableReader::require(const Param& p, double& field) {
  const double v = number(p.key, p.range);
  log(p.key, "number", p.range.describe(), "", true, p.doc, fmt_num(v));
  field = v * p.scale;
}

std::vector<double> TableReader::numbers(const Param& p, std::size_t min_count) {
  std::vector<double> v = numbers(p.key, p.range, min_count);
  std::string shown;
  for (double x : v) shown += (shown.empty() ? "" : ", ") + fmt_num(x);
  log(p.key, "array of numbers", p.range.describe(), min_count ? "" : "[]", min_count > 0, p.doc,
      "[" + shown + "]");
  if (p.scale != 1.0)
    for (double& x : v) x *= p.scale;
  return v;
}

void TableReader::read(const Param& p, bool& field) {
  const bool v = boolean(p.key, field);
  log(p.key, "boolean", "true or false", field ? "true" : "false", false, p.doc,
      v ? "true" : "false");
  field = v;
}

void TableReader::read(const Param& p, int& field) {
  const auto lo = static_cast<std::int64_t>(std::ceil(std::max(p.range.lo, -2147483648.0)));
  const auto hi = static_cast<std::int64_t>(std::floor(std::min(p.range.hi, 2147483647.0)));
  const auto v = integer(p.key, lo, hi, field);
  log(p.key, "integer", p.range.describe(), std::to_string(field), false, p.doc,
      std::to_string(v));
  field = static_cast<int>(v);
}

void TableReader::read(const Param& p, std::size_t& field) {
  const auto lo = static_cast<std::int64_t>(std::ceil(std::max(p.range.lo, 0.0)));
  const auto hi = static_cast<std::int64_t>(std::floor(std::min(p.range.hi, 9.2e18)));
  const auto v = integer(p.key, lo, hi, static_cast<std::int64_t>(field));
  log(p.key, "integer", p.range.describe(), std::to_string(field), false, p.doc,
      std::to_string(v));
  field = static_cast<std::size_t>(v);
}

std::string TableReader::pick(const Param& p, const std::vector<std::string>& choices,
                              std::optional<std::string> fallback) {
  std::string v = choice(p.key, choices, fallback);
  log(p.key, "string", "one of " + quoted_list(choices), fallback ? "\"" + *fallback + "\"" : "",
      !fallback, p.doc, v);
  return v;
}

std::string TableReader::full_key(std::string_view key) const {
  return prefix_.empty() ? std::string(key) : prefix_ + "." + std::string(key);
}

int TableReader::line() const {
  if (is_describing()) return 0;
  return static_cast<int>(table_->source().begin.line);
}

void TableReader::fail(std::string_view key, const std::string& message) const {
  if (is_describing())  // a reader that fails on defaults: use check() for cross-field rules
    throw InputError("describing '" + full_key(key) + "': " + message);
  const toml::node* n = table_->get(key);
  const auto& src = n ? n->source().begin : table_->source().begin;
  throw InputError(located(file_, static_cast<int>(src.line), static_cast<int>(src.column),
                           "key '" + full_key(key) + "': " + message));
}

bool TableReader::has(std::string_view key) const {
  if (is_describing()) return false;
  return table_->contains(key);
}

const toml::node* TableReader::get(std::string_view key) {
  used_.emplace(key);
  if (is_describing()) return nullptr;
  const toml::node* n = table_->get(key);
  if (n && locations_) {
    const auto& src = n->source().begin;
    locations_->record(full_key(key), static_cast<int>(src.line), static_cast<int>(src.column));
  }
  return n;
}

double TableReader::number_value(std::string_view key, Range range, std::optional<double> fallback) {
  const toml::node* n = get(key);
  if (!n) {
    if (fallback) return *fallback;
    if (is_describing()) {
      log(key, "number", range.describe(), "", true, "", "");
      return neutral(range);
    }
    fail(key, "missing; expected a number " + range.describe());
  }
  double v = 0.0;
  if (auto f = n->as_floating_point())
    v = f->get();
  else if (auto i = n->as_integer())
    v = static_cast<double>(i->get());
  else
    fail(key, "expected a number " + range.describe() + ", got " + type_name(*n));
  if (!range.contains(v))
    fail(key, "expected a number " + range.describe() + ", got " + fmt_num(v));
  return v;
}

std::int64_t TableReader::integer_value(std::string_view key, std::int64_t lo, std::int64_t hi,
                                  std::optional<std::int64_t> fallback) {
  const toml::node* n = get(key);
  if (!n) {
    if (fallback) return *fallback;
    if (is_describing()) {
      log(key, "integer", "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]", "", true, "",
          "");
      return lo;
    }
    fail(key, "missing; expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                  "]");
  }
  auto i = n->as_integer();
  if (!i) fail(key, "expected an integer, got " + type_name(*n));
  const std::int64_t v = i->get();
  if (v < lo || v > hi)
    fail(key, "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                  "], got " + std::to_string(v));
  return v;
}

bool TableReader::boolean_value(std::string_view key, std::optional<bool> fallback) {
  const toml::node* n = get(key);
  if (!n) {
    if (fallback) return *fallback;
    if (is_describing()) return false;
    fail(key, "missing; expected true or false");
  }
  auto b = n->as_boolean();
  if (!b) fail(key, "expected true or false, got " + type_name(*n));
  return b->get();
}

std::string TableReader::string_value(std::string_view key, std::optional<std::string> fallback) {
  const toml::node* n = get(key);
  if (!n) {
    if (fallback) return *fallback;
    if (is_describing()) {
      log(key, "string", "", "", true, "", "");
      return "";
    }
    fail(key, "missing; expected a string");
  }
  auto s = n->as_string();
  if (!s) fail(key, "expected a string, got " + type_name(*n));
  return s->get();
}

std::string TableReader::choice_value(std::string_view key, const std::vector<std::string>& choices,
                                std::optional<std::string> fallback) {
  const std::string list = quoted_list(choices);
  if (is_describing()) {
    used_.emplace(key);
    log(key, "string", "one of " + list, fallback ? "\"" + *fallback + "\"" : "", !fallback, "", "");
    return fallback ? *fallback : choices.front();
  }
  if (!has(key) && !fallback) {
    used_.emplace(key);
    fail(key, "missing; expected one of " + list);
  }
  if (!has(key) && fallback) {  // an optional choice may default to "" (none)
    used_.emplace(key);
    return *fallback;
  }
  const std::string v = string_value(key, fallback);
  for (const auto& c : choices)
    if (c == v) return v;
  fail(key, "expected one of " + list + ", got \"" + v + "\"");
}

// The public getters: the value, and a row of the log (in both modes).
double TableReader::number(std::string_view key, Range range, std::optional<double> fallback) {
  const double v = number_value(key, range, fallback);
  // A NaN default is one the section reader derives from other keys (its description says how).
  const std::string shown_default =
      !fallback ? "" : std::isnan(*fallback) ? "derived" : fmt_num(*fallback);
  log(key, "number", range.describe(), shown_default, !fallback, "",
      is_describing() ? "" : fmt_num(v));
  return v;
}

std::int64_t TableReader::integer(std::string_view key, std::int64_t lo, std::int64_t hi,
                                  std::optional<std::int64_t> fallback) {
  const std::int64_t v = integer_value(key, lo, hi, fallback);
  log(key, "integer", "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]",
      fallback ? std::to_string(*fallback) : "", !fallback, "",
      is_describing() ? "" : std::to_string(v));
  return v;
}

bool TableReader::boolean(std::string_view key, std::optional<bool> fallback) {
  const bool v = boolean_value(key, fallback);
  log(key, "boolean", "true or false", fallback ? (*fallback ? "true" : "false") : "", !fallback,
      "", is_describing() ? "" : (v ? "true" : "false"));
  return v;
}

std::string TableReader::string(std::string_view key, std::optional<std::string> fallback) {
  std::string v = string_value(key, fallback);
  log(key, "string", "", fallback ? "\"" + *fallback + "\"" : "", !fallback, "",
      is_describing() ? "" : v);
  return v;
}

std::string TableReader::choice(std::string_view key, const std::vector<std::string>& choices,
                                std::optional<std::string> fallback) {
  std::string v = choice_value(key, choices, fallback);
  log(key, "string", "one of " + quoted_list(choices), fallback ? "\"" + *fallback + "\"" : "",
      !fallback, "", is_describing() ? "" : v);
  return v;
}

void TableReader::document(std::string_view key, std::string_view doc) const {
  log(key, "", "", "", false, doc, "");
}

std::vector<double> TableReader::numbers(std::string_view key, Range range, std::size_t min_count) {
  const toml::node* n = get(key);
  if (is_describing()) {
    log(key, "array of numbers", range.describe(), min_count ? "" : "[]", min_count > 0, "", "");
    return std::vector<double>(min_count, neutral(range));
  }
  if (!n) {
    if (min_count == 0) return {};
    fail(key, "missing; expected an array of numbers");
  }
  auto a = n->as_array();
  if (!a) fail(key, "expected an array of numbers, got " + type_name(*n));
  std::vector<double> out;
  for (const auto& e : *a) {
    double v = 0.0;
    if (auto f = e.as_floating_point())
      v = f->get();
    else if (auto i = e.as_integer())
      v = static_cast<double>(i->get());
    else
      fail(key, "expected an array of numbers, found " + type_name(e));
    if (!range.contains(v))
      fail(key, "array element " + fmt_num(v) + " outside " + range.describe());
    out.push_back(v);
  }
  if (out.size() < min_count)
    fail(key, "expected at least " + std::to_string(min_count) + " numbers");
  return out;
}

std::vector<std::string> TableReader::choices(std::string_view key,
                                              const std::vector<std::string>& allowed) {
  const std::string list = quoted_list(allowed);
  const toml::node* n = get(key);
  if (is_describing()) {
    log(key, "array of strings", "each one of " + list, "", true, "", "");
    return {allowed.front()};
  }
  if (!n) fail(key, "missing; expected an array of " + list);
  auto a = n->as_array();
  if (!a || a->empty()) fail(key, "expected a non-empty array of " + list);
  std::vector<std::string> out;
  for (const auto& e : *a) {
    auto str = e.as_string();
    if (!str) fail(key, "expected strings, one of " + list);
    const std::string v = str->get();
    if (std::find(allowed.begin(), allowed.end(), v) == allowed.end())
      fail(key, "expected each of " + list + ", got \"" + v + "\"");
    out.push_back(v);
  }
  return out;
}

std::optional<TableReader> TableReader::table(std::string_view key, bool required) {
  const toml::node* n = get(key);
  if (is_describing()) {
    log(key, "table", "", required ? "" : "absent", required, "", "");
    return describing(full_key(key), log_);
  }
  if (!n) {
    if (required) fail(key, "missing table");
    return std::nullopt;
  }
  auto t = n->as_table();
  if (!t) fail(key, "expected a table, got " + type_name(*n));
  TableReader child(*t, file_, full_key(key), locations_);
  child.log_ = log_;
  return child;
}

std::vector<TableReader> TableReader::tables(std::string_view key) {
  const toml::node* n = get(key);
  std::vector<TableReader> out;
  if (is_describing()) {
    log(key, "array of tables", "", "none", false, "", "");
    out.push_back(describing(full_key(key) + "[]", log_));
    return out;
  }
  if (!n) return out;
  auto a = n->as_array();
  if (!a) fail(key, "expected an array of tables, got " + type_name(*n));
  std::size_t i = 0;
  for (const auto& e : *a) {
    auto t = e.as_table();
    if (!t) fail(key, "expected an array of tables, found " + type_name(e));
    const std::string name = full_key(key) + "[" + std::to_string(i++) + "]";
    if (locations_) {
      const auto& src = t->source().begin;
      locations_->record(name, static_cast<int>(src.line), static_cast<int>(src.column));
    }
    out.emplace_back(*t, file_, name, locations_);
    out.back().log_ = log_;
  }
  return out;
}

std::vector<std::pair<double, double>> TableReader::pairs(std::string_view key, Range first,
                                                          Range second) {
  const toml::node* n = get(key);
  std::vector<std::pair<double, double>> out;
  if (is_describing()) log(key, "array of [a, b]", first.describe() + " × " + second.describe(), "[]", false, "", "");
  if (!n) return out;
  auto a = n->as_array();
  if (!a) fail(key, "expected an array of [a, b] pairs, got " + type_name(*n));
  for (const auto& e : *a) {
    auto p = e.as_array();
    if (!p || p->size() != 2) fail(key, "expected an array of [a, b] pairs");
    double v[2] = {0, 0};
    for (std::size_t k = 0; k < 2; ++k) {
      const auto& x = *p->get(k);
      if (auto f = x.as_floating_point())
        v[k] = f->get();
      else if (auto i = x.as_integer())
        v[k] = static_cast<double>(i->get());
      else
        fail(key, "expected numbers in the pairs");
    }
    if (!first.contains(v[0]) || !second.contains(v[1]))
      fail(key, "pair [" + fmt_num(v[0]) + ", " + fmt_num(v[1]) + "] outside " + first.describe() +
                    " × " + second.describe());
    out.emplace_back(v[0], v[1]);
  }
  return out;
}

std::vector<std::string> TableReader::keys() const {
  std::vector<std::string> out;
  if (is_describing()) return out;
  for (const auto& [k, v] : *table_) out.emplace_back(k.str());
  return out;
}

void TableReader::finish() const {
  if (is_describing()) return;
  for (const auto& [k, v] : *table_) {
    if (used_.find(k.str()) == used_.end()) {
      std::string known;
      for (const auto& u : used_) known += (known.empty() ? "" : ", ") + u;
      const auto& src = v.source().begin;
      throw InputError(located(file_, static_cast<int>(src.line), static_cast<int>(src.column),
                               "unknown key '" + full_key(k.str()) + "'" +
                                   (known.empty() ? "" : " (known here: " + known + ")")));
    }
  }
}

}  // namespace lathectl::io
