// The machine-side objects for users' own loops: lathectl.SlideMachine (A), GaugeMachine (D)
// here, AdaptiveMachine (E) in machine_adaptive.cpp, ModulationMachine (B) in
// machine_modulation.cpp. Each is the C++ object `lathectl run`'s rig and the LinuxCNC component
// run, configured by its system's one machine_params() from a scenario read by the same reader
// as lathectl.run; this host adds what a HAL component adds (its periods, its outputs), as
// keyword options whose defaults are the rig's. The field tables (machine_fields.hpp) map
// keywords to the machine's Input and its Output to attributes.
#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <optional>
#include <string>

#include "lathectl/control/gauge_machine.hpp"
#include "lathectl/control/slide_machine.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/scenario.hpp"
#include "lathectl/sim/config_error.hpp"
#include "machine_fields.hpp"
#include "machine_states.hpp"
#include "systems/a_pulse_feed/machine_params.hpp"
#include "systems/a_pulse_feed/settings.hpp"
#include "systems/d_gauging/machine_params.hpp"
#include "systems/d_gauging/settings.hpp"

namespace lathectl::python::machines {

void bad_value(const char* cls, const char* name, PyObject* v, const char* expected) {
  PyErr_Format(PyExc_TypeError, "%s: input '%s': expected %s, not %R", cls, name, expected, v);
  throw py::error_already_set();
}

int Keywords::find(PyObject* key) const noexcept {
  for (std::size_t i = 0; i < keys.size(); ++i)
    if (keys[i] == key) return static_cast<int>(i);
  for (std::size_t i = 0; i < keys.size(); ++i)
    if (PyUnicode_Compare(keys[i], key) == 0) return static_cast<int>(i);
  PyErr_Clear();  // a key that is not a str compares as an error: not found
  return -1;
}

io::Scenario scenario_of(const std::optional<std::string>& text, const std::string& label,
                         const char* system, const char* cls) {
  io::Scenario sc = read_scenario(text, label);
  if (sc.system != system) {
    const std::string msg = "system " + sc.system + ": lathectl." + cls + " is system " + system +
                            "'s machine side (a system-" + system + " scenario is needed)";
    throw io::InputError(sc.keys ? sc.keys->locate("system", msg) : label + ": " + msg);
  }
  return sc;
}

void bind_reasons(py::module_& m) {
  m.def(
      "_reason_name",
      [](int code) {
        return std::string(control::reason_name(static_cast<control::Reason>(code)));
      },
      py::arg("code"));
  m.def("_reasons", [] {
    py::list l;
    for (const auto& r : control::kReasons) {
      py::dict d;
      d["code"] = static_cast<int>(r.code);
      d["bit"] = control::reason_index(r.code);
      d["name"] = std::string(r.name);
      d["alarm"] = r.alarm;
      d["systems"] = std::string(r.systems);
      d["meaning"] = std::string(r.meaning);
      l.append(d);
    }
    return l;
  });
}

namespace {

// ---- A: SlideMachine ------------------------------------------------------------------------

using SIn = control::SlideMachine::Input;
using SOut = control::SlideMachine::Output;
constexpr const char* kSlide = "SlideMachine";

const InputField<SIn> kSlideIn[] = {
    LATHECTL_IN_F(SIn, "sensor_V", in.sensor_V,
                  "U_D [V], the inductive sensor's voltage (lathectl_slide: sensor-in calibrated)"),
    LATHECTL_IN_B(SIn, "enable", in.enable,
                  "the slide is on (False: valve shut, reason slide_off); default True"),
    LATHECTL_IN_BX(SIn, "roughing",
                   in.mode = b ? control::SlideMachine::Mode::Roughing
                               : control::SlideMachine::Mode::Finishing,
                   in.mode == control::SlideMachine::Mode::Roughing,
                   "True roughing (hold the force), False finishing (hold the feed); default: "
                   "the scenario's controller.mode"),
    LATHECTL_IN_F(SIn, "feed_set_m_per_s", in.feed_m_per_s,
                  "the programmed feed [m/s]; <= 0 or NaN: the present one (default 0)"),
    LATHECTL_IN_F(SIn, "force_set_N", in.force_set_N,
                  "roughing's force setpoint [N]; <= 0 or NaN: the present one (default 0)"),
    LATHECTL_IN_F(SIn, "position_m", in.position_m,
                  "the slide's travel [m], where the scenario's feed and force laws are read"),
    LATHECTL_IN_B(SIn, "reset", in.reset_alarm,
                  "a rising edge (False then True) clears a latched alarm"),
};

const OutputField<SOut> kSlideOut[] = {
    LATHECTL_OUT_F(SOut, "slot_m", o.slot_m,
                   "AIM: the eccentric's slot command [m]; FIM: the slot"),
    LATHECTL_OUT_F(SOut, "frequency_Hz", o.frequency_Hz, "the pulse frequency [Hz]; 0: no pulses"),
    LATHECTL_OUT_B(SOut, "pulses", o.pulses, "the valve pulses (False: held shut)"),
    LATHECTL_OUT_F(SOut, "feed_cmd_m_per_s", o.feed_cmd_m_per_s, "the feed commanded [m/s]"),
    LATHECTL_OUT_F(SOut, "force_estimate_N", o.force_estimate_N,
                   "the force estimated from the sensor [N]"),
    LATHECTL_OUT_F(SOut, "feed_set_m_per_s", o.feed_set_m_per_s,
                   "the programmed feed in force, law included [m/s]"),
    LATHECTL_OUT_F(SOut, "force_set_N", o.force_set_N,
                   "the force setpoint in force, law included [N]"),
    LATHECTL_OUT_B(SOut, "roughing", o.mode == control::SlideMachine::Mode::Roughing,
                   "the mode in force is roughing"),
    LATHECTL_OUT_B(SOut, "enabled", o.enabled, "the slide is on"),
    LATHECTL_OUT_I(SOut, "reason", o.reason, "the reason code (lathectl.reason_name)"),
    LATHECTL_OUT_B(SOut, "alarm", o.alarm, "an alarm is latched (the feed is stopped or frozen)"),
    LATHECTL_OUT_I(SOut, "alarm_reason", o.alarm_reason, "the latched alarm's reason code"),
};

const Keywords& slide_keywords() {
  static const Keywords k = keywords_of<SIn>(kSlideIn);
  return k;
}

std::shared_ptr<SlideState> make_slide(const std::optional<std::string>& text,
                                       const std::string& label, bool machine_io) {
  auto s = std::make_shared<SlideState>();
  without_gil("SlideMachine", false, [&] {
    namespace a = systems::a_pulse_feed;
    auto sc = std::make_shared<io::Scenario>(scenario_of(text, label, "A", kSlide));
    const auto& cfg = sc->get<a::Settings>().rig;
    control::SlideMachine::Params mp;
    try {
      mp = a::machine_params(cfg, a::Host{.machine_io = machine_io});
      s->start_force_N = a::nominal_force_N(cfg);
      s->m.configure(mp);
    } catch (const std::invalid_argument& e) {
      io::throw_at_key(*sc, e, "controller");
    }
    s->m.start(s->start_force_N);
    s->in.mode = mp.controller.mode;
    s->name = sc->name;
    s->sc = std::move(sc);
  });
  return s;
}

struct SlideUpdate {
  using State = SlideState;
  using In = SIn;
  static constexpr const char* name = "SlideMachine.update";
  static std::span<const InputField<In>> fields() { return kSlideIn; }
  static const Keywords& keywords() { return slide_keywords(); }
  static In& input(State& s) { return s.in; }
  static py::object run(State& s) {
    s.m.update(s.in);
    return view_of(s, &s.m.output(), s.view);
  }
};

void bind_slide(py::module_& m) {
  bind_outputs<SlideState, SOut>(m, "SlideOutputs",
                                 "SlideMachine's outputs (live: they change with each update())",
                                 kSlideOut);
  static const std::string update_doc =
      "update($self, /, **inputs)\n--\n\n"
      "update(**inputs) -> SlideOutputs: one control period (period_s). Inputs not given keep "
      "their last value (as HAL pins do):\n" +
      slide_keywords().doc;
  auto c = py::class_<SlideState, std::shared_ptr<SlideState>>(m, "_SlideMachine");
  def_keyword_method<SlideUpdate>(c, "update", update_doc);
  c.def(py::init(&make_slide), py::arg("text"), py::arg("label"), py::arg("machine_io") = false)
      .def_property_readonly("outputs",
                             [](SlideState& s) { return view_of(s, &s.m.output(), s.view); })
      .def_property_readonly("inputs",
                             [](const SlideState& s) { return inputs_dict<SIn>(s.in, kSlideIn); })
      .def_property_readonly("period_s",
                             [](const SlideState& s) { return s.m.params().controller.period_s; })
      .def_property_readonly("name", [](const SlideState& s) { return s.name; })
      .def_property_readonly("start_force_N", [](const SlideState& s) { return s.start_force_N; })
      .def(
          "start",
          [](SlideState& s, std::optional<double> force_N) {
            s.m.start(force_N ? *force_N : s.start_force_N);
            return view_of(s, &s.m.output(), s.view);
          },
          py::arg("force_N") = py::none());
}

// ---- D: GaugeMachine ------------------------------------------------------------------------

using GIn = control::GaugeMachine::Input;
using GOut = control::GaugeMachine::Output;
constexpr const char* kGauge = "GaugeMachine";

const InputField<GIn> kGaugeIn[] = {
    LATHECTL_IN_F(GIn, "generator_V", in.generator_V,
                  "u [V], the generator's signal, one sample a period_s"),
    LATHECTL_IN_F(GIn, "position_m", in.position_m,
                  "the controlled size's position [m] on the backstop's scale (the size left "
                  "to remove, as the study's part; default +inf: never at the backstop)"),
    LATHECTL_IN_B(GIn, "rearm", in.rearm,
                  "a rising edge: a new part (steps back to rough, alarms cleared)"),
    LATHECTL_IN_B(GIn, "gate", in.gate,
                  "an interruption (keyway, flat) is under the probe: the sample is bridged"),
};

const OutputField<GOut> kGaugeOut[] = {
    LATHECTL_OUT_F(GOut, "signal_V", o.signal_V, "S [V], the filtered signal"),
    LATHECTL_OUT_I(GOut, "step", o.step, "how many steps' commands have operated"),
    LATHECTL_OUT_I(GOut, "command", o.command,
                   "the command in force: 0 rough, 1 fine, 2 spark-out, 3 size"),
    LATHECTL_OUT_B(GOut, "armed", o.armed, "the relay is armed"),
    LATHECTL_OUT_B(GOut, "tripped", o.tripped, "a threshold was crossed in this sample"),
    LATHECTL_OUT_F(GOut, "trip_time_s", o.trip_time_s,
                   "the last crossing's time since the (re)arm [s], interpolated; NaN before any"),
    LATHECTL_OUT_I(GOut, "tripped_steps", o.tripped_steps, "thresholds crossed"),
    LATHECTL_OUT_B(GOut, "size", o.size, "the size command has operated"),
    LATHECTL_OUT_B(GOut, "backstop", o.backstop, "the cut ended at the backstop"),
    LATHECTL_OUT_B(GOut, "stop", o.stop, "the cut must end now: size, backstop or an alarm"),
    LATHECTL_OUT_B(GOut, "alarm", o.alarm, "an alarm is latched until a rearm"),
    LATHECTL_OUT_B(GOut, "unreachable", o.unreachable,
                   "the next threshold is above what the free probe reads"),
    LATHECTL_OUT_F(GOut, "next_threshold_V", o.next_threshold_V, "the next threshold [V]"),
    LATHECTL_OUT_F(GOut, "time_s", o.time_s, "time since the last (re)arm [s]"),
    LATHECTL_OUT_B(GOut, "bridged", o.bridged, "this sample was bridged (gate or its guard)"),
    LATHECTL_OUT_I(GOut, "reason", o.reason, "the reason code (lathectl.reason_name)"),
};

const Keywords& gauge_keywords() {
  static const Keywords k = keywords_of<GIn>(kGaugeIn);
  return k;
}

// The host's additions to D's machine (lathectl_gauge's module parameters, the rig's defaults).
struct GaugeHost {
  std::optional<double> threshold_V, period_s, target_x_m;
  double signal_lost = 0.0;
};

std::shared_ptr<GaugeState> make_gauge(const std::optional<std::string>& text,
                                       const std::string& label, const GaugeHost& h) {
  auto s = std::make_shared<GaugeState>();
  without_gil("GaugeMachine", false, [&] {
    namespace dg = systems::d_gauging;
    auto sc = std::make_shared<io::Scenario>(scenario_of(text, label, "D", kGauge));
    const auto& d = sc->get<dg::Settings>();
    // The transducer as the run configures it, the threshold the plan gives (or the host's; not
    // aimed past the first-passage bias as lathectl_gauge's: that Monte Carlo is not run here),
    // the scenario's sequence before it on the plan's line.
    sensors::VibroContactGauge gauge;
    dg::configure_transducer(*sc, gauge);
    try {
      const auto plan = dg::plan_threshold(d, sc->run.step_s);
      const double th = h.threshold_V ? *h.threshold_V : plan.threshold_V;
      auto pr = d.process;
      pr.cycle = dg::cycle_for(d.transducer, d.sequence, plan.line, pr, th);
      dg::MachineHost host;
      if (h.period_s) host.period_s = *h.period_s;
      if (h.target_x_m) host.target_x_m = *h.target_x_m;
      host.signal_lost = h.signal_lost;
      s->m.configure(dg::machine_params(pr, gauge, th, host));
      s->rate_factor = pr.cycle.rate_factor;
      s->removal_m_per_s = pr.removal_m_per_s;
    } catch (const core::ParameterError& e) {
      io::throw_at_key(*sc, sim::ConfigError("gauge", e.parameter() + ": " + e.what()));
    } catch (const std::invalid_argument& e) {
      io::throw_at_key(*sc, e, "sequence");
    }
    s->name = sc->name;
    s->sc = std::move(sc);
  });
  return s;
}

struct GaugeUpdate {
  using State = GaugeState;
  using In = GIn;
  static constexpr const char* name = "GaugeMachine.update";
  static std::span<const InputField<In>> fields() { return kGaugeIn; }
  static const Keywords& keywords() { return gauge_keywords(); }
  static In& input(State& s) { return s.in; }
  static py::object run(State& s) {
    s.m.update(s.in);
    return view_of(s, &s.m.output(), s.view);
  }
};

void bind_gauge(py::module_& m) {
  bind_outputs<GaugeState, GOut>(m, "GaugeOutputs",
                                 "GaugeMachine's outputs (live: they change with each update())",
                                 kGaugeOut);
  static const std::string update_doc =
      "update($self, /, **inputs)\n--\n\n"
      "update(**inputs) -> GaugeOutputs: one sample (period_s). Inputs not given keep their "
      "last value:\n" +
      gauge_keywords().doc;
  auto c = py::class_<GaugeState, std::shared_ptr<GaugeState>>(m, "_GaugeMachine");
  def_keyword_method<GaugeUpdate>(c, "update", update_doc);
  c.def(py::init([](const std::optional<std::string>& text, const std::string& label,
                    std::optional<double> threshold_V, std::optional<double> period_s,
                    std::optional<double> target_x_m, double signal_lost) {
          return make_gauge(text, label, {threshold_V, period_s, target_x_m, signal_lost});
        }),
        py::arg("text"), py::arg("label"), py::arg("threshold_V") = py::none(),
        py::arg("period_s") = py::none(), py::arg("target_x_m") = py::none(),
        py::arg("signal_lost") = 0.0)
      .def_property_readonly("outputs",
                             [](GaugeState& s) { return view_of(s, &s.m.output(), s.view); })
      .def_property_readonly("inputs",
                             [](const GaugeState& s) { return inputs_dict<GIn>(s.in, kGaugeIn); })
      .def_property_readonly("period_s", [](const GaugeState& s) { return s.m.params().period_s; })
      .def_property_readonly("name", [](const GaugeState& s) { return s.name; })
      .def_property_readonly("thresholds_V",
                             [](const GaugeState& s) {
                               py::list l;
                               for (const auto& st : s.m.params().steps) l.append(st.threshold_V);
                               return l;
                             })
      .def_property_readonly("commands",
                             [](const GaugeState& s) {
                               py::list l;
                               for (const auto& st : s.m.params().steps)
                                 l.append(static_cast<int>(st.command));
                               return l;
                             })
      .def_property_readonly("backstop_m",
                             [](const GaugeState& s) { return s.m.params().backstop_m; })
      .def_property_readonly("free_signal_V",
                             [](const GaugeState& s) { return s.m.params().free_signal_V; })
      .def_property_readonly("rate_factor",
                             [](const GaugeState& s) {
                               return py::make_tuple(s.rate_factor[0], s.rate_factor[1],
                                                     s.rate_factor[2], s.rate_factor[3]);
                             })
      .def_property_readonly("removal_m_per_s",
                             [](const GaugeState& s) { return s.removal_m_per_s; })
      .def("reset", [](GaugeState& s) {
        s.m.reset();
        return view_of(s, &s.m.output(), s.view);
      });
}

}  // namespace

}  // namespace lathectl::python::machines

namespace lathectl::python {

void bind_machines(py::module_& m) {
  machines::bind_reasons(m);
  machines::bind_slide(m);
  machines::bind_gauge(m);
  machines::bind_adaptive(m);
  machines::bind_modulation(m);
  machines::bind_testing(m);
}

}  // namespace lathectl::python
