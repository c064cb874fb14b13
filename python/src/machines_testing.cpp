// Test helpers for python/tests/test_machines.py (underscore names, not the package's):
//   _rig_params_equal(obj): the machine's parameters equal those of the rig `lathectl run` builds
//     from the same scenario (the probe its validate() configures), Params::operator==.
//   _replay(obj, inputs): the same input sequence through a C++ loop on a machine configured
//     with obj's parameters, the inputs set and the outputs read field by field here (not
//     through the binding's tables), so that the Python object's update() can be compared with
//     it bit for bit.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <string>
#include <vector>

#include "machine_states.hpp"
#include "systems/a_pulse_feed/rig.hpp"
#include "systems/a_pulse_feed/settings.hpp"
#include "systems/b_chatter/rig.hpp"
#include "systems/b_chatter/settings.hpp"
#include "systems/e_adaptive/rig.hpp"
#include "systems/e_adaptive/settings.hpp"

namespace lathectl::python::machines {

namespace {

// A column of the inputs (1-D float64) and the outputs being collected.
struct Columns {
  py::dict in;
  std::size_t n = 0;
  std::vector<std::pair<std::string, std::vector<double>>> out;
  explicit Columns(py::dict d) : in(std::move(d)) {
    for (auto kv : in) n = std::max(n, static_cast<std::size_t>(py::len(kv.second)));
  }
  [[nodiscard]] double at(const char* name, std::size_t k, double otherwise) const {
    if (!in.contains(name)) return otherwise;
    const auto a = in[name].cast<py::array_t<double, py::array::forcecast>>();
    return a.at(static_cast<py::ssize_t>(k));
  }
  void put(const std::string& name, std::size_t k, double v) {
    auto it = std::find_if(out.begin(), out.end(), [&](const auto& c) { return c.first == name; });
    if (it == out.end()) {
      out.emplace_back(name, std::vector<double>(n));
      it = out.end() - 1;
    }
    it->second[k] = v;
  }
  [[nodiscard]] py::dict result() const {
    py::dict d;
    for (const auto& [name, v] : out)
      d[name.c_str()] = py::array_t<double>(static_cast<py::ssize_t>(v.size()), v.data());
    return d;
  }
};

double rc(control::Reason r) {
  return static_cast<double>(static_cast<int>(r));
}

py::dict replay_slide(const SlideState& s, py::dict inputs) {
  Columns c(std::move(inputs));
  control::SlideMachine m;
  m.configure(s.m.params());
  m.start(s.start_force_N);
  control::SlideMachine::Input in;
  in.mode = s.m.params().controller.mode;
  for (std::size_t k = 0; k < c.n; ++k) {
    in.sensor_V = c.at("sensor_V", k, in.sensor_V);
    in.position_m = c.at("position_m", k, in.position_m);
    in.feed_m_per_s = c.at("feed_set_m_per_s", k, in.feed_m_per_s);
    in.force_set_N = c.at("force_set_N", k, in.force_set_N);
    in.enable = c.at("enable", k, in.enable ? 1.0 : 0.0) != 0.0;
    m.update(in);
    const auto& o = m.output();
    c.put("slot_m", k, o.slot_m);
    c.put("frequency_Hz", k, o.frequency_Hz);
    c.put("feed_cmd_m_per_s", k, o.feed_cmd_m_per_s);
    c.put("force_estimate_N", k, o.force_estimate_N);
    c.put("reason", k, rc(o.reason));
    c.put("alarm", k, o.alarm ? 1.0 : 0.0);
  }
  return c.result();
}

py::dict replay_gauge(const GaugeState& s, py::dict inputs) {
  Columns c(std::move(inputs));
  control::GaugeMachine m;
  m.configure(s.m.params());
  control::GaugeMachine::Input in;
  for (std::size_t k = 0; k < c.n; ++k) {
    in.generator_V = c.at("generator_V", k, in.generator_V);
    in.position_m = c.at("position_m", k, in.position_m);
    in.gate = c.at("gate", k, in.gate ? 1.0 : 0.0) != 0.0;
    m.update(in);
    const auto& o = m.output();
    c.put("signal_V", k, o.signal_V);
    c.put("step", k, o.step);
    c.put("trip_time_s", k, o.trip_time_s);
    c.put("stop", k, o.stop ? 1.0 : 0.0);
    c.put("reason", k, rc(o.reason));
  }
  return c.result();
}

py::dict replay_adaptive(const AdaptiveState& s, py::dict inputs) {
  Columns c(std::move(inputs));
  control::AdaptiveMachine m;
  m.configure(s.m.params());
  control::AdaptiveMachine::Input in;
  control::AdaptiveMachine::Output o;
  in.nominal_period_s = s.in.nominal_period_s;
  for (std::size_t k = 0; k < c.n; ++k) {
    in.force = c.at("force", k, in.force);
    in.rpm = c.at("spindle_rpm", k, in.rpm);
    in.rpm_programmed = c.at("spindle_rpm_programmed", k, in.rpm_programmed);
    in.requested_vel = c.at("requested_vel", k, in.requested_vel);
    in.current_vel_mm_s = c.at("current_vel_mm_per_s", k, in.current_vel_mm_s);
    in.motion_type = static_cast<std::int32_t>(c.at("motion_type", k, in.motion_type));
    in.x_mm = c.at("x_pos_mm", k, in.x_mm);
    in.z_mm = c.at("z_pos_mm", k, in.z_mm);
    in.program_line = static_cast<std::int32_t>(c.at("program_line", k, in.program_line));
    in.tool_number = static_cast<std::int32_t>(c.at("tool_number", k, in.tool_number));
    m.update(in, o);
    c.put("feed_factor", k, o.feed_factor);
    c.put("adaptive_feed", k, o.adaptive_feed);
    c.put("feed_per_rev_mm", k, o.feed_per_rev_mm);
    c.put("spindle_speed_out", k, o.spindle_speed_out);
    c.put("load", k, o.load);
    c.put("reason", k, rc(o.reason));
  }
  return c.result();
}

// B: each row one module period: sense(displacement_m) as many times as the row's `senses`
// (default 10), servo(feed_block), update().
py::dict replay_modulation(const ModulationState& s, py::dict inputs) {
  Columns c(std::move(inputs));
  control::ModulationMachine m;
  m.configure(s.m.params());
  control::ModulationMachine::Input in = s.in;  // the scenario's block (as the object starts)
  control::ModulationMachine::Servo sv = s.servo;
  for (std::size_t k = 0; k < c.n; ++k) {
    const double y = c.at("displacement_m", k, 0.0);
    const auto senses = static_cast<int>(c.at("senses", k, 10.0));
    for (int i = 0; i < senses; ++i) m.sense(y);
    sv.feed_block = c.at("feed_block", k, sv.feed_block ? 1.0 : 0.0) != 0.0;
    m.servo(sv);
    in.feed_block = sv.feed_block;
    in.idle_block = c.at("idle_block", k, in.idle_block ? 1.0 : 0.0) != 0.0;
    in.motor_power_W = c.at("spindle_power_W", k, in.motor_power_W);
    in.rpm = c.at("spindle_rpm", k, in.rpm);
    in.speed_m_per_min = c.at("speed_m_per_min", k, in.speed_m_per_min);
    in.feed_requested = c.at("requested_vel", k, in.feed_requested);
    in.feed_per_rev = c.at("feed_per_rev_mode", k, in.feed_per_rev ? 1.0 : 0.0) != 0.0;
    in.feed_rpm = c.at("feed_rpm", k, in.feed_rpm);
    in.path_mm[0] = c.at("path_right_mm", k, in.path_mm[0]);
    m.update(in);
    const auto& o = m.output();
    c.put("feed_right_mm_per_min", k, o.feed_mm_per_min[0]);
    c.put("feed_left_mm_per_min", k, o.feed_mm_per_min[1]);
    c.put("a0_m", k, o.a0_m);
    c.put("cut_power_W", k, o.cut_power_W);
    c.put("n_s", k, o.plan.n_s);
    c.put("reason", k, rc(o.reason));
  }
  return c.result();
}

template <class Rig, class Settings>
const Rig& probe(const io::Scenario& sc, Rig& rig) {
  rig.configure(sc.get<Settings>().rig, sc.run.step_s, sc.run.record_interval_s,
                std::min(sc.run.duration_s, sc.run.step_s * 4));
  return rig;
}

}  // namespace

void bind_testing(py::module_& m) {
  m.def("_replay", &replay_slide);
  m.def("_replay", &replay_gauge);
  m.def("_replay", &replay_adaptive);
  m.def("_replay", &replay_modulation);
  m.def("_rig_params_equal", [](const SlideState& s) {
    systems::a_pulse_feed::Rig rig;
    return probe<systems::a_pulse_feed::Rig, systems::a_pulse_feed::Settings>(*s.sc, rig)
               .machine()
               .params() == s.m.params();
  });
  m.def("_rig_params_equal", [](const ModulationState& s) {
    systems::b_chatter::Rig rig;
    return probe<systems::b_chatter::Rig, systems::b_chatter::Settings>(*s.sc, rig)
               .machine()
               .params() == s.m.params();
  });
  m.def("_rig_params_equal", [](const AdaptiveState& s) {
    systems::e_adaptive::Rig rig;
    return probe<systems::e_adaptive::Rig, systems::e_adaptive::Settings>(*s.sc, rig)
               .machine()
               .params() == s.m.params();
  });
  // The program's feed the rig writes (its fixed mode: the worst-case feed) [mm/rev].
  m.def("_rig_feed_programmed", [](const AdaptiveState& s) {
    systems::e_adaptive::Rig rig;
    return probe<systems::e_adaptive::Rig, systems::e_adaptive::Settings>(*s.sc, rig)
        .programmed_feed();
  });
}

}  // namespace lathectl::python::machines
