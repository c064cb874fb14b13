// lathectl.ModulationMachine: system B's machine side (control::ModulationMachine: seed 001's
// vibration chain, power chain and feed-modulation planner), configured by
// b_chatter::machine_params from a scenario with what this host adds (b_chatter::Host: its
// periods, how the feed reaches the turret, the ceiling), as rig B and lathectl_modfeed
// configure it. Three calls as the machine has them: sense() every sample period, servo() every
// servo period, update() every module period. Inputs are named as lathectl_modfeed's pins, with
// their units where the pin has one.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <string>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/scenario.hpp"
#include "lathectl/sim/config_error.hpp"
#include "machine_fields.hpp"
#include "machine_states.hpp"
#include "systems/b_chatter/machine_params.hpp"
#include "systems/b_chatter/settings.hpp"

namespace lathectl::python::machines {

namespace {

using BIn = control::ModulationMachine::Input;
using BServo = control::ModulationMachine::Servo;
using BOut = control::ModulationMachine::Output;
using control::ModulationSource;
using control::Turret;
constexpr const char* kModulation = "ModulationMachine";

const InputField<BIn> kModulationIn[] = {
    LATHECTL_IN_B(
        BIn, "external_detectors", in.external_detectors,
        "a0_m and omega_d_rad_per_s come from detectors 19-20 outside (lathectl_modfeed's "
        "case) instead of the machine's own chain fed by sense() (default False)"),
    LATHECTL_IN_F(BIn, "a0_m", in.a0_m,
                  "(external) the vibration amplitude [m]; 0 below the dead zone"),
    LATHECTL_IN_F(BIn, "omega_d_rad_per_s", in.omega_d_rad_per_s,
                  "(external) the vibration frequency [rad/s]; 0 below the dead zone"),
    LATHECTL_IN_F(BIn, "spindle_power_W", in.motor_power_W,
                  "the main motor's active power [W] (sensor 11)"),
    LATHECTL_IN_B(BIn, "idle_block", in.idle_block,
                  "the NC block is flagged idle: its power is stored as the idle power"),
    LATHECTL_IN_F(BIn, "spindle_rpm", in.rpm, "the spindle speed [rpm]"),
    LATHECTL_IN_F(BIn, "speed_m_per_min", in.speed_m_per_min, "the cutting speed V [m/min]"),
    LATHECTL_IN_F(BIn, "requested_vel", in.feed_requested,
                  "the block's feed: the F word [mm/rev] (feed_per_rev_mode) or the path "
                  "velocity [mm/s]"),
    LATHECTL_IN_B(BIn, "feed_per_rev_mode", in.feed_per_rev, "the program runs G95"),
    LATHECTL_IN_F(BIn, "feed_rpm", in.feed_rpm, "the speed [rpm] a G95 feed is converted at"),
    LATHECTL_IN_I(BIn, "turrets", in.turrets, "turrets feeding: 2, or 1 (the right one alone)"),
    LATHECTL_IN_F(BIn, "path_right_mm", in.path_mm[0], "the path the right turret travelled [mm]"),
    LATHECTL_IN_F(BIn, "path_left_mm", in.path_mm[1], "the path the left turret travelled [mm]"),
    LATHECTL_IN_B(BIn, "feed_block", in.feed_block, "a cutting block is active"),
    LATHECTL_IN_IX(BIn, "source", in.source = static_cast<ModulationSource>(std::clamp(i, 0, 2)),
                   static_cast<int>(in.source),
                   "0 no modulation, 1 programmed, 2 automatic (default: the scenario's)"),
    LATHECTL_IN_BX(BIn, "turret_left", in.turret = b ? Turret::Left : Turret::Right,
                   in.turret == Turret::Left, "the block's turret flag (default: the scenario's)"),
    LATHECTL_IN_F(BIn, "prog_s_min_mm_per_min", in.programmed.s_min_mm_per_min,
                  "(programmed) S_min [mm/min] (default: the scenario's)"),
    LATHECTL_IN_F(BIn, "prog_ds_mm_per_min", in.programmed.ds_mm_per_min,
                  "(programmed) dS [mm/min]"),
    LATHECTL_IN_F(BIn, "prog_dl_mm", in.programmed.dl_mm, "(programmed) dl [mm]"),
    LATHECTL_IN_I(BIn, "prog_n_s", in.programmed.n_s, "(programmed) n_s"),
};

const InputField<BServo> kServoIn[] = {
    LATHECTL_IN_F(BServo, "dt_s", in.dt_s, "this servo period [s] (default: period_s)"),
    LATHECTL_IN_B(BServo, "on", in.on, "the module runs (default True)"),
    LATHECTL_IN_B(BServo, "feed_block", in.feed_block, "a feed (G1, arc) block is active"),
    LATHECTL_IN_BX(BServo, "turret_left", in.turret = b ? Turret::Left : Turret::Right,
                   in.turret == Turret::Left, "the block's turret flag (default: the scenario's)"),
    LATHECTL_IN_F(BServo, "path_velocity_mm_per_s", in.path_velocity_mm_per_s,
                  "(output 'factor') the velocity along the path [mm/s]"),
    LATHECTL_IN_F(BServo, "planned_right_mm", in.planned_mm[0],
                  "(output 'offset') the right turret's axis's planned position [mm]"),
    LATHECTL_IN_F(BServo, "planned_left_mm", in.planned_mm[1],
                  "(output 'offset') the left turret's axis's planned position [mm]"),
    LATHECTL_IN_F(BServo, "applied_offset_right_mm", in.applied_offset_mm[0],
                  "(output 'offset') the offset the right axis applies [mm]"),
    LATHECTL_IN_F(BServo, "applied_offset_left_mm", in.applied_offset_mm[1],
                  "(output 'offset') the offset the left axis applies [mm]"),
};

#define F(key, expr, doc) LATHECTL_OUT_F(BOut, key, expr, doc)
const OutputField<BOut> kModulationOut[] = {
    F("feed_right_mm_per_min", o.feed_mm_per_min[0],
      "the feed to the right turret's drive [mm/min]"),
    F("feed_left_mm_per_min", o.feed_mm_per_min[1], "the feed to the left turret's drive [mm/min]"),
    F("s_min_mm_per_min", o.plan.s_min_mm_per_min, "the running plan's S_min [mm/min]"),
    F("ds_mm_per_min", o.plan.ds_mm_per_min, "the running plan's dS [mm/min]"),
    F("dl_mm", o.plan.dl_mm, "the running plan's dl [mm]"),
    LATHECTL_OUT_I(BOut, "n_s", o.plan.n_s, "the running plan's n_s (0: none)"),
    LATHECTL_OUT_B(BOut, "engaged", o.engaged, "a modulation is running"),
    F("omega_m_rad_per_s", o.omega_m_rad_per_s, "the modulation frequency [rad/s]"),
    F("force_amplitude_required_N", o.force_amplitude_required_N,
      "c*a0*m_d*|w_d^2 - w_m^2|, what the quenching condition asks [N]"),
    F("force_amplitude_planned_N", o.force_amplitude_planned_N, "A_P of the plan [N]"),
    LATHECTL_OUT_I(BOut, "reason", o.reason, "the reason code (lathectl.reason_name)"),
    F("a0_m", o.a0_m, "the vibration amplitude the planner saw [m]"),
    F("omega_d_rad_per_s", o.omega_d_rad_per_s, "the vibration frequency the planner saw [rad/s]"),
    F("cut_power_W", o.cut_power_W, "N_c = N_m - N_idle [W]"),
    F("idle_power_W", o.idle_power_W, "N_idle, the stored idle power [W]"),
    LATHECTL_OUT_B(BOut, "idle_known", o.idle_known, "an idle power is stored"),
    F("mean_feed_mm_per_min", o.mean_feed_mm_per_min, "S_p, the programmed feed over the ceiling"),
    F("factor", o.factor, "(output 'factor') S(t)/F, to motion.adaptive-feed"),
    F("feed_ratio", o.feed_ratio, "S(t)/S_p, 1 while not modulating"),
    F("offset_mm", o.offset_mm, "(output 'offset') the external offset asked [mm]"),
    F("axis_vel_mm_per_s", o.axis_vel_mm_per_s, "(output 'offset') the flagged axis's velocity"),
};
#undef F

const Keywords& modulation_keywords() {
  static const Keywords k = keywords_of<BIn>(kModulationIn);
  return k;
}
const Keywords& servo_keywords() {
  static const Keywords k = keywords_of<BServo>(kServoIn);
  return k;
}

// What this host adds (b_chatter::Host); unset: the Host's defaults (the rig's).
struct ModulationHost {
  std::string output = "drives";
  double ceiling = 1.0;
  std::optional<double> module_period_s, sample_period_s;
};

std::shared_ptr<ModulationState> make_modulation(const std::optional<std::string>& text,
                                                 const std::string& label,
                                                 const ModulationHost& h) {
  auto s = std::make_shared<ModulationState>();
  without_gil("ModulationMachine", false, [&] {
    namespace b_chatter = systems::b_chatter;
    using FO = control::ModulationMachine::FeedOutput;
    auto sc = std::make_shared<io::Scenario>(scenario_of(text, label, "B", kModulation));
    const auto& b = sc->get<b_chatter::Settings>().rig;
    b_chatter::Host host;
    if (h.output != "drives" && h.output != "factor" && h.output != "offset")
      throw io::InputError("ModulationMachine: output='" + h.output +
                           "': expected 'drives', 'factor' or 'offset'");
    host.output = h.output == "factor"   ? FO::Factor
                  : h.output == "offset" ? FO::Offset
                                         : FO::Drives;
    host.ceiling = h.ceiling;
    if (h.module_period_s) host.module_period_s = *h.module_period_s;
    if (h.sample_period_s) host.sample_period_s = *h.sample_period_s;
    try {
      s->m.configure(b_chatter::machine_params(b, host));
    } catch (const std::invalid_argument& e) {
      io::throw_at_key(*sc, e, "modulation");
    }
    s->in.source = b.source;  // as lathectl_modfeed's pins start: the scenario's block
    s->in.turret = b.turret;
    s->in.programmed = b.programmed;
    s->servo.turret = b.turret;
    s->servo.dt_s = s->m.params().module.period_s;
    s->name = sc->name;
    s->sc = std::move(sc);
  });
  return s;
}

py::object view(ModulationState& s) {
  return view_of(s, &s.m.output(), s.view);
}

void sense_many(ModulationState& s,
                const py::array_t<double, py::array::c_style | py::array::forcecast>& x) {
  if (x.ndim() != 1)
    throw py::value_error("ModulationMachine.sense_many: a 1-D array of displacements [m]");
  const double* p = x.data();
  for (py::ssize_t i = 0; i < x.shape(0); ++i) s.m.sense(p[i]);
}

struct ModulationUpdate {
  using State = ModulationState;
  using In = BIn;
  static constexpr const char* name = "ModulationMachine.update";
  static std::span<const InputField<In>> fields() { return kModulationIn; }
  static const Keywords& keywords() { return modulation_keywords(); }
  static In& input(State& s) { return s.in; }
  static py::object run(State& s) {
    s.m.update(s.in);
    return view(s);
  }
};
struct ModulationServo {
  using State = ModulationState;
  using In = BServo;
  static constexpr const char* name = "ModulationMachine.servo";
  static std::span<const InputField<In>> fields() { return kServoIn; }
  static const Keywords& keywords() { return servo_keywords(); }
  static In& input(State& s) { return s.servo; }
  static py::object run(State& s) {
    s.m.servo(s.servo);
    return view(s);
  }
};

}  // namespace

void bind_modulation(py::module_& m) {
  bind_outputs<ModulationState, BOut>(
      m, "ModulationOutputs", "ModulationMachine's outputs (live: they change with each call)",
      kModulationOut);
  static const std::string update_doc =
      "update($self, /, **inputs)\n--\n\n"
      "update(**inputs) -> ModulationOutputs: one module period (period_s). Inputs not given "
      "keep their last value (as HAL pins do):\n" +
      modulation_keywords().doc;
  static const std::string servo_doc =
      "servo($self, /, **inputs)\n--\n\n"
      "servo(**inputs) -> ModulationOutputs: one servo period, before update() in a period that "
      "runs the module (the turret the output acts on, the path, the external offset). Inputs "
      "not given keep their last value:\n" +
      servo_keywords().doc;
  auto c = py::class_<ModulationState, std::shared_ptr<ModulationState>>(m, "_ModulationMachine");
  def_keyword_method<ModulationUpdate>(c, "update", update_doc);
  def_keyword_method<ModulationServo>(c, "servo", servo_doc);
  c.def(py::init([](const std::optional<std::string>& text, const std::string& label,
                    const std::string& output, double ceiling,
                    std::optional<double> module_period_s, std::optional<double> sample_period_s) {
          return make_modulation(text, label, {output, ceiling, module_period_s, sample_period_s});
        }),
        py::arg("text"), py::arg("label"), py::arg("output") = "drives", py::arg("ceiling") = 1.0,
        py::arg("module_period_s") = py::none(), py::arg("sample_period_s") = py::none())
      .def(
          "sense", [](ModulationState& s, double y) { s.m.sense(y); }, py::arg("displacement_m"),
          "One sample of the vibration sensor (every sample_period_s): the part's displacement "
          "at the tool [m].")
      .def("sense_many", &sense_many, py::arg("displacement_m"),
           "sense() for each sample of a 1-D array [m], in order.")
      .def_property_readonly("outputs", &view)
      .def_property_readonly(
          "inputs", [](const ModulationState& s) { return inputs_dict<BIn>(s.in, kModulationIn); })
      .def_property_readonly(
          "servo_inputs",
          [](const ModulationState& s) { return inputs_dict<BServo>(s.servo, kServoIn); })
      .def_property_readonly("period_s",
                             [](const ModulationState& s) { return s.m.params().module.period_s; })
      .def_property_readonly(
          "sample_period_s",
          [](const ModulationState& s) { return s.m.params().vibration.sample_period_s; })
      .def_property_readonly("name", [](const ModulationState& s) { return s.name; })
      .def_property_readonly("turret_left",
                             [](const ModulationState& s) { return s.m.turret() == Turret::Left; })
      .def_property_readonly("path_mm", [](const ModulationState& s) { return s.m.path_mm(); })
      .def_property_readonly("chain_a0_m",
                             [](const ModulationState& s) { return s.m.chain().a0_m(); })
      .def_property_readonly("chain_omega_d_rad_per_s",
                             [](const ModulationState& s) { return s.m.chain().omega_d(); });
}

}  // namespace lathectl::python::machines
