#include "systems/e_adaptive/settings.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <sstream>

#include "lathectl/cutting/stock.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/sections.hpp"
#include "lathectl/io/toml_reader.hpp"
#include "systems/e_adaptive/settings_sections.hpp"

namespace lathectl::systems::e_adaptive {

const std::vector<std::string> kModes{"fixed", "force_feed", "force_speed"};

Mode mode_from(const std::string& s) {
  return s == "fixed" ? Mode::Fixed : s == "force_feed" ? Mode::ForceFeed : Mode::ForceFeedSpeed;
}

// A number as a user wrote it (shortest form, no trailing zeros).
std::string fmt_number(double v) {
  std::ostringstream ss;
  ss << v;
  return ss.str();
}

namespace {

using io::Param;
using io::Range;
using io::TableReader;

// Points {at_mm, <value key>} along z, at_mm strictly increasing.
void read_profile(TableReader& t, std::string_view key, std::string_view value_key,
                  Range value_range, std::string_view value_doc,
                  std::vector<cutting::ProfilePoint>& out) {
  for (auto& p : t.tables(key)) {
    cutting::ProfilePoint pt;
    p.require({"at_mm", Range::any(), "position along z"}, pt.at_mm);
    p.require({value_key, value_range, value_doc}, pt.value);
    p.finish();
    out.push_back(pt);
  }
  for (std::size_t i = 1; i < out.size(); ++i)
    t.check(out[i].at_mm > out[i - 1].at_mm, key, "at_mm must increase from point to point");
}

// A pass that meets no material anywhere on its way (its diameter at or above the surface the
// earlier passes left, eccentricity included) is a mistake a shop would not make on purpose.
void warn_pass_in_air(const TableReader& p, const RigConfig& e, std::size_t k) {
  if (p.is_describing() || e.stock.blank_diameter_mm.empty()) return;
  cutting::Stock stock;
  try {
    stock.configure(e.stock);
  } catch (const std::exception&) {
    return;  // the rig's validation reports it
  }
  const auto& q = e.stock.passes[k];
  constexpr int kSamples = 256;
  double highest = 0.0;
  for (int i = 0; i <= kSamples; ++i) {
    const double z = q.z_start_mm + (q.z_end_mm - q.z_start_mm) * i / kSamples;
    const double d = stock.surface_diameter_mm(k, z) +
                     (stock.blank_surface(k, z) ? 2.0 * e.stock.eccentricity_mm : 0.0);
    highest = std::max(highest, d);
  }
  if (q.diameter_mm >= highest)
    p.warn("diameter_mm", "the pass cuts nothing: " + fmt_number(q.diameter_mm) +
                              " mm is at or above the largest diameter in front of it on z = [" +
                              fmt_number(q.z_start_mm) + ", " + fmt_number(q.z_end_mm) + "] mm (" +
                              fmt_number(highest) + " mm): it runs entirely in air");
}

void read_stock(TableReader& root, RigConfig& e, std::uint64_t seed) {
  auto st = root.table("stock", true);
  read_profile(*st, "blank", "diameter_mm", {0.0, 5000.0, true, false},
               "blank diameter there; piecewise linear between points", e.stock.blank_diameter_mm);
  st->check(!e.stock.blank_diameter_mm.empty(), "blank", "at least one {at_mm, diameter_mm} point");
  // The stock model of LinuxCNC's plant and of optimize keeps the blank on a 0.01 mm grid (it
  // refuses more than 5e7 cells): a blank longer than any lathe's bed would end there as an
  // internal error after the run had begun.
  st->check(e.stock.blank_diameter_mm.empty() ||
                e.stock.blank_diameter_mm.back().at_mm - e.stock.blank_diameter_mm.front().at_mm <=
                    20000.0,
            "blank", "at most 20 000 mm (20 m) from the first point's at_mm to the last's");
  st->read({"eccentricity_mm", Range::closed(0, 50),
            "offset of the blank's axis (runout on the blank surface only)"},
           e.stock.eccentricity_mm);
  for (auto& p : st->tables("passes")) {
    cutting::Pass k;
    p.require({"z_start_mm", Range::any(), "where the pass starts cutting (it moves toward +z)"},
              k.z_start_mm);
    p.require({"z_end_mm", Range::any(), "where the pass ends"}, k.z_end_mm);
    p.require({"diameter_mm", {0.0, 5000.0, true, false}, "diameter the pass cuts down to"},
              k.diameter_mm);
    p.check(k.z_end_mm > k.z_start_mm, "z_end_mm", "must exceed z_start_mm");
    p.finish();
    e.stock.passes.push_back(k);
    warn_pass_in_air(p, e, e.stock.passes.size() - 1);
  }
  // No passes: the scenario describes the blank alone. `lathectl optimize` and the LinuxCNC
  // components take the tool's path from the NC program and never read the passes; only
  // `lathectl run`, whose rig cuts them, needs them (it says so, run()).
  read_profile(*st, "hardness", "factor", {0.0, 10.0, true, false},
               "strength factor of the material there (1 = nominal)", e.disturbances.hardness);
  st->read({"random_depth_sigma_mm", Range::closed(0, 10), "σ of the random allowance"},
           e.disturbances.random_sigma_mm);
  st->read({"random_depth_correlation_mm", Range::positive(),
            "correlation length of the random allowance along z"},
           e.disturbances.random_correlation_mm);
  e.disturbances.seed = seed;
  st->read({"approach_mm", Range::closed(0, 1000), "air travel before each pass"}, e.approach_mm);
  st->finish();
}

void read_feed_axis(TableReader& root, RigConfig& e) {
  auto ax = root.table("feed_axis", true);
  ax->read({"time_constant_ms", {0.0, 1000.0, true, false}, "velocity-loop lag of drive 1", kMs},
           e.axis.time_constant_s);
  ax->read({"rapid_mm_per_min", {0.0, 1e6, true, false},
            "rapid traverse between passes, also the axis's top speed", 1.0 / 60000.0},
           e.rapid_m_per_s);
  e.axis.max_velocity_m_per_s = e.rapid_m_per_s;
  ax->read({"max_acceleration_m_per_s2", {0.0, 1000.0, true, false}, "axis acceleration limit"},
           e.axis.max_acceleration_m_per_s2);
  ax->read({"encoder_resolution_um", {0.0, 1000.0, true, false},
            "resolution of the position encoder (sensor 12)", 1e-6},
           e.axis.encoder_resolution_m);
  ax->read({"velocity_window_ms", {0.0, 10000.0, true, false},
            "window of the measured feed rate (sensor 12)", kMs},
           e.axis.velocity_window_s);
  ax->finish();
}

void read_sensor(TableReader& root, RigConfig& e, std::uint64_t seed) {
  auto se = root.table("sensor", true);
  const std::string param =
      se->pick({"parameter", {},
                "the force parameter sensor 4 measures; \"power\" = spindle electrical power "
                "minus its idle power"},
               {"Pz", "Py", "power"});
  e.force_parameter = param == "Pz"   ? cutting::ForceParameter::Pz
                      : param == "Py" ? cutting::ForceParameter::Py
                                      : cutting::ForceParameter::Power;
  const bool power = e.force_parameter == cutting::ForceParameter::Power;
  se->read({"time_constant_ms", Range::closed(0, 1e4), "lag of sensor 4", kMs},
           e.force_sensor.time_constant_s);
  // The unit is in the key: N for a dynamometer, W for the power sensor (both described).
  const Param noise_N{"noise_N", Range::closed(0, 1e6), "noise σ of a Pz/Py dynamometer"};
  const Param noise_W{"noise_W", Range::closed(0, 1e6), "noise σ of the power sensor"};
  const Param range_N{"range_N", {0.0, 1e9, true, false}, "saturation of a Pz/Py dynamometer"};
  const Param range_W{"range_W", {0.0, 1e9, true, false}, "saturation of the power sensor"};
  if (!power || se->is_describing()) {
    se->read(noise_N, e.force_sensor.noise_sigma);
    se->read(range_N, e.force_sensor.range);
  }
  if (power || se->is_describing()) {
    se->read(noise_W, e.force_sensor.noise_sigma);
    se->read(range_W, e.force_sensor.range);
  }
  e.force_sensor.seed = seed ^ 0x51ED2701ULL;
  se->read({"power_meter_time_constant_ms", Range::closed(0, 1e4),
            "lag of the spindle's power meter", kMs},
           e.power_meter.time_constant_s);
  se->read({"power_meter_noise_W", Range::closed(0, 1e6), "noise σ of the spindle's power meter"},
           e.power_meter.noise_sigma);
  e.power_meter.seed = seed ^ 0xB0B0B0B0ULL;
  se->finish();
}

}  // namespace

// read_controller() and its phases are in controller_settings.cpp.

namespace {

// [chatter]: the tool's modes and the part between centres (lathectl optimize's chatter margin).
// The mode and beam-material keys are the machine file's (io::read_modes, read_beam_material).
void read_chatter(TableReader& c, Chatter& ch) {
  c.document("mode", "the tool's (and machine's) vibration modes, as in a machine file");
  ch.tool_modes = io::read_modes(c);
  if (c.has("machine_file") || c.is_describing()) {
    const std::string file = c.string("machine_file", std::string());
    c.document("machine_file",
               "a machine file of `lathectl lobes` (relative to this scenario): its [[mode]]s and "
               "the modes fitted to its [[frf]]s are the tool's, beside any [[chatter.mode]] (its "
               "[part] is not used: [chatter.part] is the part)");
    if (!c.is_describing()) {
      const std::filesystem::path p(file);
      const auto path = p.is_absolute() ? p : std::filesystem::path(c.file()).parent_path() / p;
      c.check(!file.empty() && std::filesystem::is_regular_file(path), "machine_file",
              "no machine file at " + path.lexically_normal().string());
      ch.machine_file = path.lexically_normal().string();
      ch.machine_file_at_key =
          io::located(c.file(), c.line(), 0, "key '" + c.full_key("machine_file") + "'");
    }
  }
  c.document("part", "the part between centres; without it the part is rigid");
  if (auto p = c.table("part")) {
    ch.part = true;
    p->read({"tailstock_at_mm", Range::any(),
             "stock z of the tailstock centre (z = 0 is the part's face, z grows toward the "
             "chuck)"},
            ch.tailstock_at_mm);
    p->require({"headstock_at_mm", Range::any(),
                "stock z of the headstock centre; the part is a pinned-pinned beam between the "
                "two centres, of the diameter the stock has at the tool (system B's model)"},
               ch.headstock_at_mm);
    p->check(ch.headstock_at_mm > ch.tailstock_at_mm, "headstock_at_mm",
             "must exceed tailstock_at_mm");
    io::read_beam_material(*p, ch.beam, true);
    p->read({"modes", Range::closed(1, 50), "bending modes of the part"}, ch.part_modes);
    p->finish();
    ch.beam.length_m = (ch.headstock_at_mm - ch.tailstock_at_mm) * 1e-3;
  }
  c.check(ch.enabled(), "mode",
          "at least one [[chatter.mode]], a machine_file or a [chatter.part] expected");
  c.finish();
}

}  // namespace

const std::array<io::CriterionKey, 3> kAcceptanceKeys{{
    {"max_force_over_limit_pct", "largest per-revolution force (or power) above its limit", false,
     10.0, Range::closed(0, 1000),
     "largest per-revolution mean of the controlled parameter (Pz, Py or cutting power) above "
     "controller's limit in steady cutting, % (default 10: a per-revolution regulator overshoots "
     "a depth step by a few %; a part never cut has no value and fails it)"},
    {"max_cycle_time_s", "cycle time", false, 0.0, Range::closed(0, 1e6),
     "longest cycle time, approach and every pass (0: not judged, the default)"},
    {"max_tool_life_used_pct", "share of a cutting edge's life used (∫dt/T)", false, 0.0,
     Range::closed(0, 1e4),
     "largest share of an edge's tool life the part may use (0: not judged, "
     "the default)"},
}};

std::unique_ptr<io::SystemSettings> read_settings(TableReader& root, io::Scenario& sc,
                                                  const io::MaterialLibrary& lib) {
  auto out = std::make_unique<Settings>();
  auto& e = out->rig;
  double angles[2] = {e.tool_front_angle_deg, e.tool_back_angle_deg};
  io::read_material_tool(root, lib, e.cutting, &e.disturbances, false, &e.tool_orientation,
                         angles);
  e.tool_front_angle_deg = angles[0];
  e.tool_back_angle_deg = angles[1];
  read_stock(root, e, sc.run.seed);
  read_feed_axis(root, e);
  {
    auto sp = root.table("spindle", true);
    io::read_spindle(*sp, e.spindle, false);
  }
  read_sensor(root, e, sc.run.seed);
  read_controller(root, e);
  if (auto cmp = root.table("compare")) {
    for (const auto& n : cmp->choices("controllers", kModes))
      out->compare_modes.push_back(mode_from(n));
    cmp->document("controllers",
               "extra runs overlaid in the report; a compared fixed run is set for the worst "
               "case");
    cmp->finish();
  }
  if (auto co = root.table("cost")) {
    root.document("cost", "cost per part: machine time and the share of a cutting edge used");
    co->read({"machine_rate_per_h", Range::closed(0, 1e5),
              "machine-hour rate, operator and overhead included [money/h]"},
             out->cost.machine_rate_per_h);
    co->read({"tool_edge_cost", Range::closed(0, 1e5), "price of one cutting edge [money]"},
             out->cost.tool_edge_cost);
    co->read({"tool_change_min", Range::closed(0, 1e3),
              "machine time to index or change an edge"},
             out->cost.tool_change_min);
    co->finish();
  }
  if (auto sw = root.table("sweep")) {
    root.document("sweep", "extra runs: the tool-life verdict against the planned depth t_p");
    out->sweep_planned_depth_mm = sw->numbers(
        {"planned_depth_mm", {0.0, 50.0, true, false},
         "planned depths t_p: the seed law's used/plan from the main run, the depth-corrected "
         "law run at each"});
    sw->check(e.controller.mode == Mode::ForceFeedSpeed &&
                  e.force_parameter != cutting::ForceParameter::Power,
              "planned_depth_mm",
              "the planned-depth sweep needs controller.type = \"force_speed\" and a Pz or Py "
              "sensor (the depth-corrected law estimates the depth from the force)");
    sw->finish();
  }
  if (auto ch = root.table("chatter")) {
    root.document("chatter",
                  "lathectl optimize's chatter margin: the tool's modes and the part between "
                  "centres (docs/optimize.md)");
    read_chatter(*ch, out->chatter);
  }
  e.faults = io::read_faults(root);
  io::read_acceptance(root, out->acceptance);
  return out;
}

std::string mode_name(Mode m) {
  switch (m) {
    case Mode::Fixed:
      return "fixed feed and speed";
    case Mode::ForceFeed:
      return "force by feed (prior art)";
    case Mode::ForceFeedSpeed:
      return "force by feed + speed law (seed 004)";
  }
  return "?";
}

}  // namespace lathectl::systems::e_adaptive
