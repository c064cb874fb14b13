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

using control::PulseFeedController;

void read_cutting(TableReader& root, const MaterialLibrary& lib, sim::RigAConfig& a,
                  std::uint64_t seed) {
  auto m = root.table("machine", true);
  a.spindle_rpm = m->number("spindle_rpm", {0.0, 20000.0, true, false});
  m->finish();

  read_material_tool(root, lib, a.cutting);

  auto part = root.table("part", true);
  a.diameter_m = part->number("diameter_mm", {0.0, 5000.0, true, false}) * kMm;
  auto& d = a.part;
  d.depth_mm = part->number("depth_mm", {0.0, 50.0, true, false});
  d.step_ramp_mm = part->number("step_ramp_mm", Range::non_negative(), 0.5);
  d.runout_mm = part->number("runout_mm", Range::closed(0, 20), 0.0);
  d.random_sigma_mm = part->number("random_depth_sigma_mm", Range::closed(0, 10), 0.0);
  d.random_correlation_mm = part->number("random_depth_correlation_mm", Range::positive(), 5.0);
  for (auto& s : part->tables("depth_steps")) {
    d.depth_steps.push_back(
        {s.number("at_mm", Range::non_negative()), s.number("depth_mm", Range::closed(0, 50))});
    s.finish();
  }
  for (auto& h : part->tables("hardness")) {
    d.hardness.push_back(
        {h.number("at_mm", Range::non_negative()), h.number("factor", {0.0, 10.0, true, false})});
    h.finish();
  }
  for (std::size_t i = 1; i < d.depth_steps.size(); ++i)
    if (!(d.depth_steps[i].at_mm > d.depth_steps[i - 1].at_mm))
      part->fail("depth_steps", "at_mm must increase from step to step");
  for (std::size_t i = 1; i < d.hardness.size(); ++i)
    if (!(d.hardness[i].at_mm > d.hardness[i - 1].at_mm))
      part->fail("hardness", "at_mm must increase from point to point");
  if (auto w = part->table("wear")) {
    d.wear_VB0_mm = w->number("initial_VB_mm", Range::closed(0, 2), 0.0);
    d.wear_rate_mm_per_min = w->number("rate_mm_per_min", Range::closed(0, 1), 0.0);
    d.wear_force_gain_per_mm = w->number("force_gain_per_mm", Range::closed(0, 20), 0.0);
    w->finish();
  }
  d.seed = seed;
  part->finish();
}

void read_regulator(TableReader& root, sim::RigAConfig& a) {
  auto r = root.table("regulator", true);
  a.regulator_kind = r->choice("type", {"pulsed", "throttle"}) == "throttle"
                         ? sim::RegulatorKind::Throttle
                         : sim::RegulatorKind::Pulsed;
  auto& o = a.regulator.orifice;
  o.spool_diameter_m = r->number("spool_diameter_mm", {0.0, 100.0, true, false}) * kMm;
  o.discharge_coefficient = r->number("discharge_coefficient", {0.0, 1.0, true, false}, 0.65);
  o.pressure_drop_Pa = r->number("pressure_drop_MPa", {0.0, 50.0, true, false}) * kMPa;
  o.density_kg_per_m3 = r->number("oil_density_kg_per_m3", {500.0, 1500.0, false, false}, 870.0);
  a.pulse_width_s = r->number("pulse_width_ms", {0.0, 10000.0, true, false}, 10.0) * 1e-3;
  a.frequency_Hz = r->number("frequency_Hz", {0.0, 10000.0, true, false}, 10.0);
  a.slot_m = r->number("slot_mm", {0.0, 10.0, true, false}, 0.04) * kMm;
  a.regulator.max_slot_m = r->number("max_slot_mm", {0.0, 10.0, true, false}, 0.2) * kMm;
  a.regulator.lap_m = r->number("overlap_mm", Range::closed(0, 5), 0.0) * kMm;
  a.regulator.opening_time_s = r->number("opening_time_ms", Range::closed(0, 1000), 0.0) * 1e-3;
  a.regulator.closing_time_s = r->number("closing_time_ms", Range::closed(0, 1000), 0.0) * 1e-3;
  if (a.pulse_width_s * a.frequency_Hz > 1.0)
    r->fail("pulse_width_ms", "pulse width × frequency exceeds 1 (pulse longer than period)");
  if (a.slot_m > a.regulator.max_slot_m) r->fail("slot_mm", "must not exceed max_slot_mm");
  if (auto ob = r->table("obliteration")) {
    auto& p = a.regulator.obliteration;
    p.layer_max_m = ob->number("layer_um", Range::closed(0, 100)) * kUm;
    p.time_constant_s = ob->number("time_constant_min", {0.0, 1e4, true, false}) * 60.0;
    p.critical_gap_m = ob->number("critical_gap_um", Range::closed(0, 1000), 20.0) * kUm;
    ob->finish();
  }
  r->finish();
}

