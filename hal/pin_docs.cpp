// lathectl_hal_pin_docs — each HAL component's man page PINS section, made from its pin table
// (hal/pins/<component>.hpp), as LinuxCNC's halcompile makes a .comp's: one .TP per group of rows
// (rows with an empty doc share the next row's), `prefix.name type dir [unit]`, the doc wrapped.
//
//   lathectl_hal_pin_docs                       print every component's section
//   lathectl_hal_pin_docs --check DIR [JSON]    exit 1 naming each page in DIR (and the pin list
//                                               JSON) that is stale
//   lathectl_hal_pin_docs --update DIR [JSON]   rewrite them in place
//   lathectl_hal_pin_docs --json                print the pin list
//
// The pin list (hal/pins.json, installed beside lathectl_oplog.py) is every component's pins for
// the userspace programs that read them (lathectl_oplog makes its input pins from it): per
// component its name and prefix, per pin its name, HAL name, type, direction, count, unit and
// the machine object's field it copies ("glue": the component's own code).
//
// A host program: it includes the tables (no HAL headers), not the components.

#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "pins/adaptive.hpp"
#include "pins/chatter.hpp"
#include "pins/gauge.hpp"
#include "pins/gauge_plant.hpp"
#include "pins/meter.hpp"
#include "pins/modfeed.hpp"
#include "pins/plant.hpp"
#include "pins/slide.hpp"
#include "pins/slide_plant.hpp"
#include "pins/vibsensor.hpp"

