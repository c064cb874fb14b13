// The spec's reader: every error names SPEC's file, line and key (io::located).
#include "sweep/spec.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <toml++/toml.h>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/input_file.hpp"
#include "lathectl/io/scenario.hpp"

namespace lathectl::sweep {
namespace {

constexpr std::size_t kMaxSpecBytes = 1 << 20;
constexpr std::size_t kMaxSamples = 10'000'000;

Place place(const toml::node& n) {
  const auto& b = n.source().begin;
  return {static_cast<int>(b.line), static_cast<int>(b.column)};
}

[[noreturn]] void fail(const std::string& file, const toml::node& n, const std::string& key,
                       const std::string& message) {
  const Place p = place(n);
  throw io::InputError(io::located(file, p.line, p.column, "key '" + key + "': " + message));
}

// A scalar of the spec as a Value; nullopt for a table, array, date or time.
std::optional<Value> scalar(const toml::node& n) {
  if (const auto* i = n.as_integer()) return Value{i->get()};
  if (const auto* f = n.as_floating_point()) return Value{f->get()};
  if (const auto* b = n.as_boolean()) return Value{b->get()};
  if (const auto* s = n.as_string()) return Value{s->get()};
  return std::nullopt;
}

void check_key_name(const std::string& file, const toml::node& n, const std::string& key) {
  if (parse_key_path(key).size() < 2)
    fail(file, n, key,
         "a varied key is written table.key as in the scenario (\"cut.rpm\", an array element "
         "by index: \"cut.depth_mm[0]\")");
}

GridKey read_grid_key(const std::string& file, const std::string& key, const toml::node& n) {
  const std::string full = "grid.\"" + key + "\"";
  check_key_name(file, n, key);
  const auto* arr = n.as_array();
  if (!arr || arr->empty())
    fail(file, n, full, "expected a non-empty array of values ([0.1, 0.2], [\"a\", \"b\"])");
  GridKey g{key, place(n), {}, {}};
  for (const auto& e : *arr) {
    auto v = scalar(e);
    if (!v) fail(file, e, full, "each value is a number, boolean or string");
    if (const double* d = std::get_if<double>(&*v); d && !std::isfinite(*d))
      fail(file, e, full, "a value is not finite");
    g.values.push_back(std::move(*v));
    g.value_at.push_back(place(e));
  }
  return g;
}

double finite_number(const std::string& file, const toml::node& n, const std::string& key) {
  double v = std::numeric_limits<double>::quiet_NaN();
  if (const auto* i = n.as_integer()) v = static_cast<double>(i->get());
  if (const auto* f = n.as_floating_point()) v = f->get();
  if (!std::isfinite(v)) fail(file, n, key, "expected a finite number");
  return v;
}

Distribution read_distribution(const std::string& file, const std::string& full,
                               const toml::node& n) {
  const auto* t = n.as_table();
  if (!t || t->size() != 1)
    fail(file, n, full,
         "expected one distribution: { uniform = [lo, hi] }, { normal = [mean, sd] } or "
         "{ choice = [v1, v2, ...] }");
  const auto it = t->begin();
  const std::string kind(it->first.str());
  const toml::node& arg = it->second;
  const auto* arr = arg.as_array();
  Distribution d;
  if (kind == "choice") {
    d.kind = Distribution::Kind::Choice;
    if (!arr || arr->empty()) fail(file, arg, full, "choice: expected a non-empty array");
    for (const auto& e : *arr) {
      auto v = scalar(e);
      if (!v) fail(file, e, full, "choice: each value is a number, boolean or string");
      d.choices.push_back(std::move(*v));
    }
    return d;
  }
  if (kind != "uniform" && kind != "normal")
    fail(file, n, full,
         "unknown distribution '" + kind + "' (known: uniform, normal, choice)");
  if (!arr || arr->size() != 2)
    fail(file, arg, full, kind + ": expected two numbers, " +
                              (kind == "uniform" ? "[lo, hi]" : "[mean, sd]"));
  d.a = finite_number(file, *arr->get(0), full);
  d.b = finite_number(file, *arr->get(1), full);
  if (kind == "uniform") {
    if (!(d.a < d.b)) fail(file, arg, full, "uniform: expected lo < hi");
  } else {
    d.kind = Distribution::Kind::Normal;
    if (!(d.b > 0.0)) fail(file, arg, full, "normal: the standard deviation must be > 0");
  }
  return d;
}

void read_random(const std::string& file, const toml::table& t, Spec& s) {
  s.random_at = place(t);
  bool has_samples = false;
  for (const auto& [k, n] : t) {
    const std::string key(k.str());
    if (key == "samples") {
      const auto* i = n.as_integer();
      if (!i || i->get() < 1 || static_cast<std::uint64_t>(i->get()) > kMaxSamples)
        fail(file, n, "random.samples", "expected an integer in [1, 10000000]");
      s.samples = static_cast<std::size_t>(i->get());
      has_samples = true;
    } else if (key == "seed") {
      const auto* i = n.as_integer();
      if (!i || i->get() < 0) fail(file, n, "random.seed", "expected an integer >= 0");
      s.seed = static_cast<std::uint64_t>(i->get());
    } else {
      check_key_name(file, n, key);
      s.random.push_back({key, place(n), read_distribution(file, "random.\"" + key + "\"", n)});
    }
  }
  if (!has_samples) fail(file, t, "random.samples", "required: how many samples to draw");
  if (s.random.empty())
    fail(file, t, "random", "no key to draw: add \"table.key\" = { uniform = [lo, hi] }");
}

void read_output(const std::string& file, const toml::table& t, Spec& s) {
  for (const auto& [k, n] : t) {
    const std::string key(k.str());
    if (key != "metrics") fail(file, n, "output." + key, "unknown key (known: metrics)");
    const auto* arr = n.as_array();
    if (!arr || arr->empty())
      fail(file, n, "output.metrics", "expected a non-empty array of metric names");
    for (const auto& e : *arr) {
      const auto* str = e.as_string();
      if (!str || str->get().empty())
        fail(file, e, "output.metrics", "each metric is a name such as \"a.b\"");
      s.metrics.push_back(str->get());
    }
  }
}

// [report]: the lobes over the heat maps. Its keys are checked against [grid] after the whole
// spec is read (check_report).
void read_report(const std::string& file, const toml::table& t, Spec& s) {
  LobesOverlay o;
  o.at = place(t);
  const auto text = [&](const toml::node& n, const std::string& key) {
    const auto* str = n.as_string();
    if (!str || str->get().empty()) fail(file, n, "report." + key, "expected a non-empty string");
    return str->get();
  };
  bool has_reference = false;
  for (const auto& [k, n] : t) {
    const std::string key(k.str());
    if (key == "lobes") {
      o.machine = text(n, key);
      o.machine_at = place(n);
    } else if (key == "speed") {
      o.speed = text(n, key);
      o.speed_at = place(n);
    } else if (key == "depth") {
      o.depth = text(n, key);
      o.depth_at = place(n);
    } else if (key == "chatter") {
      o.chatter = text(n, key);
    } else if (key == "depth_reference") {
      o.depth_reference = finite_number(file, n, "report.depth_reference");
      if (!(o.depth_reference > 0.0)) fail(file, n, "report.depth_reference", "expected > 0");
      has_reference = true;
    } else if (key == "depth_exponent") {
      o.depth_exponent = finite_number(file, n, "report.depth_exponent");
      if (!(o.depth_exponent >= 0.0 && o.depth_exponent < 1.0))
        fail(file, n, "report.depth_exponent", "expected a number in [0, 1)");
    } else if (key == "chatter_above") {
      o.chatter_above = finite_number(file, n, "report.chatter_above");
    } else {
      fail(file, n, "report." + key,
           "unknown key (known: lobes, speed, depth, depth_reference, depth_exponent, chatter, "
           "chatter_above)");
    }
  }
  const std::pair<const char*, bool> required[] = {
      {"lobes", o.machine.empty()}, {"speed", o.speed.empty()}, {"depth", o.depth.empty()}};
  for (const auto& [key, missing] : required)
    if (missing)
      fail(file, t, std::string("report.") + key,
           "required: [report] draws the lobes of a machine file (lobes = \"machine.toml\") "
           "over the heat maps of the grid keys speed = \"...\" and depth = \"...\"");
  if (o.depth_exponent > 0.0 && !has_reference)
    fail(file, t, "report.depth_reference",
         "required with depth_exponent: the depth key's value at which the machine file's K_f "
         "holds");
  s.lobes = std::move(o);
}

// [report]'s speed and depth: two different [grid] keys whose values are numbers.
void check_report(const Spec& s) {
  const auto& o = *s.lobes;
  for (const bool speed : {true, false}) {
    const std::string& key = speed ? o.speed : o.depth;
    const std::string name = speed ? "report.speed" : "report.depth";
    const Place p = speed ? o.speed_at : o.depth_at;
    const auto g = std::find_if(s.grid.begin(), s.grid.end(),
                                [&](const GridKey& k) { return k.key == key; });
    const auto at = [&] { return io::located(s.file, p.line, p.column, "key '" + name); };
    if (g == s.grid.end() || g - s.grid.begin() > 1)
      throw io::InputError(at() + "': '" + key +
                           "' is not one of the first two keys of [grid] (the heat maps' axes)");
    for (const auto& v : g->values)
      if (std::holds_alternative<bool>(v) || std::holds_alternative<std::string>(v))
        throw io::InputError(at() + "': [grid] \"" + key + "\" has a value that is not a number");
  }
  if (o.speed == o.depth)
    throw io::InputError(io::located(s.file, o.depth_at.line, o.depth_at.column,
                                     "key 'report.depth': the same key as report.speed"));
}

void check_distinct_keys(const Spec& s) {
  std::set<std::string> seen;
  for (const auto& g : s.grid) seen.insert(g.key);
  for (const auto& r : s.random)
    if (!seen.insert(r.key).second)
      throw io::InputError(io::located(s.file, r.at.line, r.at.column,
                                       "key '" + r.key + "': varied in [grid] and [random]"));
}

}  // namespace

std::vector<PathPart> parse_key_path(const std::string& key) {
  std::vector<PathPart> parts;
  std::size_t i = 0;
  while (i <= key.size()) {
    const std::size_t dot = key.find('.', i);
    std::string part = key.substr(i, dot == std::string::npos ? std::string::npos : dot - i);
    PathPart p;
    if (const auto lb = part.find('['); lb != std::string::npos) {
      if (part.back() != ']' || lb + 2 > part.size() - 1) return {};
      const std::string digits = part.substr(lb + 1, part.size() - lb - 2);
      if (digits.empty() || digits.size() > 6 ||
          digits.find_first_not_of("0123456789") != std::string::npos)
        return {};
      p.index = std::stol(digits);
      part.resize(lb);
    }
    if (part.empty() || part.find_first_of("[] \"'") != std::string::npos) return {};
    p.name = part;
    parts.push_back(p);
    if (dot == std::string::npos) break;
    i = dot + 1;
  }
  return parts;
}

double number_of(const Value& v) {
  if (const auto* d = std::get_if<double>(&v)) return *d;
  if (const auto* i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
  return std::numeric_limits<double>::quiet_NaN();
}

std::string to_text(const Value& v) {
  return std::visit([](const auto& x) { return nlohmann::json(x).dump(); }, v);
}

std::vector<std::string> Spec::varied_keys() const {
  std::vector<std::string> k;
  for (const auto& g : grid) k.push_back(g.key);
  for (const auto& r : random) k.push_back(r.key);
  return k;
}

Place Spec::place_of(const std::string& key) const {
  for (const auto& g : grid)
    if (g.key == key) return g.at;
  for (const auto& r : random)
    if (r.key == key) return r.at;
  return {};
}

Spec parse_spec(std::string_view text, const std::string& file_label) {
  toml::table root;
  try {
    root = toml::parse(text, file_label);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw io::InputError(io::located(file_label, static_cast<int>(b.line),
                                     static_cast<int>(b.column),
                                     "TOML syntax error: " + std::string(e.description())));
  }
  Spec s;
  s.file = file_label;
  for (const auto& [k, n] : root) {
    const std::string key(k.str());
    if (key == "scenario") {
      const auto* str = n.as_string();
      if (!str || str->get().empty()) fail(file_label, n, key, "expected a file name");
      s.scenario = str->get();
      s.scenario_at = place(n);
    } else if (key == "grid" && n.is_table()) {
      for (const auto& [gk, gn] : *n.as_table())
        s.grid.push_back(read_grid_key(file_label, std::string(gk.str()), gn));
    } else if (key == "random" && n.is_table()) {
      read_random(file_label, *n.as_table(), s);
    } else if (key == "output" && n.is_table()) {
      read_output(file_label, *n.as_table(), s);
    } else if (key == "report" && n.is_table()) {
      read_report(file_label, *n.as_table(), s);
    } else {
      fail(file_label, n, key,
           "unknown key (a spec has scenario = \"...\", [grid], [random], [output] and "
           "[report])");
    }
  }
  if (s.scenario.empty())
    throw io::InputError(io::located(file_label, 1, 1,
                                     "key 'scenario': required: the scenario file to vary"));
  if (s.grid.empty() && s.random.empty())
    throw io::InputError(io::located(file_label, 1, 1,
                                     "nothing to vary: give a [grid] or a [random] table"));
  // toml++ keeps a table's keys sorted: the spec's order is its lines'.
  const auto by_place = [](const auto& x, const auto& y) {
    return std::pair(x.at.line, x.at.column) < std::pair(y.at.line, y.at.column);
  };
  std::sort(s.grid.begin(), s.grid.end(), by_place);
  std::sort(s.random.begin(), s.random.end(), by_place);
  check_distinct_keys(s);
  if (s.lobes) {
    check_report(s);
    if (s.lobes->machine.is_relative())
      s.lobes->machine = std::filesystem::path(file_label).parent_path() / s.lobes->machine;
    s.lobes->machine = std::filesystem::absolute(s.lobes->machine).lexically_normal();
  }
  if (s.scenario.is_relative())
    s.scenario = std::filesystem::path(file_label).parent_path() / s.scenario;
  // Absolute: a case's base_dir is read where the case runs (a Dask worker's directory too).
  s.scenario = std::filesystem::absolute(s.scenario).lexically_normal();
  return s;
}

std::string read_scenario(const Spec& spec) {
  try {
    return io::read_scenario_text(spec.scenario.string());
  } catch (const io::InputError& e) {
    throw io::InputError(io::located(spec.file, spec.scenario_at.line, spec.scenario_at.column,
                                     "key 'scenario': " + std::string(e.what())));
  }
}

Spec read_spec(const std::string& path) {
  return parse_spec(io::read_input_file(path, "a sweep spec", kMaxSpecBytes), path);
}

}  // namespace lathectl::sweep
