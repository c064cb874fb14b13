// The machine file of `lathectl lobes` (lobes.hpp), every key described once here: its range,
// default and meaning drive the reader, its errors and the reference (describe_machine_file).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/frf_reader.hpp"
#include "lathectl/io/sections.hpp"
#include "lathectl/io/toml_reader.hpp"
#include "systems/b_chatter/lobes_input.hpp"

namespace lathectl::systems::b_chatter {

namespace {

using io::Param;
using io::Range;
using io::TableReader;

// A number for a message (printf format): the reader is in the settings library, without the
// report's formatting (io/study.hpp).
std::string fmt(double v, const char* format = "%.4g") {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
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
  part.support = p.choice("support", {"centres", "chuck", "chuck_tailstock"}, std::string("centres"));
  p.document("support",
             "how the part is held: between centres (pinned–pinned), in a chuck (clamped at the "
             "headstock, free), or in a chuck with the tailstock (clamped–pinned)");
  // Between the centres, and kCentreMargin of the length away from each: closer, mode j is seen
  // 1/sin²(jπx/L) stiffer than mid-span (10⁴ times at 1 %), the centres' own compliance (not
  // modelled) is what the tool feels, and at the centre itself no mode is seen at all.
  const double length_mm = b.length_m * 1e3;
  const Range inside =
      Range::closed(kCentreMargin * length_mm, (1.0 - kCentreMargin) * length_mm);
  p.require({"position_mm", inside,
             "where the lobes are computed, from the headstock (left) centre; at least 1 % of "
             "length_mm from either centre",
             1e-3},
            part.position_m);
  p.read({"steady_rest_mm", Range::closed(0.0, 1e5),
          "a steady rest at this distance from the headstock (holds the axis, not its slope); "
          "by default (0) none",
          1e-3},
         part.supports.steady_rest_m);
  p.check(!(part.supports.steady_rest_m > b.length_m), "steady_rest_mm",
          "the steady rest must lie on the part (at most length_mm)");
  part.supports.headstock =
      part.support == "centres" ? dynamics::BeamEnd::pinned : dynamics::BeamEnd::clamped;
  part.supports.tailstock =
      part.support == "chuck" ? dynamics::BeamEnd::free : dynamics::BeamEnd::pinned;
  part.positions_m = p.numbers(
      {"positions_mm", inside,
       "the critical depth along the part at these positions, each at least 1 % of length_mm "
       "from either centre",
       1e-3});
  p.check(part.positions_m.size() <= kMaxPositions, "positions_mm",
          "at most " + std::to_string(kMaxPositions) + " positions (each costs a set of lobes)");
  // The part's highest mode within the [[mode]] bound on frequencies (a part of a few µm, or a
  // thick stub, would put it at 10¹⁵ Hz and the lobes' count with it).
  if (!p.is_describing()) {
    const double f_top = dynamics::beam_mode_at(b, 0.5 * b.length_m, part.modes)
                             .mode.natural_frequency_Hz;
    p.check(std::isfinite(f_top) && f_top <= kMaxModeHz, "length_mm",
            "the part's mode " + std::to_string(part.modes) + " lies at " + fmt(f_top) +
                " Hz, above " + fmt(kMaxModeHz) +
                " Hz (the [[mode]] bound): a longer or thinner part, or fewer modes");
  }
  p.finish();
  if (!p.is_describing() && (part.support != "centres" || part.supports.steady_rest_m > 0.0))
    part.model = std::make_shared<const dynamics::BeamModel>(
        dynamics::beam_model(part.beam, part.supports, part.modes));
  in.part = part;
}

// [[frf]]: measured FRFs, each file relative to the machine file's folder, oriented to the chip
// thickness at chip_direction (α from x towards y): x·cos²α + y·sin²α + (xy + yx)·cosα·sinα,
// a cross term without its reciprocal counted twice (reciprocity, H_xy = H_yx).
void read_frfs(TableReader& root, LobesInput& in, const std::filesystem::path& base) {
  root.document("frf",
                "measured FRFs (tap tests), beside or instead of [[mode]]: CSV or universal file "
                "format 58/58b (docs/machine-file-reference.md)");
  auto tables = root.tables("frf");
  for (auto& t : tables) {
    LobesFrf f;
    t.document("file", "the FRF file, CSV or UFF 58; a relative path is relative to the machine file");
    const std::string file = t.string("file", t.is_describing() ? std::optional<std::string>("")
                                                                  : std::nullopt);
    f.direction = t.choice("direction", {"x", "y", "xy", "yx"}, std::string("x"));
    t.document("direction",
               "the response/excitation directions: x, y, or a cross term xy, yx; oriented by "
               "[cutting] chip_direction_deg");
    f.of = t.choice("of", {"tool", "part"}, std::string("tool"));
    t.document("of", "what was tapped (both add: the relative tool–part receptance)");
    t.finish();
    if (t.is_describing()) continue;
    const std::filesystem::path p(file);
    f.file = file;
    f.path = (p.is_absolute() ? p : base / p).lexically_normal().string();
    try {
      f.frf = io::read_frf_file(f.path, &f.notes);
    } catch (const io::InputError& e) {
      t.fail("file", e.what());
    }
    in.frfs.push_back(std::move(f));
  }
  const double c = std::cos(in.chip_direction_rad), s = std::sin(in.chip_direction_rad);
  for (auto& f : in.frfs) {
    if (f.direction == "x") f.weight = c * c;
    else if (f.direction == "y") f.weight = s * s;
    else {
      const std::string other = f.direction == "xy" ? "yx" : "xy";
      const bool pair = std::any_of(in.frfs.begin(), in.frfs.end(), [&](const LobesFrf& g) {
        return g.of == f.of && g.direction == other;
      });
      f.weight = (pair ? 1.0 : 2.0) * c * s;
    }
  }
}

// [cutting]: K_f, and the cut the recommendation assumes.
void read_cutting(TableReader& root, LobesInput& in) {
  auto c = root.table("cutting", true);
  c->require({"kf_N_per_mm2",
              Range::closed(1.0, 1e6),
              "K_f, the cutting-force coefficient along the chip thickness (1 N/mm² and up: "
              "below, the limit depths overflow)",
              1e6},
             in.system.kf_N_per_m2);
  auto& r = in.recommend;
  c->read({"feed_mm_per_rev", Range::closed(1e-4, 10.0),
           "the feed, i.e. the chip thickness h, for the recommendation's power, torque and "
           "removal rate",
           1e-3},
          r.feed_m);
  c->read({"kc_N_per_mm2", Range::closed(0.0, 1e6),
           "k_c, the tangential cutting-force coefficient F_c = k_c·b·h for the spindle's power "
           "and torque; by default (0) K_f",
           1e6},
          r.kc_N_per_m2);
  c->read({"diameter_mm", Range::closed(0.0, 1e4),
           "the part's diameter at the cut (cutting speed, torque); by default (0) the [part]'s, "
           "else 50 mm",
           1e-3},
          r.diameter_m);
  c->read({"chip_direction_deg", Range::closed(-180.0, 180.0),
           "the chip-thickness direction, from the [[frf]]s' x towards their y", 0.0174532925199432958},
          in.chip_direction_rad);
  c->finish();
}

// [process_damping]: the flank's indentation as damping (dynamics/lobes.hpp,
// ChatterSystem::process_damping_C): C = 60·K_sp·VB²/(4π·D·sin κ), D the cutting diameter of the
// recommendation.
void read_process_damping(TableReader& root, LobesInput& in) {
  if (auto pd = root.table("process_damping")) {
    pd->read({"k_sp_N_per_mm3", Range::closed(0.0, 1e9),
              "K_sp, the specific indentation force of the flank (carbon steels: about 4e4 "
              "N/mm³, Chiou & Liang 1998)",
              1e9},
             in.process_damping_k_sp_N_per_m3);
    pd->read({"wear_land_mm", Range::closed(0.0, 5.0),
              "VB, the flank's wear land that ploughs the surface (0: no process damping)", 1e-3},
             in.process_damping_vb_m);
    pd->read({"approach_angle_deg", Range::closed(1.0, 179.0),
              "κ, the edge's approach angle: the engaged edge is b/sin κ", 0.0174532925199432958},
             in.process_damping_kappa_rad);
    pd->finish();
    in.process_damping_C = 60.0 * in.process_damping_k_sp_N_per_m3 * in.process_damping_vb_m *
                           in.process_damping_vb_m /
                           (4.0 * std::numbers::pi * recommend_diameter_m(in) *
                            std::sin(in.process_damping_kappa_rad));
  }
}

// [speed], and what the recommendation needs of [machine] and [recommend].
void read_speed_and_limits(TableReader& root, LobesInput& in) {
  auto s = root.table("speed", true);
  s->require({"min_rpm", {0.0, 1e6, true, false}, "lowest spindle speed of the lobes"}, in.min_rpm);
  s->require({"max_rpm", {0.0, 1e6, true, false}, "highest spindle speed of the lobes"},
             in.max_rpm);
  s->check(in.max_rpm > in.min_rpm, "max_rpm", "must exceed min_rpm");
  s->finish();
  if (auto mt = root.table("machine")) {
    mt->read({"power_kW", Range::closed(0.0, 1e5),
              "the spindle's power available at the cut; by default (0) no limit",
              1e3},
             in.recommend.power_W);
    mt->read({"torque_Nm", Range::closed(0.0, 1e6),
              "the spindle's torque available at the cut; by default (0) no limit"},
             in.recommend.torque_Nm);
    mt->finish();
  }
  if (auto rt = root.table("recommend")) {
    rt->read({"safety_factor", Range::closed(1.0, 10.0),
              "the recommended depth is the stability limit divided by this"},
             in.recommend.safety_factor);
    rt->read({"pockets", Range::closed(1, 50), "the best pockets listed"}, in.recommend.pockets);
    rt->finish();
  }
}

// [lobes]: the number of lobes (0: left to the reader), semi-discretization and its chart.
int read_lobes(std::optional<TableReader>& lobes, LobesInput& in) {
  int max_lobes = 0;
  if (auto& l = lobes) {
    l->read({"max_lobes", Range::closed(1, kMaxLobes),
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

// Reads everything but the number of lobes (returned: 0 when the file leaves it to the reader).
int read_tables(TableReader& root, LobesInput& in, std::optional<TableReader>& lobes,
                const std::filesystem::path& base) {
  read_cutting(root, in);
  read_modes(root, in);
  read_frfs(root, in, base);
  if (auto p = root.table("part")) read_part(*p, in);
  read_process_damping(root, in);
  root.check(!(in.tool_modes.empty() && !in.part && in.frfs.empty()), "mode",
             "at least one [[mode]], [[frf]] or a [part] expected");
  read_speed_and_limits(root, in);
  lobes = root.table("lobes");
  return read_lobes(lobes, in);
}

// The SDOF limit 2kζ(1+ζ)/(K_f·cos²θ) of a mode [m] (cos²θ kept ≥ 1e-12 as in reference_Hz).
double sdof_limit_m(const dynamics::Mode& m, double kf) {
  const double c2 = std::max(std::cos(m.angle_rad) * std::cos(m.angle_rad), 1e-12);
  return 2.0 * m.stiffness_N_per_m * m.damping_ratio * (1.0 + m.damping_ratio) / (kf * c2);
}

// Every mode the lobes will see (the tool's, and the part's at each position) has an SDOF limit
// of at least kMinLimitDepth_m: below it the depths underflow towards denormals, where the
// bisections stop converging (a stiffness of 1e-300 N/m hung the chart).
void check_limits(TableReader& root, std::optional<TableReader>& part_table, const LobesInput& in) {
  const double kf = in.system.kf_N_per_m2;
  auto tables = root.tables("mode");
  for (std::size_t i = 0; i < in.tool_modes.size() && i < tables.size(); ++i) {
    const double b = sdof_limit_m(in.tool_modes[i], kf);
    if (!(b >= kMinLimitDepth_m))
      tables[i].fail("stiffness_N_per_m",
                     "this mode's limit depth 2kζ(1+ζ)/(K_f·cos²θ) = " + fmt(b) +
                         " m is below " + fmt(kMinLimitDepth_m) +
                         " m: no lathe's mode is that soft for this K_f ([cutting] kf_N_per_mm2)");
  }
  if (!in.part) return;
  std::vector<double> xs{in.part->position_m};
  xs.insert(xs.end(), in.part->positions_m.begin(), in.part->positions_m.end());
  for (std::size_t k = 0; k < xs.size(); ++k) {
    const auto modes = part_modes_at(*in.part, xs[k]);
    double b = std::numeric_limits<double>::infinity();
    for (const auto& m : modes) b = std::min(b, sdof_limit_m(m, kf));
    if (!(b >= kMinLimitDepth_m))
      part_table->fail(
          k == 0 ? "position_mm" : "positions_mm",
          "at " + fmt(xs[k] * 1e3) + " mm the part's softest mode has a limit depth of " +
              fmt(b) + " m, below " + fmt(kMinLimitDepth_m) +
              " m: the part (diameter_mm, length_mm, youngs_modulus_GPa) is too slender for any "
              "cut, or K_f ([cutting] kf_N_per_mm2) too large");
  }
}

// The modes fitted to the [[frf]]s under the bounds of a typed [[mode]] (io::read_modes: f_n up
// to kMaxModeHz, k up to 1e13 N/m, 0 < ζ < 1) and its limit depth (check_limits): a peak at
// 1.5 GHz or of 1e100 m/N is the file's, named at frf[0].file with every file of the sum.
void check_fitted_modes(TableReader& root, const LobesInput& in) {
  if (!in.measured) return;
  std::string files;
  for (const auto& f : in.frfs) files += (files.empty() ? "" : ", ") + f.path;
  const double kf = in.system.kf_N_per_m2;
  for (const auto& m : in.measured->fit.modes) {
    std::string why;
    if (!(m.natural_frequency_Hz > 0.0 && m.natural_frequency_Hz <= kMaxModeHz))
      why = "a natural frequency of " + fmt(m.natural_frequency_Hz) + " Hz, above the " +
            fmt(kMaxModeHz) + " Hz a [[mode]] may have";
    else if (!(m.stiffness_N_per_m > 0.0 && m.stiffness_N_per_m < 1e13))
      why = "a stiffness of " + fmt(m.stiffness_N_per_m) +
            " N/m, outside the (0, 1e13) N/m a [[mode]] may have";
    else if (!(m.damping_ratio > 0.0 && m.damping_ratio < 1.0))
      why = "a damping ratio of " + fmt(m.damping_ratio) + ", outside (0, 1)";
    else if (const double b = sdof_limit_m(m, kf); !(b >= kMinLimitDepth_m))
      why = "a limit depth 2kζ(1+ζ)/K_f of " + fmt(b) + " m (k = " + fmt(m.stiffness_N_per_m) +
            " N/m, a peak of about " + fmt(1.0 / (2.0 * m.stiffness_N_per_m * m.damping_ratio)) +
            " m/N), below " + fmt(kMinLimitDepth_m) + " m: no lathe's mode is that soft";
    if (!why.empty())
      root.tables("frf").front().fail(
          "file", "the mode fitted to the measured FRF (" + files + ") at " +
                      fmt(m.natural_frequency_Hz) + " Hz has " + why +
                      ": check the file's frequency column (Hz) and units (m/N)");
  }
}

std::string gigabytes(double bytes) { return fmt(bytes / 1e9, "%.2g") + " GB"; }
std::string duration(double s) {
  return s < 120.0 ? fmt(s, "%.0f") + " s"
         : s < 7200.0 ? fmt(s / 60.0, "%.0f") + " min"
                      : fmt(s / 3600.0, "%.1f") + " h";
}

// The work, estimated before anything is allocated (lobes_cost), within kMaxBytes and
// kMaxSeconds; over either, the error names the keys that would bring it down.
void check_cost(TableReader& root, std::optional<TableReader>& lobes, const LobesInput& in) {
  const LobesCost c = lobes_cost(in);
  auto speed = root.table("speed", true);
  if (c.bytes > kMaxBytes && c.sd_bytes > c.fd_bytes) {
    root.fail("mode", std::to_string(in.system.modes.size()) +
                          " modes at the tool would need about " + gigabytes(c.bytes) +
                          " of memory for the semi-discretization's matrices, over the " +
                          gigabytes(kMaxBytes) + " bound: fewer [[mode]]s or [part] modes");
  }
  if (c.bytes > kMaxBytes) {
    speed->fail("min_rpm",
                "the frequency-domain lobes from min_rpm = " + fmt(in.min_rpm) +
                    " to max_rpm = " + fmt(in.max_rpm) + " rpm (" +
                    std::to_string(in.max_lobes) + " lobes) would hold " +
                    fmt(c.fd_points, "%.3g") + " points, about " + gigabytes(c.bytes) +
                    " of memory, over the " + gigabytes(kMaxBytes) +
                    " bound: narrow the speed range (raise min_rpm, lower max_rpm)");
  }
  if (c.seconds > kMaxSeconds) {
    const std::string what = "about " + duration(c.seconds) + " on " +
                             std::to_string(c.threads) + " threads, over the " +
                             duration(kMaxSeconds) + " bound";
    const double chart_s = c.cell_seconds / c.threads *
                           (c.chart_cells > 0 ? c.chart_cells / (c.chart_cells + c.sd_cells) : 0);
    if (lobes && chart_s > 0.5 * c.seconds)
      lobes->fail(lobes->has("chart_speeds") ? "chart_speeds" : "chart_depths",
                  "the SD chart of " + std::to_string(in.chart_speeds) + " × " +
                      std::to_string(in.chart_depths) + " cells, up to " +
                      std::to_string(c.max_steps) + " steps per revolution, would take " + what +
                      ": ask for a coarser chart (chart_speeds, chart_depths), fewer "
                      "chart_steps_per_period, or a higher [speed] min_rpm");
    if (lobes && c.sd_cells > 0 && c.fd_seconds < 0.5 * c.seconds)
      lobes->fail("sd_speeds", "the semi-discretization limits at " +
                                   std::to_string(in.sd_speeds) + " speeds and the chart, up to " +
                                   std::to_string(c.max_steps) +
                                   " steps per revolution, would take " + what +
                                   ": fewer sd_speeds, a coarser chart, or a higher [speed] "
                                   "min_rpm");
    speed->fail("min_rpm", "the lobes (" + std::to_string(in.max_lobes) + " lobes, " +
                               fmt(c.fd_point_visits, "%.3g") +
                               " points over every position; semi-discretization up to " +
                               std::to_string(c.max_steps) +
                               " steps per revolution) would take " + what +
                               ": raise min_rpm, or set a smaller [lobes] chart and sd_speeds");
  }
}

LobesInput read_lobes_input(const io::TomlDocument& doc) {
  TableReader root(doc.root(), doc.file(), "");
  LobesInput in;
  std::optional<TableReader> lobes;
  const int max_lobes =
      read_tables(root, in, lobes, std::filesystem::path(doc.file()).parent_path());
  root.finish();
  try {
    measure_frfs(in);
  } catch (const std::invalid_argument& e) {
    root.tables("frf").front().fail("file", std::string("the measured FRF: ") + e.what());
  }
  check_fitted_modes(root, in);
  in.modal = lobes_modal_system_at(in, in.part ? in.part->position_m : 0.0);
  {
    auto part_table = root.table("part");
    check_limits(root, part_table, in);
  }
  in.system = lobes_system_at(in, in.part ? in.part->position_m : 0.0);
  // The lobes down to min_rpm, counted before they are allocated (as a double: a part of a few
  // µm once made this an int overflow and a resize of billions of lobes).
  const double needed_lobes = lobes_needed_count(in);
  if (!(needed_lobes <= kMaxLobes)) {
    auto speed = root.table("speed", true);
    speed->fail("min_rpm", "the lobes down to min_rpm = " + fmt(in.min_rpm) + " rpm number " +
                               fmt(needed_lobes, "%.0f") + " (60·f_c/min_rpm at the chatter "
                               "frequency f_c = " + fmt(lobes_reference_Hz(in)) +
                               " Hz), over " + std::to_string(kMaxLobes) +
                               ": raise min_rpm to at least " +
                               fmt(60.0 * lobes_reference_Hz(in) / (kMaxLobes - 2), "%.0f"));
  }
  // Never fewer than the former fixed default of 40: existing machine files keep their rows.
  const int needed = std::max(40, lobes_needed(in));
  if (max_lobes > 0 && max_lobes < needed)
    lobes->fail("max_lobes", "must be at least " + std::to_string(needed) +
                                 " for the lobes to reach min_rpm = " + fmt(in.min_rpm) +
                                 " (60·f/min_rpm at the chatter frequency; lobes below " +
                                 fmt(60.0 * lobes_reference_Hz(in) / max_lobes, "%.0f") +
                                 " rpm would be missing); leave it out for that default");
  in.max_lobes = max_lobes > 0 ? max_lobes : needed;
  if (in.process_damping_C > 0.0) {  // semi-discretization has no process damping
    in.sd_speeds = 0;
    in.chart_speeds = in.chart_depths = 0;
  }
  check_cost(root, lobes, in);
  return in;
}

}  // namespace

LobesInput load_lobes_input(const std::string& path) {
  return read_lobes_input(io::TomlDocument::parse_file(path));
}

LobesInput parse_lobes_input(std::string_view text, const std::string& file_label) {
  return read_lobes_input(io::TomlDocument::parse(text, file_label));
}

std::vector<dynamics::Mode> read_structure_file(TableReader& t, std::string_view key,
                                                std::size_t max_modes) {
  const std::string file = t.string(key);
  if (t.is_describing()) return {};
  const std::filesystem::path p(file);
  const std::string path =
      (p.is_absolute() ? p : std::filesystem::path(t.file()).parent_path() / p)
          .lexically_normal()
          .string();
  LobesInput in;
  try {
    in = load_lobes_input(path);
  } catch (const io::InputError& e) {
    t.fail(key, std::string("the machine file: ") + e.what());
  }
  t.check(!in.part, key,
          "the machine file " + path +
              " describes a [part]; here the part is the scenario's own: the machine file gives "
              "the tool's side only ([[mode]], [[frf]])");
  auto modes = structure_modes(in);
  t.check(modes.size() <= max_modes, key,
          "the machine file " + path + " gives " + std::to_string(modes.size()) +
              " modes (its [[mode]]s and the modes fitted to its [[frf]]s), over the " +
              std::to_string(max_modes) + " this model takes");
  return modes;
}

io::ParamLog describe_machine_file() {
  auto log = std::make_shared<io::ParamLog>();
  TableReader root = TableReader::describing("", log);
  LobesInput in;
  std::optional<TableReader> lobes;
  (void)read_tables(root, in, lobes, {});
  return *log;
}

}  // namespace lathectl::systems::b_chatter
