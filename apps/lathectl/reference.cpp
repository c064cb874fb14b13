// `lathectl reference [scenario|design] [NAME]`: the reference tables, generated from the one
// description of each key (the systems' section readers run in describe mode) and of each design
// calculator's inputs and outputs (their tables). `--update DIR` rewrites the generated blocks of
// DIR/*.md, the parts between
//   <!-- BEGIN generated: lathectl reference ARGS -->  and  <!-- END generated -->
// with the output of `lathectl reference ARGS`; `--check DIR` says which are out of date (the
// docs test); `--undocumented` lists the keys that have no line of meaning yet.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "calculator.hpp"
#include "cli.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/scenario.hpp"
#include "systems/registry.hpp"

namespace fs = std::filesystem;

namespace lathectl::cli {
namespace {

std::string table_of(const std::string& key) {
  const auto dot = key.rfind('.');
  return dot == std::string::npos ? "" : key.substr(0, dot);
}

std::string heading(const std::string& table, const io::ParamLog& log) {
  if (table.empty()) return "Top level";
  const bool array = table.size() > 2 && table.ends_with("[]");
  const std::string name = array ? table.substr(0, table.size() - 2) : table;
  std::string h = array ? "`[[" + name + "]]`" : "`[" + name + "]`";
  for (const auto& r : log)
    if (r.key == name && (r.kind == "table" || r.kind == "array of tables"))
      h += r.required ? " (required)" : " (optional)";
  return h;
}

bool is_table(const io::ParamRecord& r) {
  return r.kind == "table" || r.kind == "array of tables";
}

// One Markdown table per TOML table, in the order the reader reads them.
std::string tables_markdown(const io::ParamLog& log, const std::set<std::string>& skip) {
  std::vector<std::string> order;
  std::map<std::string, std::vector<std::vector<std::string>>> rows;
  for (const auto& r : log) {
    if (is_table(r) || skip.count(r.key)) continue;
    const std::string t = table_of(r.key);
    if (!rows.count(t)) order.push_back(t);
    // The unit and default as the key's description gives them (the report's settings too).
    rows[t].push_back({"`" + r.key.substr(t.empty() ? 0 : t.size() + 1) + "`", r.kind, r.unit,
                       r.plausible.empty() ? r.range : r.range + "; usually " + r.plausible,
                       r.required ? "—" : r.fallback,
                       r.rules.empty() ? r.doc : r.doc + " (rule: " + r.rules + ")"});
  }
  std::string out;
  for (const auto& t : order) {
    out += (out.empty() ? "" : "\n") + std::string("### ") + heading(t, log) + "\n\n";
    out += markdown_table({"key", "type", "unit", "range", "default", "meaning"}, rows[t]);
  }
  return out;
}

struct Described {
  const systems::System* system;
  io::ParamLog log;
  std::string error;  // why a system's reader could not run without a scenario file
};

std::vector<Described> describe_all() {
  const auto lib = io::MaterialLibrary::load_default();
  std::vector<Described> out;
  for (const auto& s : systems::all()) {
    try {
      out.push_back({&s, io::describe_section(*s.section, lib), ""});
    } catch (const std::exception& e) {
      out.push_back({&s, {}, e.what()});
    }
  }
  return out;
}

// The keys of the part every scenario has (io/scenario.cpp's read_common): the top level and [run].
bool is_common(const std::string& key) {
  return key.find('.') == std::string::npos || key.starts_with("run.");
}

std::set<std::string> common_keys(const std::vector<Described>& all) {
  std::set<std::string> common;
  for (const auto& d : all)
    for (const auto& r : d.log)
      if (is_common(r.key)) common.insert(r.key);
  return common;
}

// The common part alone: a section that reads nothing more, its `system` row naming them all.
io::ParamLog common_log() {
  constexpr io::Section kNothing{
      "A", [](io::TableReader&, io::Scenario&,
              const io::MaterialLibrary&) -> std::unique_ptr<io::SystemSettings> { return {}; }};
  auto log = io::describe_section(kNothing, io::MaterialLibrary::load_default());
  std::string ids;
  for (const auto& s : systems::all()) ids += (ids.empty() ? "\"" : ", \"") + std::string(s.id) + "\"";
  for (auto& r : log)
    if (r.key == "system") r.range = "one of " + ids;
  return log;
}

std::string scenario_reference(const std::string& name) {
  if (name == "common") return tables_markdown(common_log(), {});
  const auto all = describe_all();
  const auto common = common_keys(all);
  std::string out;
  for (const auto& d : all) {
    if (!name.empty() && d.system->id != name) continue;
    if (name.empty())
      out += "\n## System " + std::string(d.system->id) + ": " + std::string(d.system->title) +
             "\n\n";
    if (!d.error.empty())
      out += "*Not described yet: the section reader fails without a file (" + d.error + ").*\n";
    else
      out += tables_markdown(d.log, common);
  }
  if (out.empty()) {
    std::string known;
    for (const auto& s : systems::all()) known += ", " + std::string(s.id);
    throw io::InputError("reference scenario: no system '" + name + "' (common" + known + ")");
  }
  if (name.empty()) out = "## Common tables\n\n" + tables_markdown(common_log(), {}) + out;
  return out;
}

std::string design_reference(const std::string& name) {
  std::string out, known;
  for (const auto* c : calculators()) {
    known += (known.empty() ? "" : ", ") + std::string(c->name);
    if (!name.empty() && c->name != name) continue;
    if (name.empty())
      out += (out.empty() ? "" : "\n") + std::string("## `lathectl design ") + c->name + "`\n\n" +
             c->description + ".\n\n";
    out += c->reference();
  }
  if (out.empty())
    throw io::InputError("reference design: no calculator '" + name + "' (" + known + ")");
  return out;
}

std::string reference(const std::vector<std::string>& args) {
  const std::string what = args.empty() ? "scenario" : args[0];
  const std::string name = args.size() > 1 ? args[1] : "";
  if (args.size() > 2) throw io::InputError("reference: too many arguments");
  if (what == "scenario") return scenario_reference(name);
  if (what == "design") return design_reference(name);
  throw io::InputError("reference: unknown reference '" + what + "' (scenario, design)");
}

constexpr std::string_view kBegin = "<!-- BEGIN generated: lathectl reference ";
constexpr std::string_view kEnd = "<!-- END generated -->";

// Regenerates every block of `text`; `stale` collects the arguments of the blocks that changed.
std::string regenerate(const std::string& text, const std::string& file,
                       std::vector<std::string>& stale, int& blocks) {
  std::string out;
  std::size_t pos = 0;
  for (std::size_t b; (b = text.find(kBegin, pos)) != std::string::npos;) {
    const std::size_t close = text.find("-->", b + kBegin.size());
    const std::size_t eol = text.find('\n', b);
    const std::size_t e = text.find(kEnd, b);
    if (close == std::string::npos || eol == std::string::npos || e == std::string::npos)
      throw io::InputError(file + ": a generated block without its end marker");
    std::string spec = text.substr(b + kBegin.size(), close - b - kBegin.size());
    while (!spec.empty() && spec.back() == ' ') spec.pop_back();
    std::istringstream words(spec);
    std::vector<std::string> args;
    for (std::string w; words >> w;) args.push_back(w);
    const std::string body = "\n" + reference(args) + "\n";
    if (text.compare(eol + 1, e - eol - 1, body) != 0) stale.push_back(spec);
    out += text.substr(pos, eol + 1 - pos) + body;
    pos = e;
    ++blocks;
  }
  return out + text.substr(pos);
}

int update(const std::string& dir, bool check_only) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw io::InputError(dir + ": not a directory");
  std::vector<fs::path> pages;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".md") pages.push_back(e.path());
  std::sort(pages.begin(), pages.end());
  int blocks = 0, stale_blocks = 0;
  for (const auto& p : pages) {
    std::ifstream in(p, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<std::string> stale;
    const std::string updated = regenerate(text, p.string(), stale, blocks);
    stale_blocks += static_cast<int>(stale.size());
    for (const auto& s : stale)
      std::cout << p.string() << ": generated block 'lathectl reference " << s << "' "
                << (check_only ? "is out of date" : "updated") << "\n";
    if (!check_only && !stale.empty()) std::ofstream(p, std::ios::binary) << updated;
  }
  if (blocks == 0) throw io::InputError(dir + ": no generated blocks in its *.md");
  if (check_only && stale_blocks > 0) {
    std::cout << "run: lathectl reference --update " << dir << "\n";
    return 1;
  }
  std::cout << blocks << " generated blocks " << (check_only ? "up to date" : "in " + dir)
            << "\n";
  return 0;
}

// The keys without a line of meaning, per system (tables have none of their own).
int undocumented(bool strict) {
  int missing = 0;
  for (const auto& d : describe_all()) {
    if (!d.error.empty()) {
      std::cout << "system " << d.system->id << ": not described: " << d.error << "\n";
      ++missing;
      continue;
    }
    std::string keys;
    int n = 0, total = 0;
    for (const auto& r : d.log) {
      if (is_table(r)) continue;
      ++total;
      if (!r.doc.empty()) continue;
      keys += (n++ ? ", " : "") + r.key;
    }
    missing += n;
    std::cout << "system " << d.system->id << ": " << n << " of " << total
              << " keys without a doc" << (n ? ": " + keys : "") << "\n";
  }
  return strict && missing > 0 ? 1 : 0;
}

}  // namespace

