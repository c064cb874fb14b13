#pragma once
// Hand-written loops of rig A's and rig B's stepping (issue 45 item 6): the same equations as
// the rigs, in the same order, as one function with plain locals, so that their results are
// bit-identical to the rigs' (tests/systems/hand_loop_test.cpp) and their cost is the floor of
// the stepping with no framework — no model objects, no recorder, no per-step dispatch. They
// cover what their scenarios use and throw std::invalid_argument on anything else
// (docs/code-layout.md, "Speed").

#include <cstddef>
#include <vector>

#include "systems/a_pulse_feed/rig_config.hpp"
#include "systems/b_chatter/rig_config.hpp"

namespace lathectl::bench {

struct HandRun {
  std::size_t channels = 0;
  std::size_t rows = 0;
  std::vector<double> values;  // rows × channels, row by row (the rig's recorded channels)
  // The final state.
  double t_s = 0.0;
  double x = 0.0;             // A: slide position [m]; B: tool 1's axial position [mm]
  double force_N = 0.0;       // A: radial force; B: tool 1's radial force
  double life_used = 0.0;     // A: tool life used
  double life_used_td = 0.0;  // A: after the first disturbance
  double t_disturbance_s = -1.0;
  double delivered_m3 = 0.0, leaked_m3 = 0.0;  // A: the slide's oil ledger
  double y_m = 0.0;                            // B: the part's displacement at the tool
  bool sound = true;                           // every step finite
  [[nodiscard]] double at(std::size_t row, std::size_t channel) const {
    return values[row * channels + channel];
  }
};

// Rig A's run (configure, warm-up, then `duration` of steps and rows) for an uncontrolled or AIM
// set-up on a pulsed regulator; the controller (every control period) is control::SlideMachine,
// the machine side the rig runs, called as the rig calls it.
[[nodiscard]] HandRun hand_loop_a(const systems::a_pulse_feed::RigConfig& cfg, double dt,
                                  double record_interval, double duration);

// Rig B's run (configure, then steps and rows until the cut's end or max_duration) for one tool
// or feed division, without process damping or tool modes; the CNC's side is
// control::ModulationMachine, called as the rig calls it.
[[nodiscard]] HandRun hand_loop_b(const systems::b_chatter::RigConfig& cfg, double dt,
                                  double record_interval, double max_duration);

}  // namespace lathectl::bench
