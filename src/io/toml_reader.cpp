#include "lathectl/io/toml_reader.hpp"

#include "lathectl/io/input_file.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#define TOML_EXCEPTIONS 1
#include <toml++/toml.h>

#include "lathectl/io/errors.hpp"
#include "toml_reader_text.hpp"

namespace lathectl::io {

using detail::fmt_num;
using detail::quoted_list;

namespace {
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
// A value inside `r` for a required key while describing (the reference never shows it);
// variant 1 another one, to find the defaults that follow a required key.
double neutral(const Range& r, int variant = 0) {
  const bool has_lo = r.lo > -1e299, has_hi = r.hi < 1e299;
  if (variant == 1) {
    if (has_lo && has_hi) return r.lo + 0.25 * (r.hi - r.lo);
    if (has_lo) return r.lo + 3.0;
    if (has_hi) return r.hi - 3.0;
    return 1.0;
  }
  if (has_lo && has_hi) return r.lo_open || r.hi_open ? 0.5 * (r.lo + r.hi) : r.lo;
  if (has_lo) return r.lo_open ? r.lo + 1.0 : r.lo;
  if (has_hi) return r.hi_open ? r.hi - 1.0 : r.hi;
  return 0.0;
}
// A number as TOML takes it and a person reads it: 6.0e6, 0.25, 1500.0.
std::string toml_number(double v) {
  char buf[64];
  const double a = std::abs(v);
  if (a == 0.0 || (a >= 1e-3 && a < 1e6)) {
    std::snprintf(buf, sizeof buf, "%.6g", v);
    std::string s = buf;
    if (s.find_first_of(".e") == std::string::npos) s += ".0";
    return s;
  }
  const int e = static_cast<int>(std::floor(std::log10(a)));
  std::snprintf(buf, sizeof buf, "%.6g", v / std::pow(10.0, e));
  std::string m = buf;
  if (m.find('.') == std::string::npos) m += ".0";
  return m + "e" + std::to_string(e);
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

TableReader TableReader::describing(std::string prefix, std::shared_ptr<ParamLog> log,
                                    int variant) {
  TableReader r;
  r.file_ = "(reference)";
  r.prefix_ = std::move(prefix);
  r.log_ = std::move(log);
  r.variant_ = variant;
  return r;
}

void TableReader::warn(std::string_view key, const std::string& message) const {
  if (is_describing() || !warnings_) return;
  const toml::node* n = table_->get(key);
  const auto& src = n ? n->source().begin : table_->source().begin;
  warnings_->push_back(located(file_, static_cast<int>(src.line), static_cast<int>(src.column),
                               "key '" + full_key(key) + "': " + message));
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
  if (!table_->contains(key)) {
    // Absent: is it there under a misspelt name, or in another unit? That is the mistake.
    std::vector<std::string> unread;
    for (const auto& [k, v] : *table_)
      if (used_.find(k.str()) == used_.end()) unread.emplace_back(k.str());
    for (const auto& u : unread)
      if (unit_mismatch(u, key)) fail_unknown(u, key);
    const std::string near = nearest_name(key, unread);
    if (!near.empty()) fail_unknown(near, key);
  }
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
      return neutral(range, variant_);
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
      return variant_ == 1 && lo < hi ? lo + 1 : lo;
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
  const std::string near = nearest_name(v, choices);
  fail(key, "expected one of " + list + ", got \"" + v + "\"" +
                (near.empty() ? "" : " — did you mean \"" + near + "\"?"));
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
    return std::vector<double>(min_count, neutral(range, variant_));
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
    if (std::find(allowed.begin(), allowed.end(), v) == allowed.end()) {
      const std::string near = nearest_name(v, allowed);
      fail(key, "expected each of " + list + ", got \"" + v + "\"" +
                    (near.empty() ? "" : " — did you mean \"" + near + "\"?"));
    }
    out.push_back(v);
  }
  std::string shown;
  for (const auto& v : out) shown += (shown.empty() ? "" : ", ") + v;
  log(key, "array of strings", "each one of " + list, "", true, "", "[" + shown + "]");
  return out;
}

std::optional<TableReader> TableReader::table(std::string_view key, bool required) {
  const toml::node* n = get(key);
  if (is_describing()) {
    log(key, "table", "", required ? "" : "absent", required, "", "");
    return describing(full_key(key), log_, variant_);
  }
  // A heading in the run's settings, as in the reference (the settings table leaves it out).
  log(key, "table", "", required ? "" : "absent", required, "", "");
  if (!n) {
    if (required) fail(key, "missing table");
    return std::nullopt;
  }
  auto t = n->as_table();
  if (!t) fail(key, "expected a table, got " + type_name(*n));
  TableReader child(*t, file_, full_key(key), locations_);
  child.log_ = log_;
  child.warnings_ = warnings_;
  return child;
}

std::vector<TableReader> TableReader::tables(std::string_view key) {
  const toml::node* n = get(key);
  std::vector<TableReader> out;
  if (is_describing()) {
    log(key, "array of tables", "", "none", false, "", "");
    out.push_back(describing(full_key(key) + "[]", log_, variant_));
    return out;
  }
  log(key, "array of tables", "", "none", false, "", "");
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
    out.back().warnings_ = warnings_;
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

void TableReader::fail_unknown(std::string_view user, std::string_view known) const {
  const toml::node* n = table_->get(user);
  const auto& src = n->source().begin;
  const bool is_table = n->is_table() || (n->is_array_of_tables() && !n->as_array()->empty());
  std::string msg =
      std::string(is_table ? "unknown table '" : "unknown key '") + full_key(user) + "'";
  if (const auto m = unit_mismatch(user, known)) {
    // "stiffness is given in N/m: stiffness_N_per_m = 6.0e6 for 6 N/µm"
    msg += ": " + m->quantity + " is given in " + m->unit + ": " + std::string(known);
    double v = std::nan("");
    if (auto f = n->as_floating_point())
      v = f->get();
    else if (auto i = n->as_integer())
      v = static_cast<double>(i->get());
    if (std::isfinite(v) && std::isfinite(m->factor))
      msg += " = " + toml_number(v * m->factor) + " for " + fmt_num(v) + " " + m->user_unit;
    else if (!m->user_unit.empty())
      msg += " (" + m->user_unit + " is not a unit of it)";
  } else {
    msg += " — did you mean '" + full_key(known) + "'?";  // the full key, as every message
  }
  throw InputError(located(file_, static_cast<int>(src.line), static_cast<int>(src.column), msg));
}

void TableReader::finish() const {
  if (is_describing()) return;
  // The first unknown key as the file reads (the table iterates by name).
  const toml::node* first = nullptr;
  std::string first_key;
  for (const auto& [k, v] : *table_) {
    if (used_.find(k.str()) != used_.end()) continue;
    const auto& a = v.source().begin;
    if (!first || a.line < first->source().begin.line ||
        (a.line == first->source().begin.line && a.column < first->source().begin.column)) {
      first = &v;
      first_key = k.str();
    }
  }
  if (!first) return;
  std::vector<std::string> known(used_.begin(), used_.end());
  for (const auto& k : known)
    if (unit_mismatch(first_key, k)) fail_unknown(first_key, k);
  const std::string near = nearest_name(first_key, known);
  if (!near.empty()) fail_unknown(first_key, near);
  std::string list;
  for (const auto& u : used_) list += (list.empty() ? "" : ", ") + u;
  const auto& src = first->source().begin;
  throw InputError(
      located(file_, static_cast<int>(src.line), static_cast<int>(src.column),
              std::string(first->is_table() || first->is_array_of_tables() ? "unknown table '"
                                                                           : "unknown key '") +
                  full_key(first_key) + "'" + (list.empty() ? "" : " (known here: " + list + ")")));
}

}  // namespace lathectl::io