void read_eccentric(TableReader& root, sim::RigAConfig& a) {
  auto& e = a.eccentric;
  auto t = root.table("eccentric");
  if (!t) {
    drives::EccentricDrive::circular_profile(0.0, a.regulator.max_slot_m / 2.0, 91, e);
    return;
  }
  auto profile = t->pairs("profile", Range::closed(0, 360), Range::closed(0, 10));
  if (!profile.empty()) {
    if (t->has("eccentricity_mm"))
      t->fail("eccentricity_mm", "give either profile or eccentricity_mm");
    e.profile_angle_rad.clear();
    e.profile_slot_m.clear();
    for (const auto& [deg, mm] : profile) {
      e.profile_angle_rad.push_back(deg * std::numbers::pi / 180.0);
      e.profile_slot_m.push_back(mm * kMm);
    }
    for (std::size_t i = 1; i < profile.size(); ++i)
      if (!(profile[i].first > profile[i - 1].first) ||
          !(profile[i].second > profile[i - 1].second))
        t->fail("profile", "angle and slot must both strictly increase (the profile is inverted)");
    if (profile.size() < 2) t->fail("profile", "at least two points expected");
  } else {
    const double ecc =
        t->number("eccentricity_mm", {0.0, 10.0, true, false}, a.regulator.max_slot_m / 2e-3);
    const double base = t->number("base_slot_mm", Range::closed(0, 10), 0.0);
    drives::EccentricDrive::circular_profile(base * kMm, ecc * kMm, 91, e);
  }
  e.gear_ratio = t->number("gear_ratio", {0.0, 1e5, true, false}, 100.0);
  e.motor_max_speed_rad_per_s = t->number("motor_max_speed_rpm", {0.0, 1e5, true, false}, 3000.0) *
                                2.0 * std::numbers::pi / 60.0;
  e.motor_time_constant_s =
      t->number("motor_time_constant_ms", Range::closed(0, 10000), 20.0) * 1e-3;
  e.position_gain_per_s = t->number("position_gain_per_s", {0.0, 1e5, true, false}, 20.0);
  t->finish();
}

void read_slide(TableReader& root, sim::RigAConfig& a) {
  auto s = root.table("slide", true);
  auto& p = a.slide;
  p.piston_area_m2 = s->number("piston_area_cm2", {0.0, 1e4, true, false}) * 1e-4;
  p.dead_volume_m3 = s->number("dead_volume_cm3", {0.0, 1e6, true, false}) * kCm3;
  p.bulk_modulus_Pa = s->number("oil_bulk_modulus_MPa", {100.0, 1e5, false, false}, 1400.0) * kMPa;
  // leakage given as flow per pressure: cm³/min per MPa
  p.leak_m3_per_s_Pa =
      s->number("leak_cm3_per_min_per_MPa", Range::closed(0, 1e5), 0.0) * kCm3 / 60.0 / kMPa;
  p.damper_capacitance_m3_per_Pa =
      s->number("damper_capacitance_cm3_per_MPa", Range::closed(0, 1e6), 0.0) * kCm3 / kMPa;
  p.damper_resistance_Pa_s_per_m3 =
      s->number("damper_resistance_MPa_s_per_cm3", Range::closed(0, 1e6), 0.0) * kMPa / kCm3;
  if (p.damper_capacitance_m3_per_Pa > 0.0 && !(p.damper_resistance_Pa_s_per_m3 > 0.0))
    s->fail("damper_resistance_MPa_s_per_cm3", "a damper needs a resistance > 0");
  p.mass_kg = s->number("mass_kg", {0.0, 1e5, true, false});
  p.coulomb_friction_N = s->number("coulomb_friction_N", Range::closed(0, 1e6), 0.0);
  p.viscous_friction_N_s_per_m =
      s->number("viscous_friction_N_s_per_m", Range::closed(0, 1e9), 0.0);
  s->finish();
}

