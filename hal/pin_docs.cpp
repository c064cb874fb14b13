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

struct Component {
  const char* name;
  std::vector<Row> rows;
  bool meter;  // its realtime function reports itself (MeterPins), listed last
};

const std::vector<Component>& components() {
  static const std::vector<Component> all = {
      {"lathectl_adaptive", {LATHECTL_ADAPTIVE_PINS(DOC_PIN, DOC_HEAD)}, false},
      {"lathectl_chatter", {LATHECTL_CHATTER_PINS(DOC_PIN, DOC_HEAD)}, true},
      {"lathectl_gauge", {LATHECTL_GAUGE_PINS(DOC_PIN, DOC_HEAD)}, true},
      {"lathectl_gauge_plant", {LATHECTL_GAUGE_PLANT_PINS(DOC_PIN, DOC_HEAD)}, true},
      {"lathectl_modfeed", {LATHECTL_MODFEED_PINS(DOC_PIN, DOC_HEAD)}, false},
      {"lathectl_plant", {LATHECTL_PLANT_PINS(DOC_PIN, DOC_HEAD)}, false},
      {"lathectl_slide", {LATHECTL_SLIDE_PINS(DOC_PIN, DOC_HEAD)}, true},
      {"lathectl_slide_plant", {LATHECTL_SLIDE_PLANT_PINS(DOC_PIN, DOC_HEAD)}, true},
  };
  return all;
}

std::string prefix_of(const Component& c) {
  std::string prefix = c.name;
  for (char& ch : prefix)
    if (ch == '_') ch = '-';
  return prefix;
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

std::string section(const Component& c, std::string& error) {
  const std::string prefix = prefix_of(c);
  std::vector<Row> rows = c.rows;
  if (c.meter) rows.insert(rows.end(), {LATHECTL_METER_PINS(DOC_PIN, DOC_HEAD)});
  std::string out = ".SH PINS\n";
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

// The pin list, one pin a line (diffs stay readable).
std::string pin_list() {
  std::string out = "{\"components\": [\n";
  bool first_c = true;
  for (const Component& c : components()) {
    const std::string prefix = prefix_of(c);
    out += std::string(first_c ? "" : ",\n") + " {\"name\": " + quoted(c.name) +
           ", \"prefix\": " + quoted(prefix) + ", \"pins\": [\n";
    first_c = false;
    std::vector<Row> rows = c.rows;
    if (c.meter) rows.insert(rows.end(), {LATHECTL_METER_PINS(DOC_PIN, DOC_HEAD)});
    bool first = true;
    for (const Row& r : rows) {
      if (r.member == nullptr) continue;
      std::string name = r.member;
      for (char& ch : name)
        if (ch == '_') ch = '-';
      out += std::string(first ? "" : ",\n") + "  {\"name\": " + quoted(name) +
             ", \"pin\": " + quoted(prefix + "." + name) + ", \"type\": " + quoted(r.type) +
             ", \"dir\": " + quoted(r.dir) + ", \"count\": " + std::to_string(r.count) +
             ", \"unit\": " + quoted(r.unit) + ", \"field\": " + quoted(r.field) + "}";
      first = false;
    }
    out += "\n ]}";
  }
  return out + "\n]}\n";
}

std::string read(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// The page with its PINS section (`.SH PINS` to the next `.SH`) replaced; empty if it has none.
std::string replaced(const std::string& page, const std::string& pins) {
  const auto begin = page.find("\n.SH PINS\n");
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
    const std::string pins = section(c, error);
    if (!error.empty()) {
      std::cerr << error;
      rc = 1;
    }
    if (argc == 1) {
      std::cout << ".\\\" " << c.name << "(9)\n" << pins;
      continue;
    }
    const std::string path = std::string(argv[2]) + "/" + c.name + ".9";
    const std::string now = replaced(read(path), pins);
    if (now.empty()) {
      std::cerr << path << ": no .SH PINS section\n";
      rc = 1;
    } else {
      rc |= compare(path, now, mode, how);
    }
  }
  return rc;
}
