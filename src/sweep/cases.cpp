// The cases: values drawn, applied to the scenario with toml++, checked by the scenario's reader.
#include "sweep/cases.hpp"

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>
#include <sstream>
#include <toml++/toml.h>

#include "lathectl/io/errors.hpp"
#include "systems/registry.hpp"

namespace lathectl::sweep {
namespace {

// [0, 1) from 53 bits of the generator: the same numbers on every platform.
double unit(std::mt19937_64& g) { return static_cast<double>(g() >> 11) * 0x1p-53; }

Value draw(const Distribution& d, std::mt19937_64& g) {
  switch (d.kind) {
    case Distribution::Kind::Uniform:
      return d.a + (d.b - d.a) * unit(g);
    case Distribution::Kind::Normal: {  // Box–Muller, u1 in (0, 1]
      const double u1 = 1.0 - unit(g), u2 = unit(g);
      return d.a + d.b * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
    }
    case Distribution::Kind::Choice:
    default: {
      const auto n = static_cast<double>(d.choices.size());
      const auto i = static_cast<std::size_t>(std::floor(unit(g) * n));
      return d.choices[std::min(i, d.choices.size() - 1)];
    }
  }
}

// Calls f with the value as TOML takes it: an integer where the scenario writes a float becomes
// that float (the reader takes either; the text stays the scenario's).
template <class F>
void with_value(const Value& v, bool as_float, F&& f) {
  if (const auto* i = std::get_if<std::int64_t>(&v); i && as_float)
    f(static_cast<double>(*i));
  else
    std::visit(f, v);
}

toml::node* child(toml::node* parent, const PathPart& p, bool last, const std::string& key,
                  const std::string& label) {
  auto fail = [&](const std::string& why) -> toml::node* {
    throw io::InputError(label + ": key '" + key + "': " + why);
  };
  auto* t = parent->as_table();
  if (!t) return fail("'" + p.name + "' is below a value that is not a table");
  toml::node* n = t->get(p.name);
  if (!n) {
    if (p.index >= 0) return fail("the scenario has no array '" + p.name + "' to index");
    if (last) return nullptr;  // set by the caller
    n = &t->insert_or_assign(p.name, toml::table{}).first->second;
  }
  if (p.index < 0) return n;
  auto* a = n->as_array();
  if (!a) return fail("'" + p.name + "' is not an array");
  if (static_cast<std::size_t>(p.index) >= a->size())
    return fail("index " + std::to_string(p.index) + " past the end of '" + p.name + "' (" +
                std::to_string(a->size()) + " elements)");
  return a->get(static_cast<std::size_t>(p.index));
}

// Sets the value at `key`, replacing what the scenario writes there (of any type: the reader
// then judges it) or adding the key.
void set(toml::table& root, const std::string& key, const Value& v, const std::string& label) {
  const auto parts = parse_key_path(key);
  toml::node* n = &root;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) n = child(n, parts[i], false, key, label);
  const PathPart& last = parts.back();
  auto* t = n->as_table();
  if (!t) throw io::InputError(label + ": key '" + key + "': below a value that is not a table");
  toml::node* slot = t->get(last.name);
  if (last.index >= 0) slot = child(n, last, true, key, label);
  if (slot && (slot->is_table() || slot->is_array()))
    throw io::InputError(label + ": key '" + key + "' is a " +
                         (slot->is_table() ? "table" : "array") +
                         ", not a value (an array's element is key[i])");
  const bool as_float = slot && slot->is_floating_point();
  if (last.index < 0) {
    with_value(v, as_float, [&](const auto& x) { t->insert_or_assign(last.name, x); });
  } else {
    auto* a = t->get(last.name)->as_array();
    const auto at = a->cbegin() + last.index;
    with_value(v, as_float, [&](const auto& x) { a->replace(at, x); });
  }
}

std::string vars_json(const std::vector<std::string>& keys, const std::vector<Value>& values) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (std::size_t k = 0; k < keys.size(); ++k)
    std::visit([&](const auto& x) { j[keys[k]] = x; }, values[k]);
  return j.dump();
}

// The message without its "<label>:line:col: " (the case's text lines mean nothing in SPEC).
std::string without_location(const std::string& msg, const std::string& label) {
  if (msg.rfind(label, 0) != 0) return msg;
  const auto colon = msg.find(": ", label.size());
  return colon == std::string::npos ? msg : msg.substr(colon + 2);
}

// The reader's message is about `key` itself: its value, or a key or table the system does not
// know ("unknown table 'cut'").
bool names_key(const std::string& why, const std::string& key) {
  const auto parts = parse_key_path(key);
  std::string plain;  // "part.depth_steps.depth_mm" for "part.depth_steps[0].depth_mm"
  for (const auto& p : parts) plain += (plain.empty() ? "" : ".") + p.name;
  return why.find("'" + key + "'") != std::string::npos ||
         why.find("'" + plain + "'") != std::string::npos ||
         why.rfind("unknown key '", 0) == 0 || why.rfind("unknown table '", 0) == 0;
}

}  // namespace

