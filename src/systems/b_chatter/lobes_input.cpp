// The machine file of `lathectl lobes` (lobes.hpp), every key described once here: its range,
// default and meaning drive the reader, its errors and the reference (describe_machine_file).
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <string>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/sections.hpp"
#include "lathectl/io/study.hpp"
#include "lathectl/io/toml_reader.hpp"
#include "systems/b_chatter/lobes.hpp"

namespace lathectl::b_chatter {

namespace {

using io::Param;
using io::Range;
using io::TableReader;

// The chatter frequency f_n·√(1+2ζ) of the highest mode that can chatter (see lobes_needed).
double reference_Hz(const dynamics::ChatterSystem& sys) {
  double lowest = std::numeric_limits<double>::infinity();
  auto limit = [&](const dynamics::Mode& m) {
    const double c2 = std::max(std::cos(m.angle_rad) * std::cos(m.angle_rad), 1e-12);
    return 2.0 * m.stiffness_N_per_m * m.damping_ratio * (1.0 + m.damping_ratio) / c2;
  };
  for (const auto& m : sys.modes) lowest = std::min(lowest, limit(m));
  double f = 0.0;
  for (const auto& m : sys.modes)
    if (limit(m) <= 3.0 * lowest)
      f = std::max(f, m.natural_frequency_Hz * std::sqrt(1.0 + 2.0 * m.damping_ratio));
  return f;
}
double lobes_reference_Hz(const LobesInput& in) {
  double f = reference_Hz(in.system);
  if (in.part)
    for (double x : in.part->positions_m) f = std::max(f, reference_Hz(lobes_system_at(in, x)));
  return f;
}

void read_modes(TableReader& root, LobesInput& in) {
  const auto modes = io::read_modes(root);
  in.tool_modes.insert(in.tool_modes.end(), modes.begin(), modes.end());
}

// [part]: a pinned-pinned Euler–Bernoulli beam; its modes are seen at the cutting position.
void read_part(TableReader& p, LobesInput& in) {
  LobesPart part;
  auto& b = part.beam;
  p.require({"length_mm", {0.0, 1e5, true, false}, "distance between the centres", 1e-3},
            b.length_m);
  p.require({"diameter_mm", {0.0, 1e4, true, false}, "the part's diameter", 1e-3}, b.diameter_m);
  io::read_beam_material(p, b, false);
  p.read({"modes", Range::closed(1, 50), "bending modes (at most 6 in a system-B scenario)"},
         part.modes);
  const Range inside{0.0, b.length_m * 1e3, true, true};  // between the centres
  p.require(
      {"position_mm", inside,
       "where the lobes are computed, from the headstock (left) centre; in (0, length_mm)", 1e-3},
      part.position_m);
  part.positions_m = p.numbers(
      {"positions_mm", inside,
       "the critical depth along the part at these positions, each in (0, length_mm)", 1e-3});
  p.finish();
  in.part = part;
}

// Reads everything but the number of lobes (returned: 0 when the file leaves it to the reader).
int read_tables(TableReader& root, LobesInput& in, std::optional<TableReader>& lobes) {
  auto c = root.table("cutting", true);
  c->require({"kf_N_per_mm2",
              {0.0, 1e6, true, false},
              "K_f, the cutting-force coefficient along the chip thickness",
              1e6},
             in.system.kf_N_per_m2);
  c->finish();
  read_modes(root, in);
  if (auto p = root.table("part")) read_part(*p, in);
  root.check(!(in.tool_modes.empty() && !in.part), "mode",
             "at least one [[mode]] or a [part] expected");
  auto s = root.table("speed", true);
  s->require({"min_rpm", {0.0, 1e6, true, false}, "lowest spindle speed of the lobes"}, in.min_rpm);
  s->require({"max_rpm", {0.0, 1e6, true, false}, "highest spindle speed of the lobes"},
             in.max_rpm);
  s->check(in.max_rpm > in.min_rpm, "max_rpm", "must exceed min_rpm");
  s->finish();
  int max_lobes = 0;
  lobes = root.table("lobes");
  if (auto& l = lobes) {
    l->read({"max_lobes", Range::closed(1, 5000),
             "lobes computed; by default (0) as many as reach min_rpm (at least 40)"},
            max_lobes);
    l->read({"sd_speeds", Range::closed(0, 2000),
             "speeds at which semi-discretization checks the limit by bisection"},
            in.sd_speeds);
    l->read({"chart_speeds", Range::closed(0, 2000), "SD stability chart: speeds (0: no chart)"},
            in.chart_speeds);
    l->read({"chart_depths", Range::closed(0, 2000), "SD stability chart: depths (0: no chart)"},
            in.chart_depths);
    l->check(in.chart_speeds != 1, "chart_speeds", "expected 0 (no chart) or at least 2");
    l->check(in.chart_depths != 1, "chart_depths", "expected 0 (no chart) or at least 2");
    l->read({"chart_max_depth_mm",
             {0.0, 1e4, true, false},
             "top of the chart; by default (0) 4 × the absolute limit",
             1e-3},
            in.chart_max_depth_m);
    l->read({"chart_steps_per_period", Range::closed(2, 100),
             "semi-discretization steps per period of the modes that can chatter"},
            in.chart_steps_per_period);
    l->finish();
  }
  return max_lobes;
}

LobesInput read_lobes_input(const io::TomlDocument& doc) {
  TableReader root(doc.root(), doc.file(), "");
  LobesInput in;
  std::optional<TableReader> lobes;
  const int max_lobes = read_tables(root, in, lobes);
  root.finish();
  in.system = lobes_system_at(in, in.part ? in.part->position_m : 0.0);
  // Never fewer than the former fixed default of 40: existing machine files keep their rows.
  const int needed = std::max(40, lobes_needed(in));
  if (max_lobes > 0 && max_lobes < needed)
    lobes->fail("max_lobes", "must be at least " + std::to_string(needed) +
                                 " for the lobes to reach min_rpm = " + io::fmt(in.min_rpm) +
                                 " (60·f/min_rpm at the chatter frequency; lobes below " +
                                 io::fmt(60.0 * lobes_reference_Hz(in) / max_lobes, "%.0f") +
                                 " rpm would be missing); leave it out for that default");
  in.max_lobes = max_lobes > 0 ? max_lobes : needed;
  return in;
}

}  // namespace

LobesInput load_lobes_input(const std::string& path) {
  return read_lobes_input(io::TomlDocument::parse_file(path));
}

LobesInput parse_lobes_input(std::string_view text, const std::string& file_label) {
  return read_lobes_input(io::TomlDocument::parse(text, file_label));
}

io::ParamLog describe_machine_file() {
  auto log = std::make_shared<io::ParamLog>();
  TableReader root = TableReader::describing("", log);
  LobesInput in;
  std::optional<TableReader> lobes;
  (void)read_tables(root, in, lobes);
  return *log;
}

int lobes_needed(const LobesInput& in) {
  return static_cast<int>(std::ceil(60.0 * lobes_reference_Hz(in) / in.min_rpm)) + 2;
}

dynamics::ChatterSystem lobes_system_at(const LobesInput& in, double x_m) {
  dynamics::ChatterSystem sys;
  sys.kf_N_per_m2 = in.system.kf_N_per_m2;
  if (in.part) sys.modes = dynamics::beam_modes_at(in.part->beam, x_m, in.part->modes);
  sys.modes.insert(sys.modes.end(), in.tool_modes.begin(), in.tool_modes.end());
  return sys;
}

}  // namespace lathectl::b_chatter
