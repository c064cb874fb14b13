#include "calculator.hpp"

#include "lathectl/io/errors.hpp"

#include <cstdlib>

namespace lathectl::cli {

std::string format_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

std::string bound_text(const io::Range& r) {
  const bool has_lo = r.lo > -1e299, has_hi = r.hi < 1e299;
  if (has_lo && has_hi)
    return std::string("in ") + (r.lo_open ? "(" : "[") + format_number(r.lo) + ", " +
           format_number(r.hi) + (r.hi_open ? ")" : "]");
  if (has_lo) return (r.lo_open ? "> " : ">= ") + format_number(r.lo);
  if (has_hi) return (r.hi_open ? "< " : "<= ") + format_number(r.hi);
  return "";
}

CLI::Validator range_validator(const io::Range& r) {
  const std::string bound = bound_text(r);
  return CLI::Validator(
      [r, bound](std::string& in) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(in.c_str(), &end);
        if (end != in.c_str() && *end == '\0' && std::isfinite(v) && r.contains(v)) return {};
        return in + ": expected a finite number" + (bound.empty() ? "" : " " + bound);
      },
      bound.empty() ? "finite" : bound);
}

void print_header(const char* title) {
  std::printf("%s\n  %-34s %14s %-10s %14s %s\n", title, "", "SI", "", "shop", "");
}

void print_row(std::string_view label, double si, std::string_view si_unit, double shop,
               std::string_view shop_unit) {
  std::printf("  %-34s %14.6g %-10s %14.6g %s\n", std::string(label).c_str(), si,
              std::string(si_unit).c_str(), shop, std::string(shop_unit).c_str());
}

std::string markdown_table(const std::vector<std::string>& head,
                           const std::vector<std::vector<std::string>>& rows) {
  auto line = [](const std::vector<std::string>& cells) {
    std::string s = "|";
    for (auto c : cells) {
      for (std::size_t p = 0; (p = c.find('|', p)) != std::string::npos; p += 2) c.insert(p, "\\");
      s += " " + c + " |";
    }
    return s + "\n";
  };
  std::string out = line(head) + "|";
  for (std::size_t i = 0; i < head.size(); ++i) out += "---|";
  out += "\n";
  for (const auto& r : rows) out += line(r);
  return out;
}

const cutting::Material& tool_life_material(io::MaterialLibrary& lib, const std::string& name,
                                            const std::string& who) {
  lib = io::MaterialLibrary::load_default();
  const cutting::Material* mat = lib.find(name);
  if (!mat) {
    std::string known;
    for (const auto& nm : lib.names()) known += (known.empty() ? "" : ", ") + nm;
    throw io::InputError(who + "unknown material '" + name + "' (known: " + known + ")");
  }
  if (mat->tool_life_ranges == 0)
    throw io::InputError(who + "material '" + name + "' has no tool-life data");
  return *mat;
}

}  // namespace lathectl::cli