std::vector<std::vector<Value>> draw_values(const Spec& spec) {
  std::vector<std::vector<Value>> samples;
  std::mt19937_64 g(spec.seed);
  for (std::size_t s = 0; s < spec.samples; ++s) {
    std::vector<Value> row;
    for (const auto& r : spec.random) row.push_back(draw(r.dist, g));
    samples.push_back(std::move(row));
  }
  if (samples.empty()) samples.emplace_back();
  std::size_t points = 1;
  for (const auto& k : spec.grid) points *= k.values.size();
  std::vector<std::vector<Value>> out;
  out.reserve(points * samples.size());
  for (std::size_t p = 0; p < points; ++p) {
    std::vector<Value> grid(spec.grid.size());
    std::size_t rest = p;
    for (std::size_t k = spec.grid.size(); k-- > 0;) {  // the last key fastest
      grid[k] = spec.grid[k].values[rest % spec.grid[k].values.size()];
      rest /= spec.grid[k].values.size();
    }
    for (const auto& s : samples) {
      auto row = grid;
      row.insert(row.end(), s.begin(), s.end());
      out.push_back(std::move(row));
    }
  }
  return out;
}

std::string apply(const std::string& scenario_text, const std::string& label,
                  const std::vector<std::string>& keys, const std::vector<Value>& values) {
  toml::table root;
  try {
    root = toml::parse(scenario_text, label);
  } catch (const toml::parse_error& e) {
    throw io::InputError(label + ": TOML syntax error: " + std::string(e.description()));
  }
  for (const char* t : kStudyTables) root.erase(t);
  for (std::size_t k = 0; k < keys.size(); ++k) set(root, keys[k], values[k], label);
  std::ostringstream os;
  os << toml::toml_formatter(root);
  return os.str();
}

std::string case_label(const std::string& base_dir, std::int64_t id) {
  return (std::filesystem::path(base_dir) / ("case " + std::to_string(id))).string();
}

void check_values(const Spec& spec, const std::string& scenario_text,
                  const std::vector<std::vector<Value>>& values, const io::MaterialLibrary& lib) {
  const std::string base = spec.scenario.parent_path().string();
  const std::string label = case_label(base, -1);
  auto check = [&](const std::string& key, const Value& v, Place at) {
    for (const char* t : kStudyTables)
      if (parse_key_path(key).front().name == t)
        throw io::InputError(io::located(
            spec.file, at.line, at.column,
            "key '" + key + "': the scenario's own studies ([study], [sweep], [compare]) are off "
            "in a sweep's cases; vary the keys of one run"));
    std::string text;
    try {
      text = apply(scenario_text, label, {key}, {v});
      systems::parse_scenario(text, label, lib);
    } catch (const io::InputError& e) {
      std::string why = without_location(e.what(), label);
      // A rule at another key (the cut longer than run.duration_s at this speed): the value in
      // the scenario's other values, which the cases may change; their rows will say.
      if (!text.empty() && !names_key(why, key)) return;
      if (const std::string self = "key '" + key + "': "; why.rfind(self, 0) == 0)
        why.erase(0, self.size());  // the spec's error names the key already
      throw io::InputError(io::located(spec.file, at.line, at.column,
                                       "key '" + key + "' = " + to_text(v) + ": " + why));
    }
  };
  // The scenario itself, its studies removed (its own errors name its own file and line).
  systems::parse_scenario(apply(scenario_text, spec.scenario.string(), {}, {}),
                          spec.scenario.string(), lib);
  for (const auto& g : spec.grid)
    for (std::size_t i = 0; i < g.values.size(); ++i) check(g.key, g.values[i], g.value_at[i]);
  for (std::size_t r = 0; r < spec.random.size(); ++r) {
    const auto& k = spec.random[r];
    switch (k.dist.kind) {
      case Distribution::Kind::Uniform:
        check(k.key, k.dist.a, k.at);
        check(k.key, k.dist.b, k.at);
        break;
      case Distribution::Kind::Choice:
        for (const auto& c : k.dist.choices) check(k.key, c, k.at);
        break;
      case Distribution::Kind::Normal:
        for (std::size_t c = 0; c < values.size() && c < spec.samples; ++c)
          check(k.key, values[c][spec.grid.size() + r], k.at);
        break;
    }
  }
}

std::vector<Case> make_cases(const Spec& spec, const std::string& scenario_text,
                             const std::vector<std::vector<Value>>& values) {
  const std::string base = spec.scenario.parent_path().string();
  const auto keys = spec.varied_keys();
  std::vector<Case> cases;
  cases.reserve(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    const auto id = static_cast<std::int64_t>(i);
    cases.push_back({id, apply(scenario_text, case_label(base, id), keys, values[i]), base,
                     vars_json(keys, values[i])});
  }
  return cases;
}

}  // namespace lathectl::sweep
