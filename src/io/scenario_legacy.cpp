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
#include "lathectl/sim/rig_b.hpp"

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

// System B: the twin-turret rig, its measurement chain and the CNC module.
void read_system_b(TableReader& root, const MaterialLibrary& lib, Scenario& sc) {
  auto& b = sc.b;
  auto pt = root.table("part", true);
  b.part.length_m = pt->number("length_mm", {0.0, 1e5, true, false}) * kMm;
  b.part.diameter_m = pt->number("diameter_mm", {0.0, 1e4, true, false}) * kMm;
  b.part.youngs_modulus_Pa = pt->number("youngs_modulus_GPa", {0.0, 1e4, true, false}, 210.0) * 1e9;
  b.part.density_kg_per_m3 = pt->number("density_kg_per_m3", {0.0, 1e5, true, false}, 7850.0);
  b.part.damping_ratio = pt->number("damping_ratio", {0.0, 1.0, true, true});
  b.modes = static_cast<int>(pt->integer("modes", 1, 6, 2));
  pt->finish();
  // The regenerative gain is dF/db at the chip: the Kienzle form (handbook laws have t^x, x ≠ 1).
  read_material_tool(root, lib, b.cutting, nullptr, true);

  auto c = root.table("cut", true);
  const std::string setup = c->choice("setup", {"single", "feed_division", "depth_division"});
  b.setup = setup == "single"          ? sim::TwinSetup::Single
            : setup == "feed_division" ? sim::TwinSetup::FeedDivision
                                       : sim::TwinSetup::DepthDivision;
  const auto depth = c->numbers("depth_mm", {0.0, 50.0, true, false}, 1);
  if (depth.size() > 2) c->fail("depth_mm", "one depth, or one per turret [right, left]");
  b.depth_mm[0] = depth[0];
  b.depth_mm[1] = depth.size() > 1 ? depth[1] : depth[0];
  b.feed_mm_per_rev = c->number("feed_mm_per_rev", {0.0, 10.0, true, false});
  b.rpm = c->number("rpm", {1.0, 1e5, false, false});
  b.overlap = c->number("overlap", Range::closed(0, 1), 1.0);
  b.tool2_lag_mm = c->number("tool2_lag_mm", Range::closed(0, 1000), 0.0);
  if (b.setup == sim::TwinSetup::Single && b.tool2_lag_mm > 0.0)
    c->fail("tool2_lag_mm", "a single-tool set-up has no second tool");
  b.z_start_mm = c->number("z_start_mm", {0.0, 1e5, true, false});
  b.z_end_mm = c->number("z_end_mm", {0.0, 1e5, true, false});
  if (!(b.z_end_mm > b.z_start_mm)) c->fail("z_end_mm", "must exceed z_start_mm");
  if (!(b.z_end_mm < b.part.length_m / kMm))
    c->fail("z_end_mm", "must lie before the tailstock centre (part.length_mm)");
  b.approach_mm = c->number("approach_mm", Range::closed(0, 100), 1.0);
  b.idle_block_s = c->number("idle_block_s", Range::closed(0, 100), 0.5);
  b.feed_drive_bandwidth_Hz = c->number("feed_drive_bandwidth_Hz", {0.0, 1e4, true, false}, 30.0);
  b.initial_disturbance_um = c->number("initial_disturbance_um", Range::closed(0, 1000), 1.0);
  c->finish();
  if ((b.z_end_mm - b.z_start_mm) / (b.feed_mm_per_rev * b.rpm / 60.0) > sc.run.duration_s)
    root.fail("run", "run.duration_s is shorter than the cut (z_end − z_start at feed·rpm)");

  b.spindle.inertia_kg_m2 = 0.2;
  b.spindle.max_torque_N_m = 300.0;
  b.spindle.max_power_W = 11000.0;
  b.spindle.max_rpm = 4000.0;
  if (auto sp = root.table("spindle")) read_spindle(*sp, b.spindle, true);
  if (!(b.rpm >= b.spindle.min_rpm && b.rpm <= b.spindle.max_rpm))
    root.fail("cut", "cut.rpm must lie within the spindle's [min_rpm, max_rpm]");

  auto& v = b.vibration;
  if (auto vs = root.table("vibration_sensor")) {
    v.highpass_Hz = vs->number("highpass_Hz", {0.0, 1e4, true, false}, 40.0);
    v.noise_m = vs->number("noise_um", Range::closed(0, 1000), 0.2) * kUm;
    v.dead_zone_m = vs->number("dead_zone_um", Range::closed(0, 1e4), 5.0) * kUm;
    v.amplitude_gate_s = vs->number("amplitude_gate_ms", {0.0, 1e5, true, false}, 50.0) * 1e-3;
    v.frequency_gate_s = vs->number("frequency_gate_ms", {0.0, 1e5, true, false}, 100.0) * 1e-3;
    v.adc_lsb_m = vs->number("adc_lsb_um", {0.0, 1e3, true, false}, 1.0) * kUm;
    vs->finish();
  }
  v.seed = static_cast<unsigned>(sc.run.seed ^ 0x5EED01ULL);
  auto& pw = b.power;
  pw.meter.seed = sc.run.seed ^ 0xB0B0B0B0ULL;
  if (auto ps = root.table("power_sensor")) {
    pw.meter.time_constant_s = ps->number("time_constant_ms", Range::closed(0, 1e4), 50.0) * 1e-3;
    pw.meter.noise_sigma = ps->number("noise_W", Range::closed(0, 1e6), 5.0);
    pw.adc_lsb_W = ps->number("adc_lsb_W", {0.0, 1e4, true, false}, 1.0);
    pw.idle_average_s = ps->number("idle_average_ms", {0.0, 1e5, true, false}, 200.0) * 1e-3;
    if (ps->choice("idle", {"stored", "table"}, "stored") == "table") {
      // Beyond the seed: the idle law of the spindle tabulated at these speeds (measured on the
      // machine once, at commissioning).
      pw.idle_table_rpm = ps->numbers("idle_table_rpm", {0.0, 1e5, true, false}, 2);
      for (std::size_t i = 1; i < pw.idle_table_rpm.size(); ++i)
        if (!(pw.idle_table_rpm[i] > pw.idle_table_rpm[i - 1]))
          ps->fail("idle_table_rpm", "speeds must ascend");
      for (double n : pw.idle_table_rpm)
        pw.idle_table_W.push_back(b.spindle.idle_p0_W + b.spindle.idle_p1_W_per_rpm * n +
                                  b.spindle.idle_p2_W_per_rpm2 * n * n);
    }
    ps->finish();
  }

  auto& m = b.module;
  const auto& fp = b.cutting.material.Fp;
  const auto& fc = b.cutting.material.Fc;
  // Defaults from the Kienzle law at the programmed chip: F ∝ S^(1−m_p), F_p/F_c.
  const double h =
      b.setup == sim::TwinSetup::FeedDivision ? 0.5 * b.feed_mm_per_rev : b.feed_mm_per_rev;
  m.force_feed_exponent = 1.0 - fp.m;
  m.radial_force_ratio =
      fp.k11_N_per_mm2 * std::pow(h, 1.0 - fp.m) / (fc.k11_N_per_mm2 * std::pow(h, 1.0 - fc.m));
  m.part_mass_kg = sim::RigB::modal_mass_kg(b.part, 0.5 * (b.z_start_mm + b.z_end_mm) * kMm);
  b.source = control::ModulationSource::None;
  if (auto md = root.table("modulation")) {
    const std::string src = md->choice("source", {"automatic", "programmed", "none"});
    b.source = src == "automatic"    ? control::ModulationSource::Automatic
               : src == "programmed" ? control::ModulationSource::Programmed
                                     : control::ModulationSource::None;
    b.turret = md->choice("turret", {"right", "left"}, "right") == "left" ? control::Turret::Left
                                                                          : control::Turret::Right;
    if (b.setup == sim::TwinSetup::Single && b.turret == control::Turret::Left)
      md->fail("turret", "a single-tool set-up has only the right turret");
    m.coefficient = md->number("coefficient", {0.0, 100.0, true, false}, 1.41);
    m.part_mass_kg = md->number("part_mass_kg", {0.0, 1e6, true, false}, m.part_mass_kg);
    m.radial_force_ratio =
        md->number("radial_force_ratio", {0.0, 10.0, true, false}, m.radial_force_ratio);
    m.force_feed_exponent =
        md->number("force_feed_exponent", {0.0, 1.5, true, true}, m.force_feed_exponent);
    m.modulation_frequency_Hz = md->number("modulation_frequency_Hz", {0.0, 1e4, true, false}, 2.0);
    m.drive_bandwidth_Hz = b.feed_drive_bandwidth_Hz;
    m.n_s = static_cast<int>(md->integer("n_s", 1, 1000, 5));
    m.resolution_mm = md->number("resolution_um", {0.0, 1e4, true, false}, 1.0) * kUm / kMm;
    m.s_min_fraction = md->number("s_min_fraction", {0.0, 1.0, true, true}, 0.2);
    m.s_max_fraction = md->number("s_max_fraction", {1.0, 100.0, true, false}, 2.0);
    m.engage_time_s = md->number("engage_time_ms", Range::closed(0, 1e5), 50.0) * 1e-3;
    m.replan_period_s = md->number("replan_period_s", {0.0, 1e4, true, false}, 0.5);
    m.release_below_dead_zone = md->boolean("release_below_dead_zone", false);
    m.release_time_s = md->number("release_time_ms", Range::closed(0, 1e5), 200.0) * 1e-3;
    m.desync_fraction = md->number("desync_fraction", Range::closed(0, 100), 0.0);
    if (b.source == control::ModulationSource::Programmed) {
      b.programmed.s_min_mm_per_min = md->number("S_min_mm_per_min", {0.0, 1e5, true, false});
      b.programmed.ds_mm_per_min = md->number("dS_mm_per_min", {0.0, 1e5, true, false});
      if (std::abs(std::remainder(b.programmed.ds_mm_per_min, 0.1)) > 1e-9)
        md->fail("dS_mm_per_min", "must be a multiple of 0.1 mm/min (the seed's feed quantum)");
      b.programmed.dl_mm = md->number("dl_mm", {0.0, 1e4, true, false});
      const double units = b.programmed.dl_mm / m.resolution_mm;
      if (std::abs(units - std::round(units)) > 1e-6)
        md->fail("dl_mm", "must be a multiple of the resolution (modulation.resolution_um)");
      b.programmed.n_s = m.n_s;
    }
    md->finish();
  }
  if (auto st = root.table("study")) {
    sc.b_compare = st->boolean("compare_without_modulation", true);
    sc.b_sweep_feed = st->numbers("sweep_feed_mm_per_rev", {0.0, 10.0, true, false});
    if (sc.b_sweep_feed.size() > 40) st->fail("sweep_feed_mm_per_rev", "at most 40 feeds");
    st->finish();
  }
}

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