void add_reference(CLI::App& app, Commands& out) {
  struct Args {
    std::vector<std::string> what;
    std::string update, check;
    bool undocumented = false, strict = false;
  };
  auto a = std::make_shared<Args>();
  auto* sub = app.add_subcommand(
      "reference",
      "Print the Markdown reference of the scenario keys or the design calculators, generated "
      "from their one description");
  sub->add_option("what", a->what,
                  "scenario [common|SYSTEM] (default) or design [CALCULATOR]")
      ->expected(0, 2);
  auto* up = sub->add_option("--update", a->update,
                             "rewrite the generated blocks of DIR/*.md (<!-- BEGIN generated: "
                             "lathectl reference ARGS --> … <!-- END generated -->)");
  auto* ck = sub->add_option("--check", a->check,
                             "exit 1 naming each generated block of DIR/*.md that is out of date");
  auto* un = sub->add_flag("--undocumented", a->undocumented,
                           "list, per system, the scenario keys without a line of meaning");
  sub->add_flag("--strict", a->strict, "with --undocumented: exit 1 when there is any");
  up->excludes(ck);
  un->excludes(up)->excludes(ck);
  sub->footer("The scenario reference: " + doc("scenario-reference.md") + ".");
  out.push_back({sub, [a] {
                   if (a->undocumented) return undocumented(a->strict);
                   if (!a->update.empty()) return update(a->update, false);
                   if (!a->check.empty()) return update(a->check, true);
                   std::cout << reference(a->what);
                   return 0;
                 }});
}

}  // namespace lathectl::cli