void read_sensor(TableReader& root, sim::RigAConfig& a, std::uint64_t seed) {
  auto s = root.table("sensor", true);
  auto& p = a.sensor;
  p.holder_stiffness_N_per_m =
      s->number("holder_stiffness_N_per_um", {0.0, 1e6, true, false}) * 1e6;
  p.gain_V_per_m = s->number("gain_V_per_um", {0.0, 1e3, true, false}) * 1e6;
  p.offset_V = s->number("offset_V", Range::closed(-100, 100), 0.0);
  p.noise_V = s->number("noise_mV", Range::closed(0, 1e4), 0.0) * 1e-3;
  p.time_constant_s = s->number("time_constant_ms", Range::closed(0, 1e4), 0.0) * 1e-3;
  p.saturation_V = s->number("saturation_V", {0.0, 1000.0, true, false}, 10.0);
  p.seed = seed ^ 0x9E3779B97F4A7C15ULL;
  s->finish();
}

void read_controller(TableReader& root, sim::RigAConfig& a) {
  auto c = root.table("controller", true);
  const std::string kind = c->choice("type", {"none", "aim", "fim"});
  a.controller_kind = kind == "aim"   ? sim::ControllerKind::Aim
                      : kind == "fim" ? sim::ControllerKind::Fim
                                      : sim::ControllerKind::None;
  auto& p = a.controller;
  p.mode = c->choice("mode", {"finishing", "roughing"}, "finishing") == "roughing"
               ? PulseFeedController::Mode::Roughing
               : PulseFeedController::Mode::Finishing;
  p.feed_m_per_s = c->number("feed_mm_per_min", {0.0, 1e5, true, false}) * kMm / 60.0;
  if (p.mode == PulseFeedController::Mode::Roughing)
    p.force_set_N = c->number("force_set_N", {0.0, 1e6, true, false});
  p.period_s = c->number("period_ms", {0.0, 1000.0, true, false}, 1.0) * 1e-3;
  a.leak_estimate_factor = c->number("leak_estimate_factor", Range::closed(0, 10), 1.0);
  p.force_filter_s = c->number("force_filter_ms", Range::closed(0, 1e4), 5.0) * 1e-3;
  a.compensate_compliance = c->boolean("compensate_compliance", true);
  p.rate_filter_s = c->number("rate_filter_ms", Range::closed(0, 1e4), 100.0) * 1e-3;
  p.kp = c->number("kp", Range::closed(0, 100), 3.0);
  p.ti_s = c->number("ti_s", Range::closed(0, 100), 0.5);
  p.feed_min_fraction = c->number("feed_min_fraction", {0.0, 1.0, false, true}, 0.05);
  p.slot_min_m = c->number("slot_min_mm", Range::closed(0, 10), 0.0) * kMm;
  p.slot_max_m =
      c->number("slot_max_mm", {0.0, 10.0, true, false}, a.regulator.max_slot_m / kMm) * kMm;
  p.frequency_min_Hz = c->number("frequency_min_Hz", Range::closed(0, 1e4), 0.0);
  p.frequency_max_Hz = c->number("frequency_max_Hz", {0.0, 1e4, true, false}, 50.0);
  p.frequency_ramp_Hz_per_s = c->number("frequency_ramp_Hz_per_s", {0.0, 1e7, true, false}, 500.0);
  p.duty_max = c->number("duty_max", {0.0, 1.0, true, false}, 0.9);
  p.sensor_monitor.min = c->number("sensor_min_V", Range::any(), -0.5);
  p.sensor_monitor.max = c->number("sensor_max_V", Range::any(), a.sensor.saturation_V + 0.5);
  p.sensor_monitor.stuck_time_s = c->number("sensor_stuck_ms", Range::closed(0, 1e5), 50.0) * 1e-3;
  p.sensor_monitor.stuck_tolerance =
      c->number("sensor_stuck_tolerance_V", Range::closed(0, 10), 0.0);
  p.sensor_monitor.noise_sigma = a.sensor.noise_V;  // scale of the suspect (frozen) check
  if (!(p.sensor_monitor.min < p.sensor_monitor.max))
    c->fail("sensor_max_V", "must exceed sensor_min_V");
  if (p.slot_min_m >= p.slot_max_m) c->fail("slot_max_mm", "must exceed slot_min_mm");
  if (p.frequency_min_Hz >= p.frequency_max_Hz)
    c->fail("frequency_max_Hz", "must exceed frequency_min_Hz");
  c->finish();
}

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

