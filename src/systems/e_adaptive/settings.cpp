#include "systems/e_adaptive/settings.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>

#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/cutting/stock.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/sections.hpp"
#include "lathectl/io/toml_reader.hpp"

namespace lathectl::systems::e_adaptive {

namespace {

using io::Param;
using io::Range;
using io::TableReader;

constexpr double kMs = 1e-3;
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

// The material's tool-life exponent (`yv` or `xv`) for the range that contains the feed.
template <class Field>
double tool_life_exponent(const cutting::Material& m, double feed, Field field, double fallback) {
  for (int i = 0; i < m.tool_life_ranges; ++i) {
    const auto& r = m.tool_life[static_cast<std::size_t>(i)];
    if (feed <= r.feed_max_mm_per_rev) return r.*field;
  }
  return fallback;
}

}  // namespace

void use_depth_corrected_law(RigConfig& e) {
  auto& p = e.controller;
  const auto& m = e.cutting.material;
  p.depth_exponent_xv =
      tool_life_exponent(m, p.feed_planned_mm_per_rev, &cutting::ToolLifeRange::xv, 0.15);
  p.depth_planned_mm = e.planned_depth_mm;
  // The design model: the handbook law of the measured component at the material's nominal
  // strength (the controller cannot know the local hardness; it shows up in t̂).
  const auto& law = e.force_parameter == cutting::ForceParameter::Pz ? m.Pz : m.Py;
  p.force_model_C = 10.0 * law.Cp * std::pow(m.strength / m.strength_base, m.kmp_exponent);
  p.force_model_x = law.x;
  p.force_model_y = law.y;
  p.force_model_n = law.n;
}

namespace {

std::string two_digits(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2g", v);
  return buf;
}

// V_p that no carbide edge survives on this material: the planned tool life T(V_p, S_p, t_p)
// of the extended Taylor law under a minute (1600 m/min on steel 45 gives about 0.2 s).
void warn_short_tool_life(const TableReader& c, const RigConfig& e) {
  if (c.is_describing()) return;
  const auto& p = e.controller;
  cutting::CuttingModel model;
  try {
    model.configure(e.cutting);
  } catch (const std::exception&) {
    return;
  }
  const double life_min = model.tool_life_min(p.speed_programmed_m_per_min,
                                              p.feed_planned_mm_per_rev, e.planned_depth_mm);
  if (!(life_min < 1.0)) return;
  const double v1 = model.speed_for_life(15.0, p.feed_planned_mm_per_rev, e.planned_depth_mm);
  c.warn("speed_m_per_min",
         "at V_p = " + fmt_number(p.speed_programmed_m_per_min) +
             " m/min (S_p = " + fmt_number(p.feed_planned_mm_per_rev) + " mm/rev, t_p = " +
             fmt_number(e.planned_depth_mm) + " mm) the tool life on " + e.cutting.material.name +
             " would be " + two_digits(life_min * 60.0) + " s; a 15 min edge runs at about " +
             fmt_number(std::round(v1)) + " m/min. Check the speed (it is m/min, not rpm)");
}

void read_controller(TableReader& root, RigConfig& e) {
  auto c = root.table("controller", true);
  auto& p = e.controller;
  const bool power = e.force_parameter == cutting::ForceParameter::Power;
  p.mode = mode_from(c->pick({"type", {}, "baseline (fixed), prior art (force_feed) or seed 004 "
                                          "(force_speed)"},
                             kModes));
  if (!power || c->is_describing())
    c->require({"force_limit_N", {0.0, 1e7, true, false}, "setter 6 (Pz/Py sensor)"},
               p.force_limit);
  if (power || c->is_describing())
    c->require({"cut_power_limit_kW", {0.0, 1e4, true, false},
                "setter 6 (power sensor), instead of force_limit_N", 1e3},
               p.force_limit);
  c->read({"feed_forward", {},
           "lower the feed before a rise in the depth of cut that the stock model sees ahead "
           "(in LinuxCNC with z_origin_mm); false: the regulator alone"},
          e.feed_forward);
  c->read({"learn_inertia", {},
           "power sensor: learn the spindle's inertia from its speed changes in air (rapids, the "
           "idle sweep) instead of taking [spindle] inertia_kg_m2 as known (it stays the prior)"},
          e.learn_inertia);
  c->read({"worst_case_feed", {},
           "fixed mode: the programmed feed is chosen so that the worst case meets the limit"},
          e.worst_case_feed);
  c->read({"feed_min_mm_per_rev", {0.0, 10.0, true, false}, "setter 10"}, p.feed_min_mm_per_rev);
  c->read({"feed_max_mm_per_rev", {0.0, 10.0, true, false}, "setter 9; must be > min"},
          p.feed_max_mm_per_rev);
  c->check(p.feed_max_mm_per_rev > p.feed_min_mm_per_rev, "feed_max_mm_per_rev",
           "must exceed feed_min_mm_per_rev");
  const Param feed{.key = "feed_mm_per_rev",
                   .range = {0.0, 10.0, true, false},
                   .doc =
                       "programmed feed (with worst_case_feed: optional, default "
                       "feed_min_mm_per_rev, and chosen by the rig)",
                   .derived = "feed_min_mm_per_rev",
                   .plausible = Range::closed(0.01, 2.0)};
  if (e.worst_case_feed) {
    p.feed_programmed_mm_per_rev = p.feed_min_mm_per_rev;
    c->read(feed, p.feed_programmed_mm_per_rev);
  } else {
    c->require(feed, p.feed_programmed_mm_per_rev);
    c->check(p.feed_programmed_mm_per_rev >= p.feed_min_mm_per_rev &&
                 p.feed_programmed_mm_per_rev <= p.feed_max_mm_per_rev,
             "feed_mm_per_rev", "must lie in [feed_min_mm_per_rev, feed_max_mm_per_rev]");
  }
  c->read({"allow_above_programmed", {}, "the feed may rise above the programmed feed in cut"},
          p.allow_above_programmed);
  c->read({"average_per_revolution", {},
           "regulate the force averaged over one revolution (runout is not the feed's to fight); "
           "false: the raw signal"},
          p.average_per_revolution);
  p.air_feed_mm_per_rev = p.feed_programmed_mm_per_rev;
  c->read({.key = "air_feed_mm_per_rev",
           .range = {0.0, 10.0, true, false},
           .doc = "feed in air (default: feed_mm_per_rev)",
           .derived = "feed_mm_per_rev"},
          p.air_feed_mm_per_rev);
  // Entry feed: what the feed drops to at contact before the PI takes over. Default
  // max(0.05 mm/rev, s_min): a light chip for the first revolution, never below the limiter's
  // floor (the controller would reject it). Checked here so the error names this key.
  p.entry_feed_mm_per_rev = std::max(0.05, p.feed_min_mm_per_rev);
  c->read({.key = "entry_feed_mm_per_rev",
           .range = {0.0, 10.0, true, false},
           .doc = "feed at contact before the PI takes over (default: max(0.05, "
                  "feed_min_mm_per_rev))",
           .derived = "max(0.05, feed_min_mm_per_rev)"},
          p.entry_feed_mm_per_rev);
  c->check(p.entry_feed_mm_per_rev >= p.feed_min_mm_per_rev &&
               p.entry_feed_mm_per_rev <= p.feed_max_mm_per_rev,
           "entry_feed_mm_per_rev",
           "must lie in [feed_min_mm_per_rev, feed_max_mm_per_rev] = [" +
               fmt_number(p.feed_min_mm_per_rev) + ", " + fmt_number(p.feed_max_mm_per_rev) +
               "], got " + fmt_number(p.entry_feed_mm_per_rev));
  c->require({.key = "speed_m_per_min",
              .range = {0.0, 2000.0, true, false},
              .doc = "V_p, setter 18",
              .plausible = Range::closed(10.0, 600.0)},
             p.speed_programmed_m_per_min);
  p.feed_planned_mm_per_rev = p.feed_programmed_mm_per_rev;
  c->read({.key = "planned_feed_mm_per_rev",
           .range = {0.0, 10.0, true, false},
           .doc = "S_p, setter 15 (default: feed_mm_per_rev)",
           .derived = "feed_mm_per_rev",
           .plausible = Range::closed(0.01, 2.0)},
          p.feed_planned_mm_per_rev);
  c->require({.key = "planned_depth_mm",
              .range = {0.0, 50.0, true, false},
              .doc = "t_p: the depth at which V_p and S_p give the planned tool life",
              .plausible = Range::closed(0.05, 20.0)},
             e.planned_depth_mm);
  warn_short_tool_life(*c, e);
  const auto& m = e.cutting.material;
  p.y_v = tool_life_exponent(m, p.feed_planned_mm_per_rev, &cutting::ToolLifeRange::yv, 0.2);
  // By default the speed law takes y_v (and Cv) from the material's feed ranges, the
  // table the tool-life law uses; a y_v given here is one exponent for every feed (the seed's
  // law as written).
  const bool single_yv = c->has("y_v");
  c->read({.key = "y_v",
           .range = Range::closed(0, 1.5),
           .doc = "one tool-life exponent of the feed for every feed (default: none; the speed "
                  "law takes y_v and Cv from the material's range containing each feed, as the "
                  "tool-life law does)",
           .derived = "none: the material's y_v of planned_feed_mm_per_rev's range"},
          p.y_v);
  p.y_v_ranges = 0;
  if (!single_yv)
    for (int i = 0; i < m.tool_life_ranges && i < 3; ++i) {
      const auto& r = m.tool_life[static_cast<std::size_t>(i)];
      p.y_v_table[static_cast<std::size_t>(i)] = {r.feed_max_mm_per_rev, r.Cv, r.yv};
      p.y_v_ranges = i + 1;
    }
  c->read({"speed_law_filter_s", Range::closed(0, 100), "low-pass on S_cur before the speed law"},
          p.speed_law_filter_s);
  const std::string law =
      c->pick({"speed_law", {},
               "\"depth_corrected\" also corrects V for the depth (needs a Pz or Py sensor; x_v "
               "comes from the material); \"tool_life\" keeps tool life at plan beyond the "
               "seed: V for the depth the stock model gives and for the hardness the cut's "
               "specific force shows (K_mv; any sensor; in LinuxCNC with z_origin_mm)"},
              {"seed", "depth_corrected", "tool_life"}, "seed");
  if (law == "depth_corrected") {
    c->check(!power, "speed_law",
             "the depth-corrected law estimates depth from a force; use a Pz or Py sensor, or "
             "speed_law = \"tool_life\"");
    use_depth_corrected_law(e);
  }
  if (law == "tool_life") {
    use_depth_corrected_law(e);
    e.life_law = true;
  }
  c->read({"period_ms", {0.0, 1000.0, true, false},
           "control period; in HAL, a whole multiple of the servo thread period", kMs},
          p.period_s);
  c->read({"kp", Range::closed(0, 100), "feed PI (regulator 7): proportional gain"}, p.kp);
  c->read({"ti_s", Range::closed(0, 100), "feed PI: integral time"}, p.ti_s);
  c->read({"feed_rate_limit_per_s", {0.0, 1e3, true, false},
           "rate limit of the feed, fraction of the programmed feed per s"},
          p.feed_rate_limit_per_s);
  c->read({"speed_rate_limit_m_per_min_per_s", {0.0, 1e5, true, false},
           "rate limit of the commanded cutting speed"},
          p.speed_rate_limit_m_per_min_per_s);
  c->read({"air_threshold", {0.0, 0.5, true, true},
           "fraction of the limit below which the tool is in air"},
          p.air_threshold);
  c->read({"air_time_ms", Range::closed(0, 1e4), "time below the air threshold that means air",
           kMs},
          p.air_time_s);
  c->read({"overload_margin", Range::closed(0, 10),
           "overload alarm above (1 + margin)·limit at s_min …"},
          p.overload_margin);
  c->read({"overload_time_ms", Range::closed(0, 1e5), "… for this long", kMs}, p.overload_time_s);
  c->read({"breakage_spike", {1.0, 100.0, true, false},
           "tool-breakage alarm on a spike above this multiple of the limit"},
          p.breakage_spike);
  c->read({"breakage_drop_window_ms", Range::closed(0, 1e4),
           "tool-breakage alarm on a drop from above half the limit to air within this time",
           kMs},
          p.breakage_drop_window_s);
  const auto& s = e.spindle;
  p.rpm_min = s.min_rpm;
  p.rpm_max = s.max_rpm;
  p.cut_power_max_W = 0.9 * s.max_power_W * s.efficiency / 1e3 * 1e3;
  c->read({.key = "cut_power_max_kW",
           .range = {0.0, 1e4, true, false},
           .doc = "power available for cutting, the speed law's clamp (default: "
                  "0.9·max_power_kW·efficiency)",
           .scale = 1e3,
           .derived = "0.9·spindle.max_power_kW·spindle.efficiency"},
          p.cut_power_max_W);
  // The monitor's limits are readings of the chosen sensor: N for Pz/Py, W for power.
  const std::string_view reading_unit = c->is_describing() ? "N (Pz, Py) or W (power)"
                                        : power            ? "W"
                                                           : "N";
  // A dynamometer reads little below zero; a spindle drive's power meter, braking, reads the
  // power it regenerates, up to its rating ([spindle] is read before [controller]).
  p.sensor_monitor.min = power ? -1.2 * e.spindle.max_power_W : -0.2 * p.force_limit;
  c->read({.key = "sensor_min",
           .range = Range::any(),
           .doc = "lowest plausible reading (default: −0.2·limit; power: −1.2·the spindle's "
                  "rated power, which a braking drive returns)",
           .unit = reading_unit,
           .derived = "−0.2·force_limit_N; power: −1.2·spindle.max_power_kW in W"},
          p.sensor_monitor.min);
  p.sensor_monitor.max = e.force_sensor.range;
  c->read({.key = "sensor_max",
           .range = Range::any(),
           .doc = "highest plausible reading (default: the sensor's range)",
           .unit = reading_unit,
           .derived = "sensor.range_N or sensor.range_W"},
          p.sensor_monitor.max);
  c->read({"sensor_stuck_ms", Range::closed(0, 1e5),
           "an unchanged reading this long is a stuck sensor", kMs},
          p.sensor_monitor.stuck_time_s);
  p.sensor_monitor.noise_sigma = e.force_sensor.noise_sigma;  // scale of the suspect check
  c->check(p.sensor_monitor.min < p.sensor_monitor.max, "sensor_max", "must exceed sensor_min");
  c->finish();
}

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
  io::read_material_tool(root, lib, e.cutting, &e.disturbances);
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
