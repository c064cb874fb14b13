#include "scenario_legacy.hpp"

#include "lathectl/io/scenario.hpp"
#include "lathectl/io/sections.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/study.hpp"
#include "lathectl/io/toml_reader.hpp"
#include "lathectl/sim/config_error.hpp"

namespace lathectl::io {

namespace {

// A number as a user wrote it (shortest form, no trailing zeros).
std::string fmt_number(double v) {
  std::ostringstream ss;
  ss << v;
  return ss.str();
}
constexpr double kMm = 1e-3;
constexpr double kUm = 1e-6;
constexpr double kMPa = 1e6;
constexpr double kCm3 = 1e-6;

using Mode = control::AdaptiveFeedController::Mode;

Mode mode_from(const std::string& s) {
  return s == "fixed" ? Mode::Fixed : s == "force_feed" ? Mode::ForceFeed : Mode::ForceFeedSpeed;
}
const std::vector<std::string> kModes{"fixed", "force_feed", "force_speed"};

void read_system_e(TableReader& root, const MaterialLibrary& lib, Scenario& sc) {
  auto& e = sc.e;
  read_material_tool(root, lib, e.cutting, &e.disturbances);

  auto st = root.table("stock", true);
  for (auto& b : st->tables("blank")) {
    e.stock.blank_diameter_mm.push_back(
        {b.number("at_mm", Range::any()), b.number("diameter_mm", {0.0, 5000.0, true, false})});
    b.finish();
  }
  if (e.stock.blank_diameter_mm.empty())
    st->fail("blank", "at least one {at_mm, diameter_mm} point");
  for (std::size_t i = 1; i < e.stock.blank_diameter_mm.size(); ++i)
    if (!(e.stock.blank_diameter_mm[i].at_mm > e.stock.blank_diameter_mm[i - 1].at_mm))
      st->fail("blank", "at_mm must increase from point to point");
  e.stock.eccentricity_mm = st->number("eccentricity_mm", Range::closed(0, 50), 0.0);
  for (auto& p : st->tables("passes")) {
    cutting::Pass k;
    k.z_start_mm = p.number("z_start_mm", Range::any());
    k.z_end_mm = p.number("z_end_mm", Range::any());
    k.diameter_mm = p.number("diameter_mm", {0.0, 5000.0, true, false});
    if (!(k.z_end_mm > k.z_start_mm)) p.fail("z_end_mm", "must exceed z_start_mm");
    p.finish();
    e.stock.passes.push_back(k);
  }
  if (e.stock.passes.empty())
    st->fail("passes", "at least one pass {z_start_mm, z_end_mm, diameter_mm}");
  for (auto& h : st->tables("hardness")) {
    e.disturbances.hardness.push_back(
        {h.number("at_mm", Range::any()), h.number("factor", {0.0, 10.0, true, false})});
    h.finish();
  }
  for (std::size_t i = 1; i < e.disturbances.hardness.size(); ++i)
    if (!(e.disturbances.hardness[i].at_mm > e.disturbances.hardness[i - 1].at_mm))
      st->fail("hardness", "at_mm must increase from point to point");
  e.disturbances.random_sigma_mm = st->number("random_depth_sigma_mm", Range::closed(0, 10), 0.0);
  e.disturbances.random_correlation_mm =
      st->number("random_depth_correlation_mm", Range::positive(), 20.0);
  e.disturbances.seed = sc.run.seed;
  e.approach_mm = st->number("approach_mm", Range::closed(0, 1000), 2.0);
  st->finish();

  auto ax = root.table("feed_axis", true);
  e.axis.time_constant_s = ax->number("time_constant_ms", {0.0, 1000.0, true, false}, 10.0) * 1e-3;
  e.rapid_m_per_s = ax->number("rapid_mm_per_min", {0.0, 1e6, true, false}, 6000.0) / 60000.0;
  e.axis.max_velocity_m_per_s = e.rapid_m_per_s;
  e.axis.max_acceleration_m_per_s2 =
      ax->number("max_acceleration_m_per_s2", {0.0, 1000.0, true, false}, 2.0);
  e.axis.encoder_resolution_m =
      ax->number("encoder_resolution_um", {0.0, 1000.0, true, false}, 1.0) * 1e-6;
  e.axis.velocity_window_s =
      ax->number("velocity_window_ms", {0.0, 10000.0, true, false}, 20.0) * 1e-3;
  ax->finish();

  {
    auto sp = root.table("spindle", true);
    // System E's scenarios have no idle losses unless they give them (the struct has 300 W):
    // TODO(issue 12, system E's folder): make this E's settings' own default.
    e.spindle.idle_p0_W = e.spindle.idle_p1_W_per_rpm = e.spindle.idle_p2_W_per_rpm2 = 0.0;
    read_spindle(*sp, e.spindle, false);
  }
  const auto& s = e.spindle;

  auto se = root.table("sensor", true);
  const std::string param = se->choice("parameter", {"Pz", "Py", "power"});
  e.force_parameter = param == "Pz"   ? sim::ForceParameter::Pz
                      : param == "Py" ? sim::ForceParameter::Py
                                      : sim::ForceParameter::Power;
  const bool power = e.force_parameter == sim::ForceParameter::Power;
  e.force_sensor.time_constant_s =
      se->number("time_constant_ms", Range::closed(0, 1e4), 2.0) * 1e-3;
  e.force_sensor.noise_sigma =
      se->number(power ? "noise_W" : "noise_N", Range::closed(0, 1e6), 0.0);
  e.force_sensor.range = se->number(power ? "range_W" : "range_N", {0.0, 1e9, true, false}, 1e5);
  e.force_sensor.seed = sc.run.seed ^ 0x51ED2701ULL;
  e.power_meter.time_constant_s =
      se->number("power_meter_time_constant_ms", Range::closed(0, 1e4), 20.0) * 1e-3;
  e.power_meter.noise_sigma = se->number("power_meter_noise_W", Range::closed(0, 1e6), 0.0);
  e.power_meter.range = 1e9;
  e.power_meter.seed = sc.run.seed ^ 0xB0B0B0B0ULL;
  se->finish();

  auto c = root.table("controller", true);
  auto& p = e.controller;
  p.mode = mode_from(c->choice("type", kModes));
  p.force_limit = power ? c->number("cut_power_limit_kW", {0.0, 1e4, true, false}) * 1e3
                        : c->number("force_limit_N", {0.0, 1e7, true, false});
  e.worst_case_feed = c->boolean("worst_case_feed", false);
  p.feed_min_mm_per_rev = c->number("feed_min_mm_per_rev", {0.0, 10.0, true, false}, 0.05);
  p.feed_max_mm_per_rev = c->number("feed_max_mm_per_rev", {0.0, 10.0, true, false}, 0.8);
  if (!(p.feed_max_mm_per_rev > p.feed_min_mm_per_rev))
    c->fail("feed_max_mm_per_rev", "must exceed feed_min_mm_per_rev");
  p.feed_programmed_mm_per_rev =
      e.worst_case_feed
          ? c->number("feed_mm_per_rev", {0.0, 10.0, true, false}, p.feed_min_mm_per_rev)
          : c->number("feed_mm_per_rev", {0.0, 10.0, true, false});
  if (!e.worst_case_feed && (p.feed_programmed_mm_per_rev < p.feed_min_mm_per_rev ||
                             p.feed_programmed_mm_per_rev > p.feed_max_mm_per_rev))
    c->fail("feed_mm_per_rev", "must lie in [feed_min_mm_per_rev, feed_max_mm_per_rev]");
  p.allow_above_programmed = c->boolean("allow_above_programmed", false);
  p.air_feed_mm_per_rev =
      c->number("air_feed_mm_per_rev", {0.0, 10.0, true, false}, p.feed_programmed_mm_per_rev);
  // Entry feed: what the feed drops to at contact before the PI takes over. Default
  // max(0.05 mm/rev, s_min): a light chip for the first revolution, never below the limiter's
  // floor (the controller would reject it). Checked here so the error names this key.
  p.entry_feed_mm_per_rev = c->number("entry_feed_mm_per_rev", {0.0, 10.0, true, false},
                                      std::max(0.05, p.feed_min_mm_per_rev));
  if (p.entry_feed_mm_per_rev < p.feed_min_mm_per_rev ||
      p.entry_feed_mm_per_rev > p.feed_max_mm_per_rev)
    c->fail("entry_feed_mm_per_rev",
            "must lie in [feed_min_mm_per_rev, feed_max_mm_per_rev] = [" +
                fmt_number(p.feed_min_mm_per_rev) + ", " + fmt_number(p.feed_max_mm_per_rev) +
                "], got " + fmt_number(p.entry_feed_mm_per_rev));
  p.speed_programmed_m_per_min = c->number("speed_m_per_min", {0.0, 2000.0, true, false});
  p.feed_planned_mm_per_rev =
      c->number("planned_feed_mm_per_rev", {0.0, 10.0, true, false}, p.feed_programmed_mm_per_rev);
  e.planned_depth_mm = c->number("planned_depth_mm", {0.0, 50.0, true, false});
  {
    // y_v defaults to the material's tool-life exponent for the planned feed.
    double yv = 0.2;
    const auto& m = e.cutting.material;
    for (int i = 0; i < m.tool_life_ranges; ++i)
      if (p.feed_planned_mm_per_rev <=
          m.tool_life[static_cast<std::size_t>(i)].feed_max_mm_per_rev) {
        yv = m.tool_life[static_cast<std::size_t>(i)].yv;
        break;
      }
    p.y_v = c->number("y_v", Range::closed(0, 1.5), yv);
  }
  p.speed_law_filter_s = c->number("speed_law_filter_s", Range::closed(0, 100), 1.0);
  if (c->choice("speed_law", {"seed", "depth_corrected"}, "seed") == "depth_corrected") {
    if (power)
      c->fail("speed_law",
              "the depth-corrected law estimates depth from a force; use a Pz or Py sensor");
    const auto& m = e.cutting.material;
    double xv = 0.15;
    for (int i = 0; i < m.tool_life_ranges; ++i)
      if (p.feed_planned_mm_per_rev <=
          m.tool_life[static_cast<std::size_t>(i)].feed_max_mm_per_rev) {
        xv = m.tool_life[static_cast<std::size_t>(i)].xv;
        break;
      }
    p.depth_exponent_xv = xv;
    p.depth_planned_mm = e.planned_depth_mm;
    // The design model: the handbook law of the measured component at the material's nominal
    // strength (the controller cannot know the local hardness; it shows up in t̂).
    const auto& law = e.force_parameter == sim::ForceParameter::Pz ? m.Pz : m.Py;
    p.force_model_C = 10.0 * law.Cp * std::pow(m.strength / m.strength_base, m.kmp_exponent);
    p.force_model_x = law.x;
    p.force_model_y = law.y;
    p.force_model_n = law.n;
  }
  p.period_s = c->number("period_ms", {0.0, 1000.0, true, false}, 2.0) * 1e-3;
  p.kp = c->number("kp", Range::closed(0, 100), 0.5);
  p.ti_s = c->number("ti_s", Range::closed(0, 100), 0.1);
  p.feed_rate_limit_per_s = c->number("feed_rate_limit_per_s", {0.0, 1e3, true, false}, 0.5);
  p.speed_rate_limit_m_per_min_per_s =
      c->number("speed_rate_limit_m_per_min_per_s", {0.0, 1e5, true, false}, 100.0);
  p.air_threshold = c->number("air_threshold", {0.0, 0.5, true, true}, 0.1);
  p.air_time_s = c->number("air_time_ms", Range::closed(0, 1e4), 50.0) * 1e-3;
  p.overload_margin = c->number("overload_margin", Range::closed(0, 10), 0.3);
  p.overload_time_s = c->number("overload_time_ms", Range::closed(0, 1e5), 200.0) * 1e-3;
  p.breakage_spike = c->number("breakage_spike", {1.0, 100.0, true, false}, 2.5);
  p.breakage_drop_window_s =
      c->number("breakage_drop_window_ms", Range::closed(0, 1e4), 10.0) * 1e-3;
  p.rpm_min = s.min_rpm;
  p.rpm_max = s.max_rpm;
  p.cut_power_max_W = c->number("cut_power_max_kW", {0.0, 1e4, true, false},
                                0.9 * s.max_power_W * s.efficiency / 1e3) *
                      1e3;
  p.sensor_monitor.min = c->number("sensor_min", Range::any(), -0.2 * p.force_limit);
  p.sensor_monitor.max = c->number("sensor_max", Range::any(), e.force_sensor.range);
  p.sensor_monitor.stuck_time_s = c->number("sensor_stuck_ms", Range::closed(0, 1e5), 100.0) * 1e-3;
  p.sensor_monitor.noise_sigma = e.force_sensor.noise_sigma;  // scale of the suspect check
  if (!(p.sensor_monitor.min < p.sensor_monitor.max))
    c->fail("sensor_max", "must exceed sensor_min");
  c->finish();

  if (auto cmp = root.table("compare")) {
    for (const auto& n : cmp->choices("controllers", kModes))
      sc.compare_modes.push_back(mode_from(n));
    cmp->finish();
  }
  e.faults = read_faults(root);
}

}  // namespace

std::string adaptive_mode_name(control::AdaptiveFeedController::Mode m) {
  switch (m) {
    case control::AdaptiveFeedController::Mode::Fixed:
      return "fixed feed and speed";
    case control::AdaptiveFeedController::Mode::ForceFeed:
      return "force by feed (prior art)";
    case control::AdaptiveFeedController::Mode::ForceFeedSpeed:
      return "force by feed + speed law (seed 004)";
  }
  return "?";
}

// Transitional (issue 12): the systems not yet in their folders. Reads everything after the
// common part, finishes the root and probes the rig, as parse_scenario did for every system.
std::unique_ptr<SystemSettings> read_legacy(TableReader& root, Scenario& sc,
                                            const MaterialLibrary& lib) {
    } catch (const std::invalid_argument& e) {
      throw_at_key(sc, e);
    }
    return nullptr;
  }
  if (sc.system == "E") {
    read_system_e(root, lib, sc);
    root.finish();
    sim::RigE probe;
    try {
      probe.configure(sc.e, sc.run.step_s, sc.run.record_interval_s, sc.run.step_s * 4);
    } catch (const std::invalid_argument& e) {
      throw_at_key(sc, e);
    }
    return nullptr;
  }
  throw std::logic_error("read_legacy: system " + sc.system + " has its own section reader");
}


}  // namespace lathectl::io