void read_system_c(TableReader& root, const MaterialLibrary& lib, Scenario& sc) {
  auto& c = sc.c;
  auto m = root.table("machine", true);
  c.feed_m_per_rev = m->number("feed_mm_per_rev", {0.0, 10.0, true, false}) * 1e-3;
  c.spindle_rpm = m->number("spindle_rpm", {0.0, 2e4, true, false});
  m->finish();

  auto sl = root.table("slide", true);
  c.beta_rad = sl->number("guide_angle_deg", {0.0, 90.0, true, false}) * std::numbers::pi / 180.0;
  c.linear.lever_ratio = sl->number("lever_ratio", {0.0, 1e3, true, false});
  c.linear.mass_kg = sl->number("mass_kg", {0.0, 1e5, true, false});
  sl->finish();

  auto tp = root.table("template", true);
  if (tp->has("csv")) {  // points x_mm,diameter_mm, one per line, relative to the scenario file
    if (tp->has("features")) tp->fail("csv", "give either csv or features");
    const std::string rel = tp->string("csv");
    const auto path = (std::filesystem::path(sc.file).parent_path() / rel).string();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec) ||
        std::filesystem::file_size(path, ec) > (16u << 20))
      tp->fail("csv", "expected a regular file of at most 16 MiB: " + path);
    std::ifstream in(path);
    if (!in) tp->fail("csv", "cannot open " + path);
    std::string line;
    int n = 0;
    while (std::getline(in, line)) {
      ++n;
      if (line.empty() || line[0] == '#' || std::isalpha(static_cast<unsigned char>(line[0])))
        continue;
      double xm = 0.0, dm = 0.0;
      char comma = 0;
      std::istringstream ls(line);
      if (!(ls >> xm >> comma >> dm) || comma != ',' || !std::isfinite(xm) || !(dm > 0.0))
        throw InputError(located(path, n, 0, "expected 'x_mm,diameter_mm' with a diameter > 0"));
      if (!c.profile.xs().empty() && xm * 1e-3 < c.profile.xs().back())
        throw InputError(located(path, n, 0, "x_mm must not decrease"));
      c.profile.add_point(xm * 1e-3, 0.5e-3 * dm);
    }
    if (c.profile.xs().size() < 2) tp->fail("csv", "at least two points expected in " + path);
    c.features.push_back({"csv", c.profile.xs().front(), c.profile.xs().back()});
    tp->finish();
  }
  double x = tp->has("csv") ? 0.0 : tp->number("start_x_mm", Range::any(), 0.0) * 1e-3;
  double y =
      tp->has("csv") ? 0.0 : 0.5e-3 * tp->number("start_diameter_mm", {0.0, 1e4, true, false});
  if (!tp->has("csv")) c.profile.add_point(x, y);
  for (auto& f : tp->tables("features")) {
    const std::string kind = f.choice("type", {"line", "cone", "step", "arc"});
    sim::TracerFeature feat{kind, x, x};
    if (kind == "line") {
      x += f.number("length_mm", {0.0, 1e4, true, false}) * 1e-3;
      c.profile.add_point(x, y);
    } else if (kind == "cone") {
      const double len = f.number("length_mm", {0.0, 1e4, true, false}) * 1e-3;
      const double ang =
          f.number("angle_deg", {-89.0, 89.0, false, false}) * std::numbers::pi / 180.0;
      if (ang <= -c.beta_rad || ang + c.beta_rad >= std::numbers::pi)
        f.fail("angle_deg", "the slide cannot follow a cone with α ≤ −β or α + β ≥ 180°");
      x += len;
      y += len * std::tan(ang);
      c.profile.add_point(x, y);
    } else if (kind == "step") {
      const double hgt = f.number("height_mm", {-1e3, 1e3, false, false}) * 1e-3;
      if (hgt < 0.0)
        f.fail("height_mm", "a backward-inclined slide cannot follow a step down (α = −90° < −β)");
      y += hgt;
      c.profile.add_point(x, y);
    } else {  // arc: circle of the given radius through the current point and (x+len, y+h), convex
      const double len = f.number("length_mm", {0.0, 1e4, true, false}) * 1e-3;
      const double hgt = f.number("height_mm", {-1e3, 1e3, false, false}) * 1e-3;
      const double r = f.number("radius_mm", {0.0, 1e5, true, false}) * 1e-3;
      const double chord = std::hypot(len, hgt);
      if (r < 0.5 * chord) f.fail("radius_mm", "smaller than half the chord: no such arc");
      const double mx = x + 0.5 * len, my = y + 0.5 * hgt;
      const double dist = std::sqrt(r * r - 0.25 * chord * chord);
      // centre on the inner side (below the chord): a convex arc
      const double nx = hgt / chord, ny = -len / chord;
      const double cx = mx + dist * nx, cy = my + dist * ny;
      const double a0 = std::atan2(y - cy, x - cx), a1 = std::atan2(y + hgt - cy, x + len - cx);
      double prev_x = x;
      for (int k = 1; k <= 40; ++k) {
        const double ak = a0 + (a1 - a0) * k / 40.0;
        const double px = cx + r * std::cos(ak);
        // The template is y(x): the arc must not run backward nor past its own end in x.
        if (px < prev_x - 1e-12 || px > x + len + 1e-12)
          f.fail("radius_mm",
                 "this arc would run backward in x (the template must be a function of x): "
                 "give a larger radius or a longer length");
        prev_x = std::max(px, prev_x);
        c.profile.add_point(prev_x, cy + r * std::sin(ak));
      }
      x += len;
      y += hgt;
    }
    feat.x_end_m = x;
    f.finish();
    c.features.push_back(feat);
  }
  if (c.features.empty())
    tp->fail("features", "at least one feature {type = line | cone | step | arc, ...}");
  tp->finish();

  {
    auto mt = root.table("model", true);
    c.nonlinear = mt->choice("type", {"linear", "nonlinear"}) == "nonlinear";
    sc.c_compare = mt->has("compare") ? mt->choice("compare", {"linear", "nonlinear"}) : "";
    mt->finish();
  }
  if (auto li = root.table("linear")) {
    c.linear.E0_N_per_m = li->number("E0_N_per_mm", {0.0, 1e9, true, false}) * 1e3;
    c.linear.C0_per_s = li->number("C0_per_s", {0.0, 1e6, true, false});
    c.linear.P0_N = li->number("P0_N", Range::closed(0, 1e6));
    li->finish();
  } else if (!c.nonlinear) {
    root.fail("linear", "a linear model needs [linear] E0_N_per_mm, C0_per_s, P0_N");
  }
  if (auto sv = root.table("servo")) {
    c.supply_Pa = sv->number("supply_MPa", {0.0, 100.0, true, false}) * 1e6;
    c.discharge_coefficient = sv->number("discharge_coefficient", {0.0, 1.0, true, false}, 0.65);
    c.area_gradient_m = sv->number("port_width_mm", {0.0, 1e3, true, false}) * 1e-3;
    c.density_kg_per_m3 = sv->number("oil_density_kg_per_m3", {500.0, 1500.0, false, false}, 870.0);
    c.overlap_m = sv->number("overlap_um", Range::closed(0, 1e4), 0.0) * 1e-6;
    c.clearance_leak_m3_per_s_Pa =
        sv->number("clearance_leak_cm3_per_min_per_MPa", {0.0, 1e6, true, false}) * 1e-6 / 60.0 /
        1e6;
    c.piston_area_m2 = sv->number("piston_area_cm2", {0.0, 1e4, true, false}) * 1e-4;
    c.total_volume_m3 = sv->number("volume_cm3", {0.0, 1e6, true, false}) * 1e-6;
    c.bulk_modulus_Pa = sv->number("bulk_modulus_MPa", {100.0, 1e5, false, false}, 1400.0) * 1e6;
    sv->finish();
  } else if (c.nonlinear || sc.c_compare == "nonlinear") {
    root.fail("servo", "the nonlinear model needs [servo]");
  }
  if (auto fr = root.table("friction")) {
    c.coulomb_N = fr->number("coulomb_N", Range::closed(0, 1e6), 0.0);
    c.static_N = fr->number("static_N", Range::closed(0, 1e6), c.coulomb_N);
    if (c.static_N < c.coulomb_N) fr->fail("static_N", "must be ≥ coulomb_N (falling friction)");
    c.stribeck_velocity_m_per_s =
        fr->number("stribeck_velocity_mm_per_s", {0.0, 1e4, true, false}, 0.1) * 1e-3;
    c.viscous_N_s_per_m = fr->number("viscous_N_s_per_m", Range::closed(0, 1e9), 0.0);
    fr->finish();
  }
  if (auto cu = root.table("cutting")) {
    read_material_tool(root, lib, c.cutting);
    c.blank_diameter_m = cu->number("blank_diameter_mm", {0.0, 1e4, true, false}) * 1e-3;
    cu->finish();
  }
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