void read_system_d(TableReader& root, Scenario& sc) {
  auto& d = sc.d;
  auto pr = root.table("process", true);
  d.process.allowance_m = pr->number("allowance_um", {0.0, 1e5, true, false}) * 1e-6;
  d.process.removal_m_per_s = pr->number("removal_um_per_s", {0.0, 1e5, true, false}) * 1e-6;
  d.process.target_m = pr->number("target_um", Range::any()) * 1e-6;
  if (!(d.process.target_m < d.process.allowance_m))
    pr->fail("target_um", "must be below allowance_um");
  const double sigma = pr->number("noise_sigma_um", Range::closed(0, 1e4), 0.0) * 1e-6;
  d.process.noise_variance_m2 = sigma * sigma;
  d.process.noise_beta_per_s = pr->number("noise_beta_per_s", {0.0, 1e6, true, false}, 5.0);
  d.process.relay_response_s = pr->number("relay_response_ms", Range::closed(0, 1e4), 20.0) * 1e-3;
  d.tolerance_m = pr->number("tolerance_um", {0.0, 1e5, true, false}) * 1e-6;
  pr->finish();

  auto tr = root.table("transducer", true);
  auto& t = d.transducer;
  t.supply_V = tr->number("supply_V", {0.0, 1e4, true, false});
  t.supply_Hz = tr->number("supply_Hz", {0.0, 1e5, true, false});
  t.coil_turns = tr->number("coil_turns", {0.0, 1e7, true, false});
  t.coil_resistance_ohm = tr->number("coil_resistance_ohm", {0.0, 1e7, true, false});
  t.coil_inductance_H = tr->number("coil_inductance_H", {0.0, 1e4, true, false});
  t.force_coefficient_N_per_Wb2 =
      tr->number("force_coefficient_N_per_Wb2", {0.0, 1e20, true, false});
  t.probe_mass_kg = tr->number("probe_mass_g", {0.0, 1e6, true, false}) * 1e-3;
  t.probe_damping_N_s_per_m = tr->number("probe_damping_N_s_per_m", Range::closed(0, 1e6));
  t.probe_stiffness_N_per_m = tr->number("probe_stiffness_N_per_mm", {0.0, 1e9, true, false}) * 1e3;
  t.contact_stiffness_N_per_m =
      tr->number("contact_stiffness_N_per_mm", {0.0, 1e9, true, false}, 1000.0) * 1e3;
  t.contact_damping_N_s_per_m = tr->number("contact_damping_N_s_per_m", Range::closed(0, 1e6), 5.0);
  t.generator_V_per_m_per_s = tr->number("generator_V_per_m_per_s", {0.0, 1e6, true, false});
  t.generator_time_constant_s =
      tr->number("generator_time_constant_ms", Range::closed(0, 1e4), 0.2) * 1e-3;
  t.filter_time_constant_s = tr->number("filter_time_constant_ms", {0.0, 1e6, true, false}) * 1e-3;
  tr->finish();

  if (auto g = root.table("gauge")) {
    d.threshold = g->choice("threshold", {"seed", "calibrated", "given"}, "calibrated");
    if (d.threshold == "given") d.threshold_V = g->number("threshold_V", Range::any());
    g->finish();
  }
  if (auto mc = root.table("monte_carlo")) {
    d.parts = static_cast<std::size_t>(mc->integer("parts", 1, 10000000, 100000));
    d.full_parts = static_cast<std::size_t>(mc->integer("full_parts", 0, 10000, 8));
    mc->finish();
  }
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
  auto keys = std::const_pointer_cast<KeyLocations>(sc.keys);
  if (sc.system == "B") {
    try {
      read_system_b(root, lib, sc);
    } catch (const std::invalid_argument& e) {
      throw_at_key(sc, e, "part");
    }
    root.finish();
    try {
      // Like A, C, D and E: refuse a step too coarse for the dynamics (here the chatter).
      double f_Hz = 0.0;
      const double max_step = sim::RigB::max_step_s(sc.b, &f_Hz);
      if (sc.run.step_s > max_step)
        root.table("run", true)->fail("step_s", "too coarse for the part's chatter near " +
                                                    fmt(f_Hz, "%.0f") + " Hz (ω·dt ≤ 0.2): use "
                                                    "step_s ≤ " + fmt(max_step, "%.3g") + " s");
      sim::RigB probe;
      probe.configure(sc.b, sc.run.step_s, sc.run.record_interval_s, sc.run.step_s * 4);
    } catch (const std::invalid_argument& e) {
      throw_at_key(sc, e);
    }
    return nullptr;
  }
  if (sc.system == "D") {
    read_system_d(root, sc);
    root.finish();
    sensors::VibroContactGauge probe;
    try {
      probe.configure(sc.d.transducer, sc.run.step_s);
    } catch (const std::invalid_argument& e) {
      throw_at_key(sc, e, "transducer");
    }
    // The transducer reads nothing above its free amplitude: found here, not after a run.
    if (sc.d.process.allowance_m > probe.free_amplitude_m())
      keys->fail("process.allowance_um",
                 fmt_number(sc.d.process.allowance_m * 1e6) +
                     " µm exceeds the largest allowance this transducer can measure, A0 = " +
                     fmt_number(probe.free_amplitude_m() * 1e6) + " µm");
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
