// System A's section reader: every key once, with its range, one line of meaning (the notes of
// docs/scenario-reference.md) and its shop → SI factor; absent keys keep Settings' defaults.
#include "systems/a_pulse_feed/settings.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "lathectl/io/sections.hpp"
#include "lathectl/io/toml_reader.hpp"

namespace lathectl::systems::a_pulse_feed {

namespace {
using control::PulseFeedController;
using io::Param;
using io::Range;
using io::TableReader;

constexpr double kMm = 1e-3;
constexpr double kUm = 1e-6;
constexpr double kMs = 1e-3;
constexpr double kMPa = 1e6;
constexpr double kCm3 = 1e-6;

void read_cutting(TableReader& root, const io::MaterialLibrary& lib, RigConfig& a,
                  std::uint64_t seed) {
  auto m = root.table("machine", true);
  root.document("machine", "the lathe's spindle");
  m->require({"spindle_rpm", {0.0, 20000.0, true, false}, "spindle speed n"}, a.spindle_rpm);
  m->finish();

  io::read_material_tool(root, lib, a.cutting);

  auto part = root.table("part", true);
  root.document("part", "the part and its disturbances along the slide's travel");
  part->require({"diameter_mm", {0.0, 5000.0, true, false}, "sets the cutting speed", kMm},
                a.diameter_m);
  auto& d = a.part;
  part->require({"depth_mm", {0.0, 50.0, true, false}, "depth of cut at the start"}, d.depth_mm);
  part->read({"step_ramp_mm", Range::non_negative(), "travel over which a step is entered"},
             d.step_ramp_mm);
  part->read({"runout_mm", Range::closed(0, 20), "depth amplitude once per revolution"},
             d.runout_mm);
  part->read({"random_depth_sigma_mm", Range::closed(0, 10), "random allowance σ"},
             d.random_sigma_mm);
  part->read({"random_depth_correlation_mm", Range::positive(),
              "correlation length of the random allowance"},
             d.random_correlation_mm);
  for (auto& s : part->tables("depth_steps")) {
    cutting::ProfilePoint pt{};
    s.require({"at_mm", Range::non_negative(), "travel where the step starts"}, pt.at_mm);
    s.require({"depth_mm", Range::closed(0, 50), "depth of cut after the step"}, pt.value);
    s.finish();
    d.depth_steps.push_back(pt);
  }
  part->document("depth_steps", "depth steps {at_mm, depth_mm}; at_mm strictly increasing");
  for (auto& h : part->tables("hardness")) {
    cutting::ProfilePoint pt{};
    h.require({"at_mm", Range::non_negative(), "travel of the hardness point"}, pt.at_mm);
    h.require({"factor",
               {0.0, 10.0, true, false},
               "multiplies the material's strength (force × factor^kmp_exponent)"},
              pt.value);
    h.finish();
    d.hardness.push_back(pt);
  }
  part->document("hardness",
      "hardness points {at_mm, factor}, interpolated; at_mm strictly increasing");
  for (std::size_t i = 1; i < d.depth_steps.size(); ++i)
    part->check(d.depth_steps[i].at_mm > d.depth_steps[i - 1].at_mm, "depth_steps",
                "at_mm must increase from step to step");
  for (std::size_t i = 1; i < d.hardness.size(); ++i)
    part->check(d.hardness[i].at_mm > d.hardness[i - 1].at_mm, "hardness",
                "at_mm must increase from point to point");
  if (auto w = part->table("wear")) {
    part->document("wear", "tool flank wear; the force factor is 1 + force_gain_per_mm·VB");
    w->read({"initial_VB_mm", Range::closed(0, 2), "flank wear VB at the start"}, d.wear_VB0_mm);
    w->read({"rate_mm_per_min", Range::closed(0, 1), "VB growth per minute in cut"},
            d.wear_rate_mm_per_min);
    w->read({"force_gain_per_mm", Range::closed(0, 20), "force factor growth per mm of VB"},
            d.wear_force_gain_per_mm);
    w->finish();
  }
  d.seed = seed;
  part->finish();
}

void read_regulator(TableReader& root, RigConfig& a) {
  auto r = root.table("regulator", true);
  root.document("regulator", "discrete regulator 5, or the continuous throttle");
  a.regulator_kind =
      r->pick({"type", {}, "the pulsed regulator of the seed, or a continuous throttle"},
              {"pulsed", "throttle"}) == "throttle"
          ? RegulatorKind::Throttle
          : RegulatorKind::Pulsed;
  auto& o = a.regulator.orifice;
  r->require({"spool_diameter_mm", {0.0, 100.0, true, false}, "d", kMm}, o.spool_diameter_m);
  r->read({"discharge_coefficient", {0.0, 1.0, true, false}, "μ"}, o.discharge_coefficient);
  r->require(
      {"pressure_drop_MPa", {0.0, 50.0, true, false}, "Δp, held by the reducing valve РК", kMPa},
      o.pressure_drop_Pa);
  r->read({"oil_density_kg_per_m3", Range::closed(500, 1500), "ρ"}, o.density_kg_per_m3);
  r->read({"pulse_width_ms", {0.0, 10000.0, true, false}, "Δt", kMs}, a.pulse_width_s);
  r->read({"frequency_Hz", {0.0, 10000.0, true, false}, "1/T: fixed with AIM and without control"},
          a.frequency_Hz);
  r->read({"slot_mm", {0.0, 10.0, true, false}, "the fixed h of FIM", kMm}, a.slot_m);
  r->read({"max_slot_mm", {0.0, 10.0, true, false}, "largest opening", kMm},
          a.regulator.max_slot_m);
  r->read({"overlap_mm", Range::closed(0, 5), "spool overlap: no flow below it", kMm},
          a.regulator.lap_m);
  r->read({"opening_time_ms", Range::closed(0, 1000), "valve opening time (full travel)", kMs},
          a.regulator.opening_time_s);
  r->read({"closing_time_ms", Range::closed(0, 1000), "valve closing time (full travel)", kMs},
          a.regulator.closing_time_s);
  r->check(a.pulse_width_s * a.frequency_Hz <= 1.0, "pulse_width_ms",
           "pulse width × frequency exceeds 1 (pulse longer than period)");
  r->check(a.slot_m <= a.regulator.max_slot_m, "slot_mm", "must not exceed max_slot_mm");
  if (auto ob = r->table("obliteration")) {
    r->document("obliteration",
        "silting: below the critical gap a layer grows toward layer_um; a wider opening clears it");
    auto& p = a.regulator.obliteration;
    ob->require({"layer_um", Range::closed(0, 100), "layer per wall it grows toward", kUm},
                p.layer_max_m);
    ob->require({"time_constant_min", {0.0, 1e4, true, false}, "growth time constant", 60.0},
                p.time_constant_s);
    ob->read(
        {"critical_gap_um", Range::closed(0, 1000), "openings at or above it do not silt", kUm},
        p.critical_gap_m);
    ob->read({"removal_per_stroke", Range::closed(0, 1),
              "share of the layer each closing stroke of the spool sweeps off (1: all, the "
              "seed's assumption; not measured)"},
             p.removal_per_stroke);
    ob->finish();
  }
  r->finish();
}

void read_eccentric(TableReader& root, RigConfig& a) {
  auto& e = a.eccentric;
  auto t = root.table("eccentric");
  if (!t) {  // a circular profile from 0 to max_slot_mm, the drive's defaults
    drives::EccentricDrive::circular_profile(0.0, a.regulator.max_slot_m / 2.0, 91, e);
    return;
  }
  root.document("eccentric", "AIM actuator ЭД, Р and 8: a circular eccentric or a profile");
  auto profile = t->pairs("profile", Range::closed(0, 360), Range::closed(0, 10));
  t->document("profile",
      "[[deg, mm], …]: ≥ 2 points, both columns strictly increasing; not with eccentricity_mm");
  if (!profile.empty()) {
    t->check(!t->has("eccentricity_mm"), "eccentricity_mm",
             "give either profile or eccentricity_mm");
    e.profile_angle_rad.clear();
    e.profile_slot_m.clear();
    for (const auto& [deg, mm] : profile) {
      e.profile_angle_rad.push_back(deg * std::numbers::pi / 180.0);
      e.profile_slot_m.push_back(mm * kMm);
    }
    for (std::size_t i = 1; i < profile.size(); ++i)
      t->check(profile[i].first > profile[i - 1].first && profile[i].second > profile[i - 1].second,
               "profile", "angle and slot must both strictly increase (the profile is inverted)");
    t->check(profile.size() >= 2, "profile", "at least two points expected");
  } else {
    // Shop units here: the circular profile is built from them (default: max_slot_mm / 2).
    double ecc_mm = a.regulator.max_slot_m / 2e-3;
    double base_mm = 0.0;
    t->read({.key = "eccentricity_mm",
             .range = {0.0, 10.0, true, false},
             .doc = "circular profile (default max_slot_mm/2)",
             .derived = "regulator.max_slot_mm/2"},
            ecc_mm);
    t->read({"base_slot_mm", Range::closed(0, 10), "slot at angle 0 (circular profile)"}, base_mm);
    drives::EccentricDrive::circular_profile(base_mm * kMm, ecc_mm * kMm, 91, e);
  }
  t->read({"gear_ratio", {0.0, 1e5, true, false}, "motor turns per eccentric turn"}, e.gear_ratio);
  t->read({"motor_max_speed_rpm",
           {0.0, 1e5, true, false},
           "motor speed limit",
           2.0 * std::numbers::pi / 60.0},
          e.motor_max_speed_rad_per_s);
  t->read({"motor_time_constant_ms", Range::closed(0, 10000), "motor time constant", kMs},
          e.motor_time_constant_s);
  t->read({"position_gain_per_s", {0.0, 1e5, true, false}, "K_v: eccentric speed per rad of error"},
          e.position_gain_per_s);
  t->finish();
}

void read_slide(TableReader& root, RigConfig& a) {
  auto s = root.table("slide", true);
  root.document("slide", "slide 2, cylinder 3 and damper 6");
  auto& p = a.slide;
  s->require({"piston_area_cm2", {0.0, 1e4, true, false}, "F", 1e-4}, p.piston_area_m2);
  s->require({"dead_volume_cm3", {0.0, 1e6, true, false}, "chamber and line volume at x = 0", kCm3},
             p.dead_volume_m3);
  s->read({"oil_bulk_modulus_MPa", Range::closed(100, 1e5), "B of the oil", kMPa},
          p.bulk_modulus_Pa);
  // Converted as before the described reader (× cm³ ÷ 60 ÷ MPa, not × one factor): the same bits.
  double leak = p.leak_m3_per_s_Pa / (kCm3 / 60.0 / kMPa);
  s->read({"leak_cm3_per_min_per_MPa", Range::closed(0, 1e5), "K_leak: q_leak = K_leak·p_cylinder"},
          leak);
  if (s->has("leak_cm3_per_min_per_MPa")) p.leak_m3_per_s_Pa = leak * kCm3 / 60.0 / kMPa;
  s->read(
      {"damper_capacitance_cm3_per_MPa", Range::closed(0, 1e6), "0 means no damper", kCm3 / kMPa},
      p.damper_capacitance_m3_per_Pa);
  s->read({"damper_resistance_MPa_s_per_cm3", Range::closed(0, 1e6),
           "must be > 0 when there is a damper", kMPa / kCm3},
          p.damper_resistance_Pa_s_per_m3);
  s->check(!(p.damper_capacitance_m3_per_Pa > 0.0) || p.damper_resistance_Pa_s_per_m3 > 0.0,
           "damper_resistance_MPa_s_per_cm3", "a damper needs a resistance > 0");
  s->require({"mass_kg", {0.0, 1e5, true, false}, "slide and tool"}, p.mass_kg);
  s->read({"coulomb_friction_N", Range::closed(0, 1e6), "with stiction"}, p.coulomb_friction_N);
  s->read({"viscous_friction_N_s_per_m", Range::closed(0, 1e9), "viscous friction b"},
          p.viscous_friction_N_s_per_m);
  s->finish();
}

void read_sensor(TableReader& root, RigConfig& a, std::uint64_t seed) {
  auto s = root.table("sensor", true);
  root.document("sensor", "inductive sensor Д");
  auto& p = a.sensor;
  s->require({"holder_stiffness_N_per_um", {0.0, 1e6, true, false}, "δ = Py/k", 1e6},
             p.holder_stiffness_N_per_m);
  s->require({"gain_V_per_um", {0.0, 1e3, true, false}, "U_D rises with Py", 1e6}, p.gain_V_per_m);
  s->read({"offset_V", Range::closed(-100, 100), "U_D at zero force"}, p.offset_V);
  s->read({"noise_mV", Range::closed(0, 1e4), "σ per sample", 1e-3}, p.noise_V);
  s->read({"time_constant_ms", Range::closed(0, 1e4), "sensor lag τ_s", kMs}, p.time_constant_s);
  s->read({"saturation_V", {0.0, 1000.0, true, false}, "the output is clamped to [0, saturation]"},
          p.saturation_V);
  p.seed = seed ^ 0x9E3779B97F4A7C15ULL;
  s->finish();
}

// read_controller() in phases, in the order it reads the keys.

// The regulation: mode, programmed feed, force setpoint, control period, filters and PI.
void read_regulation(TableReader& c, RigConfig& a) {
  auto& p = a.controller;
  p.mode = c.pick({"mode", {}, "finishing holds the feed, roughing the force"},
                  {"finishing", "roughing"}, "finishing") == "roughing"
               ? PulseFeedController::Mode::Roughing
               : PulseFeedController::Mode::Finishing;
  c.require(
      {"feed_mm_per_min", {0.0, 1e5, true, false}, "programmed feed, from the ЗПУ", kMm / 60.0},
      p.feed_m_per_s);
  if (p.mode == PulseFeedController::Mode::Roughing || c.is_describing())
    c.require({"force_set_N",
               {0.0, 1e6, true, false},
               "roughing only, and required there; an unknown key in finishing"},
              p.force_set_N);
  c.read({"period_ms", {0.0, 1000.0, true, false}, "control period", kMs}, p.period_s);
  c.read({"leak_estimate_factor", Range::closed(0, 10),
          "the controller's K_leak as a multiple of the plant's"},
         a.leak_estimate_factor);
  c.read({"force_filter_ms", Range::closed(0, 1e4), "low-pass on the force estimate", kMs},
         p.force_filter_s);
  c.read({"compensate_compliance", {}, "finishing: add C·dP̂/dt/F (beyond the seed)"},
         a.compensate_compliance);
  c.read({"rate_filter_ms", Range::closed(0, 1e4), "low-pass on the force rate of that term", kMs},
         p.rate_filter_s);
  c.read({"kp", Range::closed(0, 100), "roughing PI: gain"}, p.kp);
  c.read({"ti_s", Range::closed(0, 100), "roughing PI: integral time"}, p.ti_s);
  c.read({"feed_min_fraction",
          {0.0, 1.0, false, true},
          "roughing: lowest feed as a fraction of the programmed feed"},
         p.feed_min_fraction);
}

// What the actuator may be driven to: AIM's slot, FIM's frequency and its ramp, the duty.
void read_actuator_range(TableReader& c, RigConfig& a) {
  auto& p = a.controller;
  c.read({"slot_min_mm", Range::closed(0, 10), "AIM: smallest slot", kMm}, p.slot_min_m);
  p.slot_max_m = a.regulator.max_slot_m;
  c.read({.key = "slot_max_mm",
          .range = {0.0, 10.0, true, false},
          .doc = "AIM: largest slot (default max_slot_mm)",
          .scale = kMm,
          .derived = "regulator.max_slot_mm"},
         p.slot_max_m);
  c.read({"frequency_min_Hz", Range::closed(0, 1e4), "FIM: lowest frequency"}, p.frequency_min_Hz);
  c.read({"frequency_max_Hz", {0.0, 1e4, true, false}, "FIM: highest frequency"},
         p.frequency_max_Hz);
  c.read({"frequency_ramp_Hz_per_s", {0.0, 1e7, true, false}, "converter ПЧ ramp"},
         p.frequency_ramp_Hz_per_s);
  c.read({"duty_max", {0.0, 1.0, true, false}, "f·Δt limit"}, p.duty_max);
}

// The plausible sensor range and the stuck-sensor check.
void read_sensor_monitor(TableReader& c, RigConfig& a) {
  auto& p = a.controller;
  auto& mon = p.sensor_monitor;
  c.read({"sensor_min_V", Range::any(), "plausible sensor range: lowest"}, mon.min);
  mon.max = a.sensor.saturation_V + 0.5;
  c.read({"sensor_max_V", Range::any(),
          "plausible sensor range: highest (default saturation_V + 0.5)"},
         mon.max);
  c.read({"sensor_stuck_ms", Range::closed(0, 1e5), "unchanged this long: stuck", kMs},
         mon.stuck_time_s);
  c.read(
      {"sensor_stuck_tolerance_V", Range::closed(0, 10), "a change at or below it counts as none"},
      mon.stuck_tolerance);
  mon.noise_sigma = a.sensor.noise_V;  // scale of the suspect (frozen) check
}

// The machine side around the controller: roughing's tool alarms (control::SlideMachine).
void read_tool_alarms(TableReader& c, RigConfig& a) {
  const auto& p = a.controller;
  auto& m = a.machine;
  c.read({"overload_factor",
          {1.0, 1e6, true, false},
          "roughing: overload alarm above this × force_set_N …"},
         m.overload_factor);
  c.read({"overload_time_ms", Range::closed(0, 1e5), "… for longer than this", kMs},
         m.overload_time_s);
  c.read({"breakage_drop",
          {0.0, 1e6, true, false},
          "roughing: breakage alarm when the force falls by this × force_set_N …"},
         m.breakage_drop);
  m.breakage_window_s = std::max(m.breakage_window_s, p.period_s);
  c.read({"breakage_window_ms",
          {0.0, 1e4, true, false},
          "… within this (1 … 255 control periods; default 10 ms or one period)",
          kMs},
         m.breakage_window_s);
  c.check(m.breakage_window_s >= p.period_s * (1 - 1e-9) &&
              m.breakage_window_s <= p.period_s * 255.0 * (1 + 1e-9),
          "breakage_window_ms", "must span 1 … 255 control periods");
}

// The laws along the travel (control::SlideMachine): the feed's and the force setpoint's.
void read_travel_laws(TableReader& c, RigConfig& a) {
  auto& m = a.machine;
  for (auto& t : c.tables("feed_law")) {
    control::SlideMachine::LawPoint pt{};
    t.require({"at_mm", Range::any(), "slide travel of the point", kMm}, pt.position_m);
    t.require({"feed_mm_per_min", {0.0, 1e5, true, false}, "finishing feed there", kMm / 60.0},
              pt.value);
    t.finish();
    m.feed_law.push_back(pt);
  }
  c.document("feed_law",
             "finishing: the programmed feed along the travel {at_mm, feed_mm_per_min}, "
             "linear between points, held beyond; at_mm strictly increasing (the seed's "
             "\"any law of h\")");
  for (auto& t : c.tables("force_law")) {
    control::SlideMachine::LawPoint pt{};
    t.require({"at_mm", Range::any(), "slide travel of the point", kMm}, pt.position_m);
    t.require({"force_N", {0.0, 1e6, true, false}, "roughing force setpoint there"}, pt.value);
    t.finish();
    m.force_law.push_back(pt);
  }
  c.document("force_law",
             "roughing: the force setpoint along the travel {at_mm, force_N}, linear between "
             "points, held beyond; at_mm strictly increasing");
  for (auto* law : {&m.feed_law, &m.force_law})
    for (std::size_t i = 1; i < law->size(); ++i)
      c.check((*law)[i].position_m > (*law)[i - 1].position_m,
              law == &m.feed_law ? "feed_law" : "force_law",
              "at_mm must increase from point to point");
}

void read_controller(TableReader& root, RigConfig& a) {
  auto c = root.table("controller", true);
  root.document("controller",
                "read even with type = \"none\" (then it only matters for [compare] and [sweep])");
  const std::string kind =
      c->pick({"type", {}, "no control, AIM (amplitude-pulse) or FIM (frequency-pulse)"},
              {"none", "aim", "fim"});
  a.controller_kind = kind == "aim"   ? ControllerKind::Aim
                      : kind == "fim" ? ControllerKind::Fim
                                      : ControllerKind::None;
  read_regulation(*c, a);
  read_actuator_range(*c, a);
  read_sensor_monitor(*c, a);
  const auto& p = a.controller;
  const auto& mon = p.sensor_monitor;
  c->check(mon.min < mon.max, "sensor_max_V", "must exceed sensor_min_V");
  c->check(p.slot_min_m < p.slot_max_m, "slot_max_mm", "must exceed slot_min_mm");
  c->check(p.frequency_min_Hz < p.frequency_max_Hz, "frequency_max_Hz",
           "must exceed frequency_min_Hz");
  // The machine side around the controller: roughing's tool alarms and the laws along the
  // travel (control::SlideMachine).
  read_tool_alarms(*c, a);
  read_travel_laws(*c, a);
  c->finish();
}

ControllerKind controller_from(const std::string& s) {
  return s == "aim" ? ControllerKind::Aim : s == "fim" ? ControllerKind::Fim : ControllerKind::None;
}

void read_options(TableReader& root, Settings& st) {
  auto& a = st.rig;
  if (auto m = root.table("metrics")) {
    root.document("metrics", "how the metrics are taken");
    m->read({"feed_window_s",
             {0.0, 100.0, true, false},
             "window of the reported feed rate, rounded to whole pulse periods"},
            a.feed_window_s);
    m->finish();
  }
  if (auto cmp = root.table("compare")) {
    root.document("compare", "a second run with another controller and/or regulator, overlaid");
    Comparison c;
    const std::string ctl =
        cmp->pick({"controller", {}, "a second run with this controller, overlaid in the report"},
                  {"none", "aim", "fim"}, "");
    if (!ctl.empty()) c.controller = controller_from(ctl);
    const std::string reg =
        cmp->pick({"regulator", {}, "… or with this regulator; give at least one of the two"},
                  {"pulsed", "throttle"}, "");
    if (!reg.empty())
      c.regulator = reg == "throttle" ? RegulatorKind::Throttle : RegulatorKind::Pulsed;
    cmp->check(c.controller || c.regulator, "controller",
               "give controller and/or regulator to compare with");
    c.label = cmp->string("label", "");
    cmp->document("label", "the second run's name in the report (default: its controller)");
    cmp->finish();
    st.compare = c;
  }
  if (auto sw = root.table("sweep")) {
    root.document("sweep", "reruns with the controller's K_leak estimate off by factors");
    st.sweep_leak_estimate_factor = sw->numbers(
        {"leak_estimate_factor", Range::closed(0, 10),
         "controller K_leak / true K_leak for each extra run of the sweep"},
        1);
    sw->document("leak_estimate_factor",
        "reruns with the controller's K_leak off by these factors");
    sw->check(a.controller_kind != ControllerKind::None, "leak_estimate_factor",
              "a sweep of the controller's K_leak needs a controller");
    sw->finish();
  }
  if (auto ob = root.table("obliteration_study")) {
    root.document("obliteration_study",
                  "the regulators alone over the run: flow drift against the share of the layer a "
                  "closing stroke removes");
    st.obliteration_removal = ob->numbers(
        {"removal_per_stroke", Range::closed(0, 1), "shares η to run, each a regulator pair"}, 1);
    st.obliteration_layer_m = ob->numbers(
        {"layer_um", {0.0, 100.0, true, false},
         "layers δ_max per wall to run with no sweeping at all (η = 0): where the advantage ends",
         kUm});
    ob->check(a.regulator.obliteration.layer_max_m > 0.0, "removal_per_stroke",
              "needs [regulator.obliteration] with layer_um > 0");
    ob->finish();
  }
  if (auto tol = root.table("tolerance")) {
    root.document("tolerance",
                  "Monte Carlo of manufacturing errors through the pulsed regulator and a "
                  "continuous throttle set for the same flow");
    ToleranceStudy t;
    tol->read({"samples", Range::closed(10, 100000), "regulators drawn"}, t.samples);
    tol->read({"slot_error_um", Range::closed(0, 100),
               "σ of the slot/gap opening error (the same machining error for both)", kUm},
              t.slot_sigma_m);
    tol->read({"diameter_error_um", Range::closed(0, 1000), "σ of the spool diameter error", kUm},
              t.diameter_sigma_m);
    tol->read({"discharge_coefficient_error_pct", Range::closed(0, 50),
               "σ of μ (edge sharpness, burrs), % of μ", 0.01},
              t.mu_sigma);
    tol->read({"lap_error_um", Range::closed(0, 100),
               "σ of the spool overlap (pulsed regulator only; clipped at 0)", kUm},
              t.lap_sigma_m);
    tol->read({"switching_time_error_pct", Range::closed(0, 100),
               "σ of the opening and closing times (pulsed regulator only), %", 0.01},
              t.switching_sigma);
    tol->read({"flow_tolerance_pct", {0.0, 100.0, true, false},
               "flow (feed) error a regulator may make: the pass mark of each sample", 0.01},
              t.flow_tolerance);
    tol->finish();
    st.tolerance = t;
  }
  a.faults = io::read_faults(root);
  root.document("fault", "sensor faults to inject");
}

}  // namespace

const std::array<io::CriterionKey, 3> kAcceptanceKeys{{
    {"max_feed_deviation_pct", "largest feed deviation after the disturbance (finishing)", false,
     5.0, Range::closed(0, 1000),
     "finishing mode: largest |S − S_ref|/S_ref of the feed after the tool meets the first "
     "disturbance, transient included, % (default 5; not judged in roughing, whose law lowers "
     "the feed on purpose)"},
    {"max_force_over_set_pct", "largest force above its set value (roughing)", false, 25.0,
     Range::closed(0, 1000),
     "roughing mode: largest cutting force Py above controller.force_set_N, the transient of a "
     "disturbance included, % (default 25: the slide answers a step in about a second; not "
     "judged in finishing)"},
    {"max_size_error_um", "steady diameter error from the holder's deflection", false, 0.0,
     Range::closed(0, 1e4),
     "largest |steady diameter error| 2·ΔPy/k the holder's deflection leaves after the "
     "disturbance (0: not judged, the default)"},
}};

std::unique_ptr<io::SystemSettings> read_settings(TableReader& root, io::Scenario& sc,
                                                  const io::MaterialLibrary& lib) {
  auto st = std::make_unique<Settings>();
  auto& a = st->rig;
  read_cutting(root, lib, a, sc.run.seed);
  read_regulator(root, a);
  read_eccentric(root, a);
  read_slide(root, a);
  read_sensor(root, a, sc.run.seed);
  read_controller(root, a);
  read_options(root, *st);
  io::read_acceptance(root, st->acceptance);
  return st;
}

std::string controller_kind_name(ControllerKind k) {
  switch (k) {
    case ControllerKind::Aim:
      return "AIM (amplitude-pulse)";
    case ControllerKind::Fim:
      return "FIM (frequency-pulse)";
    case ControllerKind::None:
      return "no control";
  }
  return "?";
}

std::string regulator_kind_name(RegulatorKind k) {
  return k == RegulatorKind::Throttle ? "continuous throttle" : "pulsed regulator";
}

}  // namespace lathectl::systems::a_pulse_feed