sim::ControllerKind controller_from(const std::string& s) {
  return s == "aim"   ? sim::ControllerKind::Aim
         : s == "fim" ? sim::ControllerKind::Fim
                      : sim::ControllerKind::None;
}
}  // namespace

std::string controller_kind_name(sim::ControllerKind k) {
  switch (k) {
    case sim::ControllerKind::Aim:
      return "AIM (amplitude-pulse)";
    case sim::ControllerKind::Fim:
      return "FIM (frequency-pulse)";
    case sim::ControllerKind::None:
      return "no control";
  }
  return "?";
}
std::string regulator_kind_name(sim::RegulatorKind k) {
  return k == sim::RegulatorKind::Throttle ? "continuous throttle" : "pulsed regulator";
}

// Transitional (issue 12): the systems not yet in their folders. Reads everything after the
// common part, finishes the root and probes the rig, as parse_scenario did for every system.
std::unique_ptr<SystemSettings> read_legacy(TableReader& root, Scenario& sc,
                                            const MaterialLibrary& lib) {
  auto keys = std::const_pointer_cast<KeyLocations>(sc.keys);
  if (sc.system == "C") {
    try {
      read_system_c(root, lib, sc);
    } catch (const std::invalid_argument& e) {
      throw_at_key(sc, e, "template");
    }
    root.finish();
    try {
      sim::RigC probe;
      probe.configure(sc.c, sc.run.step_s, sc.run.record_interval_s);
    } catch (const std::invalid_argument& e) {
      throw_at_key(sc, e);
    }
    return nullptr;
  }
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
  auto& a = sc.a;
  read_cutting(root, lib, a, sc.run.seed);
  read_regulator(root, a);
  read_eccentric(root, a);
  read_slide(root, a);
  read_sensor(root, a, sc.run.seed);
  read_controller(root, a);
  if (auto m = root.table("metrics")) {
    a.feed_window_s = m->number("feed_window_s", {0.0, 100.0, true, false}, 0.1);
    m->finish();
  }
  if (auto cmp = root.table("compare")) {
    Comparison c;
    if (cmp->has("controller"))
      c.controller = controller_from(cmp->choice("controller", {"none", "aim", "fim"}));
    if (cmp->has("regulator"))
      c.regulator = cmp->choice("regulator", {"pulsed", "throttle"}) == "throttle"
                        ? sim::RegulatorKind::Throttle
                        : sim::RegulatorKind::Pulsed;
    if (!c.controller && !c.regulator)
      cmp->fail("controller", "give controller and/or regulator to compare with");
    c.label = cmp->string("label", "");
    cmp->finish();
    sc.compare = c;
  }
  if (auto sw = root.table("sweep")) {
    sc.sweep_leak_estimate_factor = sw->numbers("leak_estimate_factor", Range::closed(0, 10), 1);
    if (a.controller_kind == sim::ControllerKind::None)
      sw->fail("leak_estimate_factor", "a sweep of the controller's K_leak needs a controller");
    sw->finish();
  }
  a.faults = read_faults(root);
  root.finish();
  // Cross-checks that need the whole scenario, reported against the key that decides them.
  sim::RigA probe;
  try {
    probe.configure(a, sc.run.step_s, sc.run.record_interval_s,
                    std::min(sc.run.duration_s, sc.run.step_s * 4));
  } catch (const std::invalid_argument& e) {
    throw_at_key(sc, e);
  }
  return nullptr;
}


}  // namespace lathectl::io
