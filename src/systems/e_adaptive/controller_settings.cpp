// System E's [controller] section: setter 6's limit, the feeds, the speed plan and law, the
// regulator and its detectors, the spindle's limits and the sensor's plausible range (the rest of
// the scenario is read in settings.cpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/io/toml_reader.hpp"
#include "systems/e_adaptive/settings.hpp"
#include "systems/e_adaptive/settings_sections.hpp"

namespace lathectl::systems::e_adaptive {

namespace {

using io::Param;
using io::Range;
using io::TableReader;

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

// read_controller() in phases, in the order it reads the keys.

// Setter 6, the limit (a force, or the cutting power with the power sensor), and what runs
// around the regulator: the feed-forward, inertia learning, the worst-case feed.
void read_limit(TableReader& c, RigConfig& e) {
  auto& p = e.controller;
  const bool power = e.force_parameter == cutting::ForceParameter::Power;
  if (!power || c.is_describing())
    c.require({"force_limit_N", {0.0, 1e7, true, false}, "setter 6 (Pz/Py sensor)"}, p.load_limit);
  if (power || c.is_describing())
    c.require({"cut_power_limit_kW",
               {0.0, 1e4, true, false},
               "setter 6 (power sensor), instead of force_limit_N",
               1e3},
              p.load_limit);
  c.read({"feed_forward",
          {},
          "lower the feed before a rise in the depth of cut that the stock model sees ahead "
          "(in LinuxCNC with z_origin_mm); false: the regulator alone"},
         e.feed_forward);
  c.read({"learn_inertia",
          {},
          "power sensor: learn the spindle's inertia from its speed changes in air (rapids, the "
          "idle sweep) instead of taking [spindle] inertia_kg_m2 as known (it stays the prior)"},
         e.learn_inertia);
  c.read({"worst_case_feed",
          {},
          "fixed mode: the programmed feed is chosen so that the worst case meets the limit"},
         e.worst_case_feed);
}

// The feeds: the limiter's bounds (setters 9, 10), the programmed, air and entry feeds.
void read_feeds(TableReader& c, RigConfig& e) {
  auto& p = e.controller;
  c.read({"feed_min_mm_per_rev", {0.0, 10.0, true, false}, "setter 10"}, p.feed_min_mm_per_rev);
  c.read({"feed_max_mm_per_rev", {0.0, 10.0, true, false}, "setter 9; must be > min"},
         p.feed_max_mm_per_rev);
  c.check(p.feed_max_mm_per_rev > p.feed_min_mm_per_rev, "feed_max_mm_per_rev",
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
    c.read(feed, p.feed_programmed_mm_per_rev);
  } else {
    c.require(feed, p.feed_programmed_mm_per_rev);
    c.check(p.feed_programmed_mm_per_rev >= p.feed_min_mm_per_rev &&
                p.feed_programmed_mm_per_rev <= p.feed_max_mm_per_rev,
            "feed_mm_per_rev", "must lie in [feed_min_mm_per_rev, feed_max_mm_per_rev]");
  }
  c.read({"allow_above_programmed", {}, "the feed may rise above the programmed feed in cut"},
         p.allow_above_programmed);
  c.read({"average_per_revolution",
          {},
          "regulate the force averaged over one revolution (runout is not the feed's to fight); "
          "false: the raw signal"},
         p.average_per_revolution);
  p.air_feed_mm_per_rev = p.feed_programmed_mm_per_rev;
  c.read({.key = "air_feed_mm_per_rev",
          .range = {0.0, 10.0, true, false},
          .doc = "feed in air (default: feed_mm_per_rev)",
          .derived = "feed_mm_per_rev"},
         p.air_feed_mm_per_rev);
  // Entry feed: what the feed drops to at contact before the PI takes over. Default
  // max(0.05 mm/rev, s_min): a light chip for the first revolution, never below the limiter's
  // floor (the controller would reject it). Checked here so the error names this key.
  p.entry_feed_mm_per_rev = std::max(0.05, p.feed_min_mm_per_rev);
  c.read({.key = "entry_feed_mm_per_rev",
          .range = {0.0, 10.0, true, false},
          .doc = "feed at contact before the PI takes over (default: max(0.05, "
                 "feed_min_mm_per_rev))",
          .derived = "max(0.05, feed_min_mm_per_rev)"},
         p.entry_feed_mm_per_rev);
  c.check(p.entry_feed_mm_per_rev >= p.feed_min_mm_per_rev &&
              p.entry_feed_mm_per_rev <= p.feed_max_mm_per_rev,
          "entry_feed_mm_per_rev",
          "must lie in [feed_min_mm_per_rev, feed_max_mm_per_rev] = [" +
              fmt_number(p.feed_min_mm_per_rev) + ", " + fmt_number(p.feed_max_mm_per_rev) +
              "], got " + fmt_number(p.entry_feed_mm_per_rev));
}

// The plan the speed law starts from: V_p, S_p and t_p (and a warning when no edge survives it).
void read_speed_plan(TableReader& c, RigConfig& e) {
  auto& p = e.controller;
  c.require({.key = "speed_m_per_min",
             .range = {0.0, 2000.0, true, false},
             .doc = "V_p, setter 18",
             .plausible = Range::closed(10.0, 600.0)},
            p.speed_programmed_m_per_min);
  p.feed_planned_mm_per_rev = p.feed_programmed_mm_per_rev;
  c.read({.key = "planned_feed_mm_per_rev",
          .range = {0.0, 10.0, true, false},
          .doc = "S_p, setter 15 (default: feed_mm_per_rev)",
          .derived = "feed_mm_per_rev",
          .plausible = Range::closed(0.01, 2.0)},
         p.feed_planned_mm_per_rev);
  c.require({.key = "planned_depth_mm",
             .range = {0.0, 50.0, true, false},
             .doc = "t_p: the depth at which V_p and S_p give the planned tool life",
             .plausible = Range::closed(0.05, 20.0)},
            e.planned_depth_mm);
  warn_short_tool_life(c, e);
}

// The speed law: y_v (one, or the material's table), the filter on S_cur, and seed 004's law,
// the depth-corrected one or the tool-life one.
void read_speed_law(TableReader& c, RigConfig& e) {
  auto& p = e.controller;
  const bool power = e.force_parameter == cutting::ForceParameter::Power;
  const auto& m = e.cutting.material;
  p.y_v = tool_life_exponent(m, p.feed_planned_mm_per_rev, &cutting::ToolLifeRange::yv, 0.2);
  // By default the speed law takes y_v (and Cv) from the material's feed ranges, the
  // table the tool-life law uses; a y_v given here is one exponent for every feed (the seed's
  // law as written).
  const bool single_yv = c.has("y_v");
  c.read({.key = "y_v",
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
  c.read({"speed_law_filter_s", Range::closed(0, 100), "low-pass on S_cur before the speed law"},
         p.speed_law_filter_s);
  const std::string law =
      c.pick({"speed_law",
              {},
              "\"depth_corrected\" also corrects V for the depth (needs a Pz or Py sensor; x_v "
              "comes from the material); \"tool_life\" keeps tool life at plan beyond the "
              "seed: V for the depth the stock model gives and for the hardness the cut's "
              "specific force shows (K_mv; any sensor; in LinuxCNC with z_origin_mm)"},
             {"seed", "depth_corrected", "tool_life"}, "seed");
  if (law == "depth_corrected") {
    c.check(!power, "speed_law",
            "the depth-corrected law estimates depth from a force; use a Pz or Py sensor, or "
            "speed_law = \"tool_life\"");
    use_depth_corrected_law(e);
  }
  if (law == "tool_life") {
    use_depth_corrected_law(e);
    e.life_law = true;
  }
}

// The regulator (period, PI, rate limits) and the air, overload and breakage detectors.
void read_regulator(TableReader& c, RigConfig& e) {
  auto& p = e.controller;
  c.read({"period_ms",
          {0.0, 1000.0, true, false},
          "control period; in HAL, a whole multiple of the servo thread period",
          kMs},
         p.period_s);
  c.read({"kp", Range::closed(0, 100), "feed PI (regulator 7): proportional gain"}, p.kp);
  c.read({"ti_s", Range::closed(0, 100),
          "feed PI: integral time (at 600 rpm; above, in revolutions)"},
         p.ti_s);
  c.read({"feed_rate_limit_per_s",
          {0.0, 1e3, true, false},
          "rate limit of the feed, fraction of the programmed feed per s"},
         p.feed_rate_limit_per_s);
  c.read({"speed_rate_limit_m_per_min_per_s",
          {0.0, 1e5, true, false},
          "rate limit of the commanded cutting speed"},
         p.speed_rate_limit_m_per_min_per_s);
  c.read({"air_threshold",
          {0.0, 0.5, true, true},
          "fraction of the limit below which the tool is in air"},
         p.air_threshold);
  c.read({"air_time_ms", Range::closed(0, 1e4), "time below the air threshold that means air", kMs},
         p.air_time_s);
  c.read({"overload_margin", Range::closed(0, 10),
          "overload alarm above (1 + margin)·limit at s_min …"},
         p.overload_margin);
  c.read({"overload_time_ms", Range::closed(0, 1e5), "… for this long", kMs}, p.overload_time_s);
  c.read({"breakage_spike",
          {1.0, 100.0, true, false},
          "tool-breakage alarm on a spike above this multiple of the limit"},
         p.breakage_spike);
  c.read({"breakage_drop_window_ms", Range::closed(0, 1e4),
          "tool-breakage alarm on a drop from above half the limit to air within this time", kMs},
         p.breakage_drop_window_s);
}

// The spindle's speed range and the power available for cutting.
void read_spindle_limits(TableReader& c, RigConfig& e) {
  auto& p = e.controller;
  const auto& s = e.spindle;
  p.rpm_min = s.min_rpm;
  p.rpm_max = s.max_rpm;
  p.cut_power_max_W = 0.9 * s.max_power_W * s.efficiency / 1e3 * 1e3;
  c.read({.key = "cut_power_max_kW",
          .range = {0.0, 1e4, true, false},
          .doc = "power available for cutting, the speed law's clamp (default: "
                 "0.9·max_power_kW·efficiency)",
          .scale = 1e3,
          .derived = "0.9·spindle.max_power_kW·spindle.efficiency"},
         p.cut_power_max_W);
}

// The plausible range of the chosen sensor's readings and the stuck-sensor check.
void read_sensor_monitor(TableReader& c, RigConfig& e) {
  auto& p = e.controller;
  const bool power = e.force_parameter == cutting::ForceParameter::Power;
  // The monitor's limits are readings of the chosen sensor: N for Pz/Py, W for power.
  const std::string_view reading_unit = c.is_describing() ? "N (Pz, Py) or W (power)"
                                        : power           ? "W"
                                                          : "N";
  // A dynamometer reads little below zero; a spindle drive's power meter, braking, reads the
  // power it regenerates, up to its rating ([spindle] is read before [controller]).
  p.sensor_monitor.min = power ? -1.2 * e.spindle.max_power_W : -0.2 * p.load_limit;
  c.read({.key = "sensor_min",
          .range = Range::any(),
          .doc = "lowest plausible reading (default: −0.2·limit; power: −1.2·the spindle's "
                 "rated power, which a braking drive returns)",
          .unit = reading_unit,
          .derived = "−0.2·force_limit_N; power: −1.2·spindle.max_power_kW in W"},
         p.sensor_monitor.min);
  p.sensor_monitor.max = e.force_sensor.range;
  c.read({.key = "sensor_max",
          .range = Range::any(),
          .doc = "highest plausible reading (default: the sensor's range)",
          .unit = reading_unit,
          .derived = "sensor.range_N or sensor.range_W"},
         p.sensor_monitor.max);
  c.read({"sensor_stuck_ms", Range::closed(0, 1e5),
          "an unchanged reading this long is a stuck sensor", kMs},
         p.sensor_monitor.stuck_time_s);
  p.sensor_monitor.noise_sigma = e.force_sensor.noise_sigma;  // scale of the suspect check
  c.check(p.sensor_monitor.min < p.sensor_monitor.max, "sensor_max", "must exceed sensor_min");
}

}  // namespace

void read_controller(TableReader& root, RigConfig& e) {
  auto c = root.table("controller", true);
  auto& p = e.controller;
  p.mode = mode_from(c->pick({"type",
                              {},
                              "baseline (fixed), prior art (force_feed) or seed 004 "
                              "(force_speed)"},
                             kModes));
  read_limit(*c, e);
  read_feeds(*c, e);
  read_speed_plan(*c, e);
  read_speed_law(*c, e);
  read_regulator(*c, e);
  read_spindle_limits(*c, e);
  read_sensor_monitor(*c, e);
  c->finish();
}

}  // namespace lathectl::systems::e_adaptive
