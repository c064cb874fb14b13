// lathectl.AdaptiveMachine: system E's machine side (control::AdaptiveMachine), configured by
// e_adaptive::machine_params from a scenario with what this host adds (MachineHost: the load,
// the stock model's origin, the program's feed, a tool table and taught references), as the
// rig, lathectl_adaptive and `lathectl optimize` configure it. Inputs are named as
// lathectl_adaptive's pins, with their units where the pin has one.
#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <optional>
#include <string>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/scenario.hpp"
#include "machine_fields.hpp"
#include "machine_states.hpp"
#include "systems/e_adaptive/machine_params.hpp"
#include "systems/e_adaptive/settings.hpp"
#include "systems/e_adaptive/tool_limits.hpp"

namespace lathectl::python::machines {

namespace {

using EIn = control::AdaptiveMachine::Input;
using EOut = control::AdaptiveMachine::Output;
constexpr const char* kAdaptive = "AdaptiveMachine";

const InputField<EIn> kAdaptiveIn[] = {
    LATHECTL_IN_F(EIn, "period_s", in.nominal_period_s,
                  "the servo period update() runs at [s] (default: the scenario's run.step_s)"),
    LATHECTL_IN_F(EIn, "elapsed_s", in.elapsed_s,
                  "time measured since the last call [s]; 0: period_s (default 0)"),
    LATHECTL_IN_B(EIn, "enable", in.enable, "adaptive control on (default True)"),
    LATHECTL_IN_B(EIn, "reset", in.reset, "a rising edge clears the latched alarms"),
    LATHECTL_IN_F(EIn, "force", in.force,
                  "sensor 4's reading in the load's unit (load_unit: N, or W for a power "
                  "parameter)"),
    LATHECTL_IN_F(EIn, "spindle_power_W", in.spindle_power_W,
                  "the spindle drive's electrical power [W] (the load with sensor='power')"),
    LATHECTL_IN_F(EIn, "spindle_rpm", in.rpm, "the measured spindle speed [rpm] (sign ignored)"),
    LATHECTL_IN_F(EIn, "spindle_rpm_programmed", in.rpm_programmed,
                  "the program's S [rpm], signed: the direction"),
    LATHECTL_IN_F(EIn, "current_vel_mm_per_s", in.current_vel_mm_s,
                  "the path's measured velocity [mm/s] (motion.current-vel)"),
    LATHECTL_IN_F(EIn, "requested_vel", in.requested_vel,
                  "motion.requested-vel: the F word [mm/rev] under G95 (straight moves), [mm/s] "
                  "under G94"),
    LATHECTL_IN_F(EIn, "feed_upm", in.feed_upm,
                  "motion.feed-upm: the move's F times motion's net feed scale [mm/min]"),
    LATHECTL_IN_I(EIn, "motion_type", in.motion_type,
                  "motion.motion-type: 0 none, 1 traverse, 2 feed, 3 arc (2 and 3 cut)"),
    LATHECTL_IN_B(EIn, "feed_per_rev_mode", in.per_rev, "the program runs G95 (default True)"),
    LATHECTL_IN_F(EIn, "x_pos_mm", in.x_mm, "the tool's radius [mm]"),
    LATHECTL_IN_F(EIn, "z_pos_mm", in.z_mm, "the tool's machine z [mm]"),
    LATHECTL_IN_B(EIn, "homed", in.homed, "positions mean something (default True)"),
    LATHECTL_IN_F(EIn, "cutting_speed_m_per_min", in.cutting_speed_m_per_min,
                  "a measured cutting speed V [m/min]; 0: pi*2x*n"),
    LATHECTL_IN_F(EIn, "limit_cmd", in.limit_cmd,
                  "the operation's load limit (M68 E0), in the load's unit; 0: not set"),
    LATHECTL_IN_F(EIn, "feed_min_cmd", in.feed_min_cmd,
                  "the operation's least feed [mm/rev] (M68 E1); 0: not set"),
    LATHECTL_IN_F(EIn, "feed_max_cmd", in.feed_max_cmd,
                  "the operation's largest feed [mm/rev] (M68 E2); 0: not set"),
    LATHECTL_IN_F(EIn, "mode_cmd", in.mode_cmd,
                  "the operation's mode (M68 E3): 1 off, 2 on, 3 teach, 4 taught; 0: not set"),
    LATHECTL_IN_F(EIn, "operation_cmd", in.operation_cmd,
                  "the operation's number (M68 E4); 0: not set"),
    LATHECTL_IN_I(EIn, "tool_number", in.tool_number, "the tool in the spindle's turret"),
    LATHECTL_IN_I(EIn, "program_line", in.program_line,
                  "the program's line (motion.program-line); -1: no program"),
    LATHECTL_IN_F(EIn, "tool_diameter_mm", in.tool_diameter, "the tool table's diameter [mm]"),
    LATHECTL_IN_F(EIn, "tool_offset_x_mm", in.tool_offset_x, "the tool's x offset [mm]"),
    LATHECTL_IN_F(EIn, "tool_offset_z_mm", in.tool_offset_z, "the tool's z offset [mm]"),
    LATHECTL_IN_F(EIn, "operator_override", in.knob, "the operator's feed override (default 1)"),
    LATHECTL_IN_F(EIn, "max_feed_override", in.max_override,
                  "[DISPLAY]MAX_FEED_OVERRIDE (default 1)"),
    LATHECTL_IN_F(EIn, "feed_override_in_motion", in.scale_in_motion,
                  "the feed scale motion reports; 0: not wired (default)"),
};

#define F(key, expr, doc) LATHECTL_OUT_F(EOut, key, expr, doc)
#define B(key, expr, doc) LATHECTL_OUT_B(EOut, key, expr, doc)
#define I(key, expr, doc) LATHECTL_OUT_I(EOut, key, expr, doc)
const OutputField<EOut> kAdaptiveOut[] = {
    F("adaptive_feed", o.adaptive_feed, "to motion.adaptive-feed, 0 … 1"),
    F("feed_override", o.feed_override, "motion's feed scale to command"),
    I("feed_override_counts", o.feed_override_counts, "the feed scale in halui's counts"),
    F("feed_factor", o.feed_factor, "the net override of the program's feed"),
    F("spindle_speed_out", o.spindle_speed_out, "the spindle speed command [rpm]"),
    F("spindle_override", o.spindle_override, "the spindle override"),
    B("feed_hold", o.feed_hold, "the feed is held"),
    B("alarm", o.alarm, "an alarm is latched (until a reset)"),
    I("reason", o.reason, "the reason code (lathectl.reason_name)"),
    I("alarm_reason", o.alarm_reason, "the latched alarm's reason code"),
    F("feed_per_rev_mm", o.feed_per_rev_mm, "the controller's feed [mm/rev]"),
    F("speed_cmd_m_per_min", o.speed_cmd_m_per_min, "the cutting speed commanded [m/min]"),
    F("speed_opt_m_per_min", o.speed_opt_m_per_min, "the speed law's V_opt [m/min]"),
    F("depth_estimate_mm", o.depth_estimate_mm, "the depth of cut estimated [mm]"),
    F("cut_power_W", o.cut_power_W, "the cutting power [W]"),
    B("in_cut", o.in_cut, "the regulator is in the cut"),
    B("contact", o.contact, "the tool is in the material (every mode)"),
    B("period_error", o.period_error,
      "the control period is not a whole number of servo periods (the feed holds)"),
    F("load", o.load, "what the controller sees, in the load's unit"),
    F("limit", o.limit, "the load limit in force"),
    F("feed_min", o.feed_min, "the least feed in force [mm/rev]"),
    F("feed_max", o.feed_max, "the largest feed in force [mm/rev]"),
    B("adaptive_on", o.adaptive_on, "the operation's mode regulates"),
    B("teaching", o.teaching, "a teach-in cut is running"),
    F("idle_power_W", o.idle_power_W, "the spindle's idle power now [W]"),
    B("tare_ready", o.tare_ready, "the idle law is learned near this speed"),
    F("acceleration_power_W", o.acceleration_power_W, "J*w*dw/dt, lagged as the meter [W]"),
    F("inertia_kg_m2", o.inertia_kg_m2, "the spindle's inertia in use [kg m^2]"),
    B("inertia_learned", o.inertia_learned, "the inertia is learned"),
    B("bad_setting", o.bad_setting, "a per-operation setting was refused"),
    I("bad_code", o.bad_code, "which setting was refused and why (0: none)"),
    I("bad_line", o.bad_line, "the program line of the refused setting"),
    F("bad_value", o.bad_value, "the refused value"),
    B("overload_warn", o.overload_warn, "the load is above the warning level"),
    B("overload_hold", o.overload_hold, "the load is above the hold level"),
    F("load_rev", o.load_rev, "the load's per-revolution mean"),
    F("load_percent", o.load_percent, "load_rev in percent of the reference"),
    F("predicted_depth_mm", o.predicted_depth_mm, "the stock model's depth at the tool [mm]"),
    F("depth_ahead_mm", o.depth_ahead_mm, "the stock model's depth ahead of the tool [mm]"),
    F("feed_ceiling_mm_per_rev", o.feed_ceiling_mm_per_rev,
      "the feed-forward's ceiling [mm/rev]; 0: none"),
    F("specific_force_ratio", o.specific_force_ratio, "kappa: measured load over the law's"),
    F("hardness_estimate", o.hardness_estimate, "h = kappa^(1/kmp)"),
    B("breakage", o.breakage, "tool breakage detected"),
    B("tool_data_changed", o.tool_data_changed, "tool data changed inside a feed move"),
    B("control_period", o.control_period, "this call ran the control law"),
    I("op_seq", o.op.seq, "the operation records published (see op)"),
    I("teach_seq", o.teach.seq, "the teach-in records published (see teach)"),
};
#undef F
#undef B
#undef I

const Keywords& adaptive_keywords() {
  static const Keywords k = keywords_of<EIn>(kAdaptiveIn);
  return k;
}

// What this host adds to the scenario (e_adaptive::MachineHost); unset: the rig's choice.
struct AdaptiveHost {
  std::optional<std::string> sensor;        // "force" | "power"; unset: the scenario's parameter
  std::optional<double> z_origin_mm = 0.0;  // unset (None): no stock model
  std::optional<double> feed_programmed_mm_per_rev;
  std::optional<std::string> tools, taught;  // files
  std::optional<double> period_s;
};

std::shared_ptr<AdaptiveState> make_adaptive(const std::optional<std::string>& text,
                                             const std::string& label, const AdaptiveHost& h) {
  auto s = std::make_shared<AdaptiveState>();
  without_gil("AdaptiveMachine", false, [&] {
    namespace e_adaptive = systems::e_adaptive;
    auto sc = std::make_shared<io::Scenario>(scenario_of(text, label, "E", kAdaptive));
    const auto& e = sc->get<e_adaptive::Settings>().rig;
    e_adaptive::MachineHost host;
    const std::string sensor =
        h.sensor ? *h.sensor
                 : (e.force_parameter == cutting::ForceParameter::Power ? "power" : "force");
    if (sensor != "force" && sensor != "power")
      throw io::InputError("AdaptiveMachine: sensor='" + sensor + "': expected 'force' or 'power'");
    if (sensor == "power") host.load = e_adaptive::MachineHost::Load::SpindlePower;
    host.z_origin_mm = h.z_origin_mm ? *h.z_origin_mm : std::nan("");
    if (h.feed_programmed_mm_per_rev)
      host.feed_programmed_mm_per_rev = *h.feed_programmed_mm_per_rev;
    e_adaptive::ToolTable table;
    if (h.tools) {  // the files as lathectl_adaptive reads them
      table = e_adaptive::read_tool_table(io::read_scenario_text(*h.tools), *h.tools);
      host.tools = &table;
      host.tools_file = *h.tools;
    }
    if (h.taught) {
      host.taught = e_adaptive::read_taught(io::read_scenario_text(*h.taught), *h.taught);
      host.taught_file = *h.taught;
    }
    try {
      s->m.configure(e_adaptive::machine_params(e, host));
    } catch (const std::invalid_argument& x) {
      io::throw_at_key(*sc, x, "controller");
    }
    s->in.nominal_period_s = h.period_s ? *h.period_s : sc->run.step_s;
    s->load_unit = e_adaptive::load_unit(e, host);
    s->name = sc->name;
    s->sc = std::move(sc);
  });
  return s;
}

py::dict op_record(const control::AdaptiveMachine::OperationRecord& r) {
  py::dict d;
  d["seq"] = r.seq;
  d["line"] = r.line;
  d["tool"] = r.tool;
  d["operation"] = r.operation;
  d["mode"] = r.mode;
  d["limit"] = r.limit;
  d["load_mean"] = r.load_mean;
  d["load_peak"] = r.load_peak;
  d["feed_min"] = r.feed_min;
  d["feed_mean"] = r.feed_mean;
  d["time_in_cut_s"] = r.time_in_cut_s;
  d["time_s"] = r.time_s;
  d["reasons"] = r.reasons;
  d["alarm"] = r.alarm;
  return d;
}

py::object view(AdaptiveState& s) {
  return view_of(s, &s.out, s.view);
}

struct AdaptiveUpdate {
  using State = AdaptiveState;
  using In = EIn;
  static constexpr const char* name = "AdaptiveMachine.update";
  static std::span<const InputField<In>> fields() { return kAdaptiveIn; }
  static const Keywords& keywords() { return adaptive_keywords(); }
  static In& input(State& s) { return s.in; }
  static py::object run(State& s) {
    s.m.update(s.in, s.out);
    return view(s);
  }
};

}  // namespace

void bind_adaptive(py::module_& m) {
  using V = OutputView<AdaptiveState, EOut>;
  bind_outputs<AdaptiveState, EOut>(
      m, "AdaptiveOutputs", "AdaptiveMachine's outputs (live: they change with each update())",
      kAdaptiveOut)
      .def_property_readonly(
          "idle_law",
          [](const V& v) {
            return py::make_tuple(v.out->idle_law[0], v.out->idle_law[1], v.out->idle_law[2]);
          },
          "the idle power law (p0 [W], p1 [W/rpm], p2 [W/rpm^2])")
      .def_property_readonly(
          "op", [](const V& v) { return op_record(v.out->op); },
          "the last operation's record (a dict; published when op_seq changes)")
      .def_property_readonly(
          "teach",
          [](const V& v) {
            py::dict d;
            d["seq"] = v.out->teach.seq;
            d["tool"] = v.out->teach.tool;
            d["operation"] = v.out->teach.operation;
            d["reference"] = v.out->teach.reference;
            return d;
          },
          "the last teach-in's record (a dict: seq, tool, operation, reference)");
  static const std::string update_doc =
      "update($self, /, **inputs)\n--\n\n"
      "update(**inputs) -> AdaptiveOutputs: one servo period. Inputs not given keep their last "
      "value (as HAL pins do):\n" +
      adaptive_keywords().doc;
  auto c = py::class_<AdaptiveState, std::shared_ptr<AdaptiveState>>(m, "_AdaptiveMachine");
  def_keyword_method<AdaptiveUpdate>(c, "update", update_doc);
  c.def(py::init([](const std::optional<std::string>& text, const std::string& label,
                    std::optional<std::string> sensor, std::optional<double> z_origin_mm,
                    std::optional<double> feed_programmed_mm_per_rev,
                    std::optional<std::string> tools, std::optional<std::string> taught,
                    std::optional<double> period_s) {
          return make_adaptive(
              text, label,
              {sensor, z_origin_mm, feed_programmed_mm_per_rev, tools, taught, period_s});
        }),
        py::arg("text"), py::arg("label"), py::arg("sensor") = py::none(),
        py::arg("z_origin_mm") = 0.0, py::arg("feed_programmed_mm_per_rev") = py::none(),
        py::arg("tools") = py::none(), py::arg("taught") = py::none(),
        py::arg("period_s") = py::none())
      .def_property_readonly("outputs", &view)
      .def_property_readonly(
          "inputs", [](const AdaptiveState& s) { return inputs_dict<EIn>(s.in, kAdaptiveIn); })
      .def_property_readonly("period_s",
                             [](const AdaptiveState& s) { return s.in.nominal_period_s; })
      .def_property_readonly(
          "control_period_s",
          [](const AdaptiveState& s) { return s.m.params().controller.period_s; })
      .def_property_readonly("load_unit", [](const AdaptiveState& s) { return s.load_unit; })
      .def_property_readonly(
          "load_limit", [](const AdaptiveState& s) { return s.m.params().controller.load_limit; })
      .def_property_readonly(
          "feed_programmed_mm_per_rev",
          [](const AdaptiveState& s) { return s.m.params().controller.feed_programmed_mm_per_rev; })
      .def_property_readonly("name", [](const AdaptiveState& s) { return s.name; })
      .def_property_readonly("taught",
                             [](const AdaptiveState& s) {
                               py::list l;
                               for (std::size_t i = 0; i < s.m.taught_count(); ++i) {
                                 const auto& t = s.m.taught(i);
                                 py::dict d;
                                 d["tool"] = t.tool;
                                 d["operation"] = t.operation;
                                 d["reference"] = t.reference;
                                 l.append(d);
                               }
                               return l;
                             })
      .def("end_operation", [](AdaptiveState& s) {
        s.m.end_operation(s.out);
        return view(s);
      });
}

}  // namespace lathectl::python::machines
