#include "systems/d_gauging/machine_params.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace lathectl::systems::d_gauging {

GaugingCycle cycle_for(const sensors::VibroContactGauge::Params& transducer, const Sequence& s,
                       const design::GaugeLine& line, const GaugingProcess& p,
                       double size_threshold_V) {
  const double lag = sensors::VibroContactGauge::filter_lag_s(transducer) + p.relay_response_s +
                     p.interruption.bridge_lag_s(transducer.supply_Hz);
  return gauging_cycle(s, line, p, lag, size_threshold_V);
}

control::GaugeMachine::Params machine_params(const GaugingProcess& p,
                                             const sensors::VibroContactGauge& g,
                                             double threshold_V, const MachineHost& h) {
  const auto& gp = g.params();
  control::GaugeMachine::Params m;
  m.period_s = std::isfinite(h.period_s) ? h.period_s : g.step_s();
  m.filter = sensors::VibroContactGauge::filter_params(gp);
  m.steps = p.cycle.before;
  m.steps.push_back({threshold_V, control::GaugeMachine::Command::Size});
  // The guard after an interruption, where the surface has gated ones.
  const auto& ir = p.interruption;
  m.gate_guard_s = ir.any() && ir.gate ? ir.guard_s : 0.0;
  if (!(h.stop_latency_s >= 0.0 && h.stop_latency_s <= p.relay_response_s))
    throw std::invalid_argument("the host's stop latency (" + std::to_string(h.stop_latency_s) +
                                " s) must be 0 … the relay's response t_r (" +
                                std::to_string(p.relay_response_s) + " s)");
  m.relay_response_s = p.relay_response_s - h.stop_latency_s;
  // The relay arms once the signal has settled below the threshold after the first contact.
  m.arm_after_s = 5.0 * gp.filter_time_constant_s;
  m.backstop_m = (std::isfinite(h.target_x_m) ? h.target_x_m + (p.backstop_m - p.target_m)
                                               : p.backstop_m) +
                 h.backstop_tolerance_m;
  m.free_signal_V = g.free_signal_V();
  m.initial_signal_V = g.free_signal_V();
  m.signal_lost_V = h.signal_lost * g.free_signal_V();
  return m;
}

}  // namespace lathectl::systems::d_gauging