namespace {

struct Row {
  const char* member;  // nullptr: a heading
  const char* type;
  const char* dir;
  int count;
  const char* unit;
  const char* field;
  const char* doc;  // the heading's text for a heading
};

#define DOC_PIN(m, t, d, n, u, field, doc) Row{#m, #t, #d, n, u, #field, doc},
#define DOC_HEAD(text) Row{nullptr, "", "", 0, "", "", text},
#define DOC_PARAM(m, u, field, doc) Row{#m, "float", "ro", 0, u, #field, doc},

struct Component {
  const char* name;
  std::vector<Row> rows;
  bool meter;                 // its realtime function reports itself (MeterPins), listed last
  std::vector<Row> params{};  // its read-only parameters (a PARAMS table), if any
};

const std::vector<Component>& components() {
  static const std::vector<Component> all = {
      {"lathectl_adaptive",
       {LATHECTL_ADAPTIVE_PINS(DOC_PIN, DOC_HEAD)},
       false,
       {LATHECTL_ADAPTIVE_PARAMS(DOC_PARAM)}},
      {"lathectl_chatter", {LATHECTL_CHATTER_PINS(DOC_PIN, DOC_HEAD)}, true},
      {"lathectl_gauge", {LATHECTL_GAUGE_PINS(DOC_PIN, DOC_HEAD)}, true},
      {"lathectl_gauge_plant", {LATHECTL_GAUGE_PLANT_PINS(DOC_PIN, DOC_HEAD)}, true},
      {"lathectl_modfeed",
       {LATHECTL_MODFEED_PINS(DOC_PIN, DOC_HEAD)},
       false,
       {LATHECTL_MODFEED_PARAMS(DOC_PARAM)}},
      {"lathectl_plant", {LATHECTL_PLANT_PINS(DOC_PIN, DOC_HEAD)}, false},
      {"lathectl_slide", {LATHECTL_SLIDE_PINS(DOC_PIN, DOC_HEAD)}, true},
      {"lathectl_slide_plant", {LATHECTL_SLIDE_PLANT_PINS(DOC_PIN, DOC_HEAD)}, true},
      {"lathectl_vibsensor", {LATHECTL_VIBSENSOR_PINS(DOC_PIN, DOC_HEAD)}, false},
  };
  return all;
}

std::string prefix_of(const Component& c) {
  std::string prefix = c.name;
  for (char& ch : prefix)
    if (ch == '_') ch = '-';
  return prefix;
}

// A component's pins: its table's rows, the meter's last.
std::vector<Row> pin_rows(const Component& c) {
  std::vector<Row> rows = c.rows;
  if (c.meter) rows.insert(rows.end(), {LATHECTL_METER_PINS(DOC_PIN, DOC_HEAD)});
  return rows;
}

// '_' → '-' (the pin's name), troff's minus for '-'.
std::string troff_name(const std::string& s) {
  std::string out;
  for (char c : s) out += (c == '_' || c == '-') ? std::string("\\-") : std::string(1, c);
  return out;
}

std::string tag(const std::string& prefix, const Row& r) {
  std::string t = "\\fB" + troff_name(prefix) + "." + troff_name(r.member);
  if (r.count > 0)
    t += "\\-\\fIi\\fR";
  else
    t += "\\fR";
  t += std::string(" ") + r.type + " " + r.dir;
  if (*r.unit != '\0') t += std::string(" [") + r.unit + "]";
  if (r.count > 0) t += " (\\fIi\\fR = 0 \\(.. " + std::to_string(r.count - 1) + ")";
  return t;
}

// Words filled to 100 columns; a line that would start with '.' or '\'' escaped.
std::string wrap(const std::string& text) {
  std::istringstream in(text);
  std::string word, line, out;
  auto flush = [&] {
    if (line.empty()) return;
    if (line[0] == '.' || line[0] == '\'') line = "\\&" + line;
    out += line + "\n";
    line.clear();
  };
  while (in >> word) {
    if (!line.empty() && line.size() + 1 + word.size() > 100) flush();
    line += (line.empty() ? "" : " ") + word;
  }
  flush();
  return out;
}

// A section of the page: `head` (".SH PINS\n", or PARAMETERS with its first line), the rows.
std::string section(const Component& c, const std::vector<Row>& rows, const std::string& head,
                    std::string& error) {
  const std::string prefix = prefix_of(c);
  std::string out = head;
  bool open = false;  // a group's first tag written, its doc not yet
  for (const Row& r : rows) {
    if (r.member == nullptr) {
      if (open) error += std::string(c.name) + ": a heading after a row without doc\n";
      out += std::string(".SS ") + r.doc + "\n";
      open = false;
      continue;
    }
    out += open ? ".TQ\n" : ".TP\n";
    out += tag(prefix, r) + "\n";
    open = *r.doc == '\0';
    if (!open) out += wrap(r.doc);
  }
  if (open) error += std::string(c.name) + ": the last row has no doc\n";
  return out;
}

std::string quoted(const std::string& s) {  // the tables' names, units and fields: plain ASCII
  std::string out = "\"";
  for (char ch : s) out += (ch == '"' || ch == '\\') ? std::string("\\") + ch : std::string(1, ch);
  return out + "\"";
}

// A list of rows as JSON objects, one a line; `pin` is the HAL name.
std::string rows_json(const std::string& prefix, const std::vector<Row>& rows) {
  std::string out;
  for (const Row& r : rows) {
    if (r.member == nullptr) continue;
    std::string name = r.member;
    for (char& ch : name)
      if (ch == '_') ch = '-';
    out += std::string(out.empty() ? "" : ",\n") + "  {\"name\": " + quoted(name) +
           ", \"pin\": " + quoted(prefix + "." + name) + ", \"type\": " + quoted(r.type) +
           ", \"dir\": " + quoted(r.dir) + ", \"count\": " + std::to_string(r.count) +
           ", \"unit\": " + quoted(r.unit) + ", \"field\": " + quoted(r.field) + "}";
  }
  return out;
}

// The pin list, one pin a line (diffs stay readable); a parameter's dir is "ro".
std::string pin_list() {
  std::string out = "{\"components\": [\n";
  bool first = true;
  for (const Component& c : components()) {
    const std::string prefix = prefix_of(c);
    out += std::string(first ? "" : ",\n") + " {\"name\": " + quoted(c.name) +
           ", \"prefix\": " + quoted(prefix) + ", \"pins\": [\n" + rows_json(prefix, pin_rows(c)) +
           "\n ], \"params\": [" +
           (c.params.empty() ? "" : "\n" + rows_json(prefix, c.params) + "\n ") + "]}";
    first = false;
  }
  return out + "\n]}\n";
}

std::string read(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// The page with its section `title` (`.SH title` to the next `.SH`) replaced; empty if it has
// none.
std::string replaced(const std::string& page, const std::string& title, const std::string& pins) {
  const auto begin = page.find("\n.SH " + title + "\n");
  if (begin == std::string::npos) return {};
  auto end = page.find("\n.SH ", begin + 1);
  end = end == std::string::npos ? page.size() : end + 1;
  return page.substr(0, begin + 1) + pins + page.substr(end);
}

}  // namespace

// A generated file against its committed copy: rewritten (--update) or named (--check).
int compare(const std::string& path, const std::string& now, const std::string& mode,
            const std::string& how) {
  if (now == read(path)) return 0;
  if (mode == "--update") {
    std::ofstream(path) << now;
    std::cout << "updated " << path << "\n";
    return 0;
  }
  std::cerr << path << ": stale (" << how << ")\n";
  return 1;
}

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  const bool files = (argc == 3 || argc == 4) && (mode == "--check" || mode == "--update");
  if (!(argc == 1 || files || (argc == 2 && mode == "--json"))) {
    std::cerr
        << "usage: lathectl_hal_pin_docs [--check DIR [JSON] | --update DIR [JSON] | --json]\n";
    return 2;
  }
  if (mode == "--json") {
    std::cout << pin_list();
    return 0;
  }
  const std::string how = "lathectl_hal_pin_docs --update " + std::string(files ? argv[2] : "") +
                          (argc == 4 ? std::string(" ") + argv[3] : std::string());
  int rc = argc == 4 ? compare(argv[3], pin_list(), mode, how) : 0;
  for (const Component& c : components()) {
    std::string error;
    // The sections the tables make: PINS always, PARAMETERS for a component with a PARAMS table.
    std::vector<std::pair<std::string, std::string>> sections = {
        {"PINS", section(c, pin_rows(c), ".SH PINS\n", error)}};
    if (!c.params.empty())
      sections.emplace_back("PARAMETERS",
                            section(c, c.params,
                                    ".SH PARAMETERS\nRead\\-only: the settings the machine runs "
                                    "with, as its machine parameters derive them (the scenario, "
                                    "the module parameters).\n",
                                    error));
    if (!error.empty()) {
      std::cerr << error;
      rc = 1;
    }
    if (argc == 1) {
      std::cout << ".\\\" " << c.name << "(9)\n";
      for (const auto& [title, text] : sections) std::cout << text;
      continue;
    }
    const std::string path = std::string(argv[2]) + "/" + c.name + ".9";
    std::string now = read(path);
    for (const auto& [title, text] : sections) {
      now = replaced(now, title, text);
      if (now.empty()) {
        std::cerr << path << ": no .SH " << title << " section\n";
        rc = 1;
        break;
      }
    }
    if (!now.empty()) rc |= compare(path, now, mode, how);
  }
  return rc;
}
