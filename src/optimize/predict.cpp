// Prediction: the program's moves run through sim::LathePlant — the cutting process of the
// LinuxCNC plant component — at LinuxCNC's servo period (1 ms, hal/config/lathectl-lathe.ini),
// the tool moving along each move at its programmed velocity (no acceleration phases: a move's
// time is length / velocity; the trajectory planner's blending and ramps are not modelled).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/cutting/disturbances.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/sim/lathe_plant.hpp"
#include "optimize/optimize.hpp"
#include "optimize/path.hpp"

namespace lathectl::optimize {

using io::CanonMove;

Plan programmed(const io::CanonProgram& prog) {
  Plan plan(prog.moves.size());
  for (std::size_t i = 0; i < prog.moves.size(); ++i)
    plan[i].push_back({0.0, 1.0, prog.moves[i].feed, "programmed", 0});
  return plan;
}

Prediction predict(const io::CanonProgram& prog, const Plan& plan,
                   const systems::e_adaptive::Settings& e, const Options& opt) {
  Prediction pr;
  Samples& s = pr.s;
  s.dt_s = 0.001;  // LinuxCNC's servo period in the simulated lathe
  sim::LathePlant plant;
  plant.configure(e.rig, sim::LathePlant::Params{.cell_mm = 0.01, .z_origin_mm = opt.z_origin_mm});
  cutting::CuttingModel cut;
  cut.configure(e.rig.cutting);
  cutting::Disturbances wear;  // the plant's wear law (its force factor from the time in cut)
  wear.configure(e.rig.disturbances);
  const double rapid = e.rig.rapid_m_per_s * 1000.0;  // mm/s, also the top feed velocity
  {  // reserve the samples: the moves' times at their start speeds, plus a margin
    double t = 0.0;
    for (std::size_t mi = 0; mi < prog.moves.size(); ++mi) {
      const CanonMove& m = prog.moves[mi];
      const double rpm = spindle_rpm(m, m.x0);
      for (const Piece& pc : plan[mi]) {
        const double v = m.kind == CanonMove::Kind::Traverse ? rapid
                         : m.per_rev                         ? pc.feed * rpm / 60.0
                                                             : pc.feed / 60.0;
        if (v > 0.0) t += move_length(m) * (pc.to - pc.from) / std::min(v, rapid);
      }
    }
    const auto n = static_cast<std::size_t>(std::min(t / s.dt_s * 1.1 + 1000.0, 5e7));
    for (auto* v : {&s.path_mm, &s.depth, &s.feed_rev, &s.speed, &s.rpm, &s.strength, &s.param,
                    &s.pz, &s.py, &s.power, &s.torque, &s.life_use, &s.x, &s.z, &s.dt, &s.wear})
      v->reserve(n);
    s.move.reserve(n);
    s.piece.reserve(n);
  }
  double path = 0.0;
  for (std::size_t mi = 0; mi < prog.moves.size(); ++mi) {
    const CanonMove& m = prog.moves[mi];
    const double len = move_length(m);
    for (std::size_t pi = 0; pi < plan[mi].size(); ++pi) {
      const Piece& pc = plan[mi][pi];
      const double l = len * (pc.to - pc.from);
      if (!(l > 1e-9)) continue;
      // The velocity at the piece's start (css: it changes with x; re-evaluated every step).
      double u = pc.from;
      const double du_len = 1.0 / len;
      while (u < pc.to - 1e-12) {
        const auto [x, z] = point_at(m, u);
        const double rpm = spindle_rpm(m, x);
        double v = rapid;
        if (m.kind != CanonMove::Kind::Traverse) {
          v = m.per_rev ? pc.feed * rpm / 60.0 : pc.feed / 60.0;
          if (!(v > 0.0))
            throw io::InputError(
                io::located(opt.label, m.line, 0,
                            m.per_rev && rpm <= 0.0
                                ? "a feed-per-revolution move (G95) with the spindle stopped: "
                                  "LinuxCNC would wait for ever (start it, or --spindle-rpm N)"
                                : "a feed move with no feed rate (F0)"));
          v = std::min(v, rapid);
        }
        double dt = s.dt_s;
        double step_u = v * dt * du_len;
        if (u + step_u > pc.to) {
          step_u = pc.to - u;
          dt = step_u * len / v;
        }
        u += step_u;
        const auto [x1, z1] = point_at(m, u);
        sim::LathePlant::Output out;
        plant.step({.x_mm = x1, .z_mm = z1, .rpm = rpm}, dt, out);
        path += step_u * len;
        s.move.push_back(static_cast<int>(mi));
        s.piece.push_back(static_cast<int>(pi));
        s.path_mm.push_back(path);
        s.depth.push_back(out.depth_mm);
        s.feed_rev.push_back(out.feed_per_rev_mm);
        s.speed.push_back(out.speed_m_per_min);
        s.rpm.push_back(rpm);
        s.strength.push_back(out.strength_factor);
        s.param.push_back(out.force_parameter);
        s.pz.push_back(out.Pz_N);
        s.py.push_back(out.Py_N);
        s.power.push_back(out.cut_power_W);
        s.x.push_back(x1);
        s.z.push_back(z1);
        s.wear.push_back(wear.wear_factor(out.time_in_cut_s));
        const double torque = out.Pz_N * (x1 + out.depth_mm) * 1e-3;
        s.torque.push_back(torque);
        double life = 0.0;
        if (out.depth_mm > 0.0 && out.feed_per_rev_mm > 0.0 && out.speed_m_per_min > 0.0)
          life = dt / 60.0 /
                 cut.tool_life_min(out.speed_m_per_min, out.feed_per_rev_mm, out.depth_mm,
                                   out.strength_factor);
        s.life_use.push_back(life);
        s.dt.push_back(dt);
        pr.life_use += life;
        pr.cycle_time_s += dt;
        if (m.kind == CanonMove::Kind::Traverse && out.force_parameter > 0.0) {
          pr.rapid_in_material_s += dt;
          if (pr.rapid_first_line == 0) pr.rapid_first_line = m.line;
          pr.rapid_peak = std::max(pr.rapid_peak, out.force_parameter);
        }
      }
    }
  }
  return pr;
}

}  // namespace lathectl::optimize
