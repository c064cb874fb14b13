// Prediction: the program's moves run through cutting::LathePlant — the cutting process of the
// LinuxCNC plant component — at LinuxCNC's servo period (1 ms, hal/config/lathectl-lathe.ini),
// the tool moving along each move at its programmed velocity, with LinuxCNC's G64 blend arcs at
// the corners (blend.hpp): the path the tool takes there, at the feed LinuxCNC runs it. The time
// the planner loses accelerating out of a stop and braking into one or into a slower segment is
// added to the cycle (accel_time_s), not to the samples: at the lower speed the chip, and so
// the force, is only smaller.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "lathectl/control/adaptive_machine.hpp"
#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/cutting/disturbances.hpp"
#include "lathectl/cutting/force_parameter.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/cutting/lathe_plant.hpp"
#include "lathectl/drives/spindle_drive.hpp"
#include "lathectl/sensors/force_sensor.hpp"
#include "systems/e_adaptive/machine_params.hpp"
#include "optimize/adaptive_params.hpp"
#include "optimize/optimize.hpp"
#include "optimize/blend.hpp"
#include "optimize/path.hpp"

namespace lathectl::optimize {

using io::CanonMove;

Plan programmed(const io::CanonProgram& prog) {
  Plan plan(prog.moves.size());
  for (std::size_t i = 0; i < prog.moves.size(); ++i)
    plan[i].push_back({0.0, 1.0, prog.moves[i].feed, "programmed", 0});
  return plan;
}

control::AdaptiveMachine::Params adaptive_machine_params(const systems::e_adaptive::Settings& e,
                                                         const Options& opt) {
  // The machine side as every host derives it from the scenario (e_adaptive::machine_params),
  // with the stock model as the sample configuration loads lathectl_adaptive (z_origin_mm).
  systems::e_adaptive::MachineHost host;
  host.z_origin_mm = opt.z_origin_mm;
  return systems::e_adaptive::machine_params(e.rig, host);
}

io::ToolGeometry tool_geometry(const Options& opt, const systems::e_adaptive::Settings& e,
                               int number) {
  return io::tool_geometry(opt.tool_specs, opt.table_tools, number,
                           {e.rig.cutting.nose_radius_mm, e.rig.tool_orientation,
                            e.rig.tool_front_angle_deg, e.rig.tool_back_angle_deg});
}

double largest_nose_radius_mm(const Options& opt, const systems::e_adaptive::Settings& e) {
  return io::largest_nose_radius_mm(opt.tool_specs, opt.table_tools,
                                    e.rig.cutting.nose_radius_mm);
}

namespace {

// Reserves the samples: the moves' times at their start speeds, plus a margin. Refuses, before
// a sample is taken, a program whose samples would exceed kMaxPredictedSamples (G76 P0.001 or
// G95 F0.0001 over a few cm: hours of servo periods, gigabytes), naming the slowest move's line.
void reserve_samples(const io::CanonProgram& prog, const Plan& plan, double rapid,
                     const Options& opt, Samples& s) {
  double t = 0.0, slowest_t = 0.0;
  const CanonMove* slowest = nullptr;
  for (std::size_t mi = 0; mi < prog.moves.size(); ++mi) {
    const CanonMove& m = prog.moves[mi];
    const double rpm = spindle_rpm(m, m.x0);
    double tm = 0.0;
    for (const Piece& pc : plan[mi]) {
      const double v = m.kind == CanonMove::Kind::Traverse ? rapid
                       : m.synced                          ? m.pitch_mm * rpm / 60.0
                       : m.per_rev                         ? pc.feed * rpm / 60.0
                                                           : pc.feed / 60.0;
      if (v > 0.0) tm += move_length(m) * (pc.to - pc.from) / std::min(v, rapid);
    }
    t += tm;
    if (tm > slowest_t) slowest_t = tm, slowest = &m;
  }
  if (t / s.dt_s > kMaxPredictedSamples && slowest) {
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "the program runs about %.3g h (%.3g servo periods of 1 ms), over the %.3g h "
                  "lathectl optimize predicts (its memory grows with the cycle time); this "
                  "move alone takes %.3g h at %s %.4g mm%s: a larger feed or pitch",
                  t / 3600.0, t / s.dt_s, kMaxPredictedSamples * s.dt_s / 3600.0,
                  slowest_t / 3600.0, slowest->synced ? "a pitch of" : "a feed of",
                  slowest->synced ? slowest->pitch_mm : slowest->feed,
                  slowest->synced ? "" : slowest->per_rev ? "/rev" : "/min");
    throw io::InputError(io::located(opt.label, slowest->line, 0, buf));
  }
  const auto n = static_cast<std::size_t>(t / s.dt_s * 1.1 + 1000.0);
  for (auto* v : {&s.path_mm, &s.depth, &s.feed_rev, &s.speed, &s.rpm, &s.strength, &s.param,
                  &s.pz, &s.py, &s.power, &s.torque, &s.life_use, &s.x, &s.z, &s.dt, &s.wear})
    v->reserve(n);
  s.move.reserve(n);
  s.piece.reserve(n);
}

// The planner's segments: every piece of every move, in order (a split move's pieces are
// blocks of their own), and LinuxCNC's blend at each corner (blend.hpp).
struct Seg {
  std::size_t mi, pi;
  double u0, u1, len;                 // share of the move, and the piece's length
  double trim0 = 0.0, trim1 = 0.0;    // cut off its start / end by the blends
  Corner next;                        // the blend into the next segment
  bool stop_after = true;             // the planner stops at its end
};

std::vector<Seg> planner_segments(const io::CanonProgram& prog, const Plan& plan,
                                  const Options& opt) {
  std::vector<Seg> segs;
  for (std::size_t mi = 0; mi < prog.moves.size(); ++mi) {
    const double len = move_length(prog.moves[mi]);
    for (std::size_t pi = 0; pi < plan[mi].size(); ++pi) {
      const Piece& pc = plan[mi][pi];
      const double l = len * (pc.to - pc.from);
      if (l > 1e-9) segs.push_back({mi, pi, pc.from, pc.to, l, 0.0, 0.0, {}});
    }
  }
  for (std::size_t k = 0; k + 1 < segs.size() && opt.blends; ++k) {
    const CanonMove& a = prog.moves[segs[k].mi];
    const CanonMove& b = prog.moves[segs[k + 1].mi];
    // Which corners LinuxCNC blends, as measured in the simulated lathe: two feed moves of one
    // feed mode, or two rapids, in G64. Between a rapid and a feed move it did not blend: the
    // tool went through the programmed corner, in G95 (profile_arcs.ngc: G0 X16 Z2 → G1 Z-8
    // stops there) and in G94 alike (lathe_g70_71_demo.ngc: 60 such corners, all within 5 µm).
    const bool same_kind = a.kind == CanonMove::Kind::Traverse
                               ? b.kind == CanonMove::Kind::Traverse
                               : b.kind != CanonMove::Kind::Traverse && a.per_rev == b.per_rev;
    const bool new_move = segs[k].mi != segs[k + 1].mi;
    if (!same_kind || a.synced || b.synced || a.blend_tol_mm < 0.0 ||
        (new_move && b.stop_before))
      continue;
    const Segment sa{&a, segs[k].u0, segs[k].u1, segs[k].len - segs[k].trim0};
    const Segment sb{&b, segs[k + 1].u0, segs[k + 1].u1, segs[k + 1].len};
    Corner c = blend_corner(sa, sb, opt.machine);
    // Blended or not, the planner runs on through a corner it may blend (tangent pieces of a
    // split move, a kink it takes as tangent, a parabolic blend where no arc fits), except
    // where the path turns back.
    segs[k].stop_after = c.reversal;
    if (!c.blended || c.trim_end_mm > segs[k].len - segs[k].trim0) continue;
    segs[k].trim1 = c.trim_end_mm;
    segs[k + 1].trim0 = c.trim_start_mm;
    segs[k].next = std::move(c);
  }
  return segs;
}

// Walks the moves one servo period at a time through the plant (and System E's machine side,
// Options::adaptive, as lathectl_adaptive runs it), recording each sample into pr.s.
struct Walker {
  const systems::e_adaptive::Settings& e;
  const Options& opt;
  const double rapid;  // mm/s, also the top feed velocity
  cutting::LathePlant& plant;
  cutting::CuttingModel& cut;
  cutting::Disturbances& wear;
  control::AdaptiveMachine& machine;
  control::AdaptiveMachine::Output& mo;
  drives::SpindlePowerAtSpeed& drive;  // the spindle drive's power through its meter
  sensors::LaggedNoisySensor& meter;
  Prediction& pr;
  double path = 0.0;
  double leaving_mm = 0.0;  // what is left of a retract's way out of the cut before it
  int q_tool = -1;  // the tool whose nose the plant has (set_tool)

  // The velocity of a feed move at the piece's F: a thread (G33, G33.1, G76) advances its pitch
  // per revolution whatever the modal F (LinuxCNC synchronises the move to the spindle:
  // START_SPEED_FEED_SYNC's pitch).
  double feed_velocity(const CanonMove& m, double feed, double rpm, double rpm_run) const {
    double v = m.synced    ? m.pitch_mm * rpm_run / 60.0
               : m.per_rev ? feed * rpm_run / 60.0
                           : feed / 60.0;
    if (!(v > 0.0))
      throw io::InputError(io::located(
          opt.label, m.line, 0,
          (m.per_rev || m.synced) && rpm <= 0.0
              ? std::string(m.synced ? "a thread (G33/G76)" : "a feed-per-revolution move (G95)") +
                    " with the spindle stopped: LinuxCNC would wait for ever (start it, or "
                    "--spindle-rpm N)"
              : std::string("a feed move with no feed rate (F0)")));
    v = std::min(v, rapid);
    if (opt.adaptive) v *= mo.feed_factor;  // motion's feed scale × adaptive-feed
    return v;
  }

  // One servo period of System E's machine side on the sample.
  void adaptive_step(const CanonMove& m, double feed, bool rapid_move, double rpm, double rpm_run,
                     double v, double dt, double x1, double z1,
                     const cutting::LathePlant::Output& out) {
    control::AdaptiveMachine::Input in;
    in.nominal_period_s = pr.s.dt_s;
    in.elapsed_s = dt;
    in.force = out.force_measured;
    meter.step(dt, drive.step(dt, rpm_run, out.cut_power_W));
    in.spindle_power_W = machine.params().power_sensor ? meter.sample() : meter.lagged();
    in.rpm = rpm_run;
    in.rpm_programmed = rpm;
    in.current_vel_mm_s = v;
    in.requested_vel = m.per_rev ? feed : feed / 60.0;
    in.motion_type = static_cast<std::int32_t>(
        rapid_move                       ? control::AdaptiveMachine::Motion::Traverse
        : m.kind == CanonMove::Kind::Arc ? control::AdaptiveMachine::Motion::Arc
                                         : control::AdaptiveMachine::Motion::Feed);
    in.feed_upm = m.per_rev ? feed * rpm_run * mo.feed_factor : feed * mo.feed_factor;
    in.per_rev = m.per_rev;
    in.x_mm = x1;
    in.z_mm = z1;
    in.tool_number = m.tool;
    in.program_line = m.line;
    machine.update(in, mo);
    pr.adaptive_feed_rev.push_back(mo.feed_hold ? 0.0 : mo.feed_per_rev_mm);
    pr.adaptive_factor.push_back(mo.feed_factor);
    if (mo.alarm && pr.adaptive_alarm == 0) pr.adaptive_alarm = static_cast<int>(mo.alarm_reason);
  }

  // The sample: where, the cut, the forces, the tool life it used.
  void record(std::size_t mi, std::size_t pi, double step_mm, double rpm, double dt, double x1,
              double z1, const cutting::LathePlant::Output& out) {
    Samples& s = pr.s;
    path += step_mm;
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
  }

  // A rapid that starts where a cut ended first lifts the tool out of that cut's last chip
  // (a retract at the end of a pass): contact within the nose's width and a feed of the
  // cut's end is the tool leaving it. Past that, or from air, it is a rapid through material.
  void track_rapid(const CanonMove& m, bool rapid_move, double step_mm, double dt,
                   const cutting::LathePlant::Output& out) {
    const bool contact = out.force_parameter > 0.0;
    if (!rapid_move) {
      leaving_mm = contact ? 2.0 * plant.nose_radius_mm() + out.feed_per_rev_mm : 0.0;
    } else if (contact && leaving_mm > 0.0) {
      leaving_mm -= step_mm;
    } else if (contact) {
      pr.rapid_in_material_s += dt;
      if (pr.rapid_first_line == 0) pr.rapid_first_line = m.line;
      pr.rapid_peak = std::max(pr.rapid_peak, out.force_parameter);
    } else {
      leaving_mm = 0.0;
    }
  }

  // Walks the share [u_from, u_to] of `m` one servo period at a time; `feed` is the piece's F,
  // `v_cap` the planner's limit (a blend arc's), `rapid_move` whether it runs at rapid.
  void walk(const CanonMove& m, double u_from, double u_to, double feed, double v_cap,
            bool rapid_move, std::size_t mi, std::size_t pi) {
    const double len = move_length(m);
    double u = u_from;
    const double du_len = 1.0 / len;
    const ToolSpec* spec = find_tool(opt.tool_specs, m.tool);
    const bool plunge = spec && spec->plunge() && !rapid_move && !m.synced;
    // The programmed point is this tool's tip (its orientation Q) and the plant cuts with its
    // nose: the nose's centre follows it.
    if (m.tool != q_tool) {
      q_tool = m.tool;
      const io::ToolGeometry g = tool_geometry(opt, e, m.tool);
      plant.set_tool(g.nose_radius_mm, g.orientation);
      plant.set_edges(g.front_angle_deg, g.back_angle_deg);  // its insert's edges (I, J)
    }
    while (u < u_to - 1e-12) {
      const auto [x, z] = point_at(m, u);
      const double rpm = spindle_rpm(m, x);
      const double rpm_run = opt.adaptive && mo.control_period && mo.spindle_speed_out != 0.0
                                 ? std::abs(mo.spindle_speed_out)
                                 : rpm;
      double v = rapid_move ? rapid : feed_velocity(m, feed, rpm, rpm_run);
      v = std::min(v, v_cap);
      if (opt.adaptive && (mo.alarm || !(v > 0.0))) return;  // held: the prediction ends here
      double dt = pr.s.dt_s;
      double step_u = v * dt * du_len;
      if (u + step_u > u_to) {
        step_u = u_to - u;
        dt = step_u * len / v;
      }
      u += step_u;
      const auto [x1, z1] = point_at(m, u);
      cutting::LathePlant::Output out;
      // A grooving or parting insert cuts its whole width (the plant's Input::insert_width_mm,
      // the law the LinuxCNC plant takes for the tool in its spindle too).
      plant.step({.x_mm = x1, .z_mm = z1, .rpm = rpm_run,
                  .insert_width_mm = plunge ? spec->insert_width_mm : 0.0},
                 dt, out);
      if (opt.adaptive) adaptive_step(m, feed, rapid_move, rpm, rpm_run, v, dt, x1, z1, out);
      record(mi, pi, step_u * len, rpm, dt, x1, z1, out);
      track_rapid(m, rapid_move, step_u * len, dt, out);
    }
  }
};

// Walks every segment and the blend arc after it; the legs the planner's velocity profile needs.
void walk_segments(const io::CanonProgram& prog, const Plan& plan, const std::vector<Seg>& segs,
                   const Options& opt, Walker& w) {
  Prediction& pr = w.pr;
  const Samples& s = pr.s;
  const double no_cap = std::numeric_limits<double>::infinity();
  // What the planner's velocity profile needs of each walked leg (a segment or a blend arc).
  std::vector<Leg> legs;
  legs.reserve(2 * segs.size());
  auto leg = [&](const CanonMove& m, double len_mm, double t0, bool stop_after) {
    const double t = pr.cycle_time_s - t0;
    if (!(len_mm > 1e-9) || !(t > 0.0)) {  // nothing left of it: its stop is the previous leg's
      if (stop_after && !legs.empty()) legs.back().stop_after = true;
      return;
    }
    // [TRAJ]MAX_LINEAR_ACCELERATION along a line; on a circle half of it is left for the
    // tangent (tc.c tcGetTangentialMaxAccel, BLEND_ACC_RATIO_TANGENTIAL).
    const double a = opt.machine.accel_mm_s2 * (m.kind == CanonMove::Kind::Arc ? 0.5 : 1.0);
    legs.push_back({len_mm, len_mm / t, a, stop_after});
  };
  for (std::size_t k = 0; k < segs.size(); ++k) {
    const Seg& g = segs[k];
    const CanonMove& m = prog.moves[g.mi];
    const double len = move_length(m);
    const bool traverse = m.kind == CanonMove::Kind::Traverse;
    const double t0 = pr.cycle_time_s;
    w.walk(m, g.u0 + g.trim0 / len, g.u1 - g.trim1 / len, plan[g.mi][g.pi].feed, no_cap, traverse,
         g.mi, g.pi);
    leg(m, g.len - g.trim0 - g.trim1, t0, g.stop_after || k + 1 == segs.size());
    if (!g.next.blended) continue;
    // The blend arc runs with the next segment's state (tp.c, tcSetupState): its feed per
    // revolution when synchronised, else the larger requested velocity; at most v_plan. Its
    // samples count to the next segment, whose feed they are cut at.
    const Seg& h = segs[k + 1];
    const CanonMove& b = prog.moves[h.mi];
    const bool rapid_blend = b.kind == CanonMove::Kind::Traverse;
    double feed = plan[h.mi][h.pi].feed;
    if (!b.per_rev && !rapid_blend) feed = std::max(feed, plan[g.mi][g.pi].feed);
    const std::size_t first = s.depth.size();
    const double t_arc = pr.cycle_time_s;
    w.walk(g.next.arc, 0.0, 1.0, feed, g.next.v_max_mm_s, rapid_blend, h.mi, h.pi);
    leg(g.next.arc, move_length(g.next.arc), t_arc, false);
    bool in_cut = false;
    for (std::size_t i = first; i < s.depth.size(); ++i) in_cut = in_cut || s.depth[i] > 0.0;
    if (in_cut) {  // how far inside the programmed corner (the end of segment k) it cuts
      const auto [px, pz] = point_at(m, g.u1);
      const double r = std::hypot(g.next.arc.x0 - g.next.arc.xc, g.next.arc.z0 - g.next.arc.zc);
      const double inside = std::hypot(px - g.next.arc.xc, pz - g.next.arc.zc) - r;
      if (inside > pr.blend_inside_max_mm) {
        pr.blend_inside_max_mm = inside;
        pr.blend_inside_line = m.line;
      }
    }
  }
  pr.accel_time_s = acceleration_time(legs);
}

}  // namespace

Prediction predict(const io::CanonProgram& prog, const Plan& plan,
                   const systems::e_adaptive::Settings& e, const Options& opt) {
  Prediction pr;
  Samples& s = pr.s;
  s.dt_s = 0.001;  // LinuxCNC's servo period in the simulated lathe
  cutting::LathePlant plant;
  plant.configure(e.rig, cutting::LathePlant::Params{
                            .cell_mm = 0.01,
                            .z_origin_mm = opt.z_origin_mm,
                            .max_nose_radius_mm = largest_nose_radius_mm(opt, e)});
  // The workpiece on a grid of at most 4000 points along z, before and (at the end) after.
  {
    const auto& b = e.rig.stock.blank_diameter_mm;
    const double z_lo = b.front().at_mm, z_hi = b.back().at_mm;
    const double step = std::max((z_hi - z_lo) / 4000.0, 0.05);
    for (double z = z_lo; z <= z_hi + 1e-9; z += step) {
      pr.part_z.push_back(opt.z_origin_mm - z);
      pr.blank_r.push_back(plant.radius_mm(z));
    }
  }
  cutting::CuttingModel cut;
  cut.configure(e.rig.cutting);
  cutting::Disturbances wear;  // the plant's wear law (its force factor from the time in cut)
  wear.configure(e.rig.disturbances);
  const double rapid = e.rig.rapid_m_per_s * 1000.0;  // mm/s, also the top feed velocity
  // System E's machine side in the loop (Options::adaptive), as lathectl_adaptive runs it.
  control::AdaptiveMachine machine;
  control::AdaptiveMachine::Output mo;
  // The spindle drive's power at the predicted speed through its meter, as the rig and the
  // simulated lathe read it (the load when the machine controls on the spindle's power).
  drives::SpindlePowerAtSpeed drive;
  sensors::LaggedNoisySensor meter;
  if (opt.adaptive) {
    drive.configure(e.rig.spindle);
    meter.configure(systems::e_adaptive::spindle_power_meter(e.rig));
    machine.configure(adaptive_machine_params(e, opt));
    if (!prog.moves.empty()) drive.reset(spindle_rpm(prog.moves.front(), prog.moves.front().x0));
    meter.reset(0.0);
  }
  reserve_samples(prog, plan, rapid, opt, s);
  const std::vector<Seg> segs = planner_segments(prog, plan, opt);
  Walker w{e, opt, rapid, plant, cut, wear, machine, mo, drive, meter, pr};
  walk_segments(prog, plan, segs, opt, w);
  pr.cycle_time_s += pr.accel_time_s;
  pr.part_r.reserve(pr.part_z.size());
  for (const double z : pr.part_z) pr.part_r.push_back(plant.radius_mm(plant.stock_z_mm(z)));
  return pr;
}

double leg_time(double len, double v, double v0, double v1, double a) {
  const double vp = std::min(v, std::sqrt((2.0 * a * len + v0 * v0 + v1 * v1) / 2.0));
  const double d_acc = (vp * vp - v0 * v0) / (2.0 * a);
  const double d_dec = (vp * vp - v1 * v1) / (2.0 * a);
  return (vp - v0) / a + (vp - v1) / a + std::max(len - d_acc - d_dec, 0.0) / vp;
}

double acceleration_time(const std::vector<Leg>& legs) {
  // The velocity at each junction: at most both legs' velocities, 0 at a stop, and what
  // accelerating forward and braking backward allow (the planner's look-ahead).
  const std::size_t n = legs.size();
  std::vector<double> b(n + 1, 0.0);
  for (std::size_t k = 0; k < n; ++k)
    b[k + 1] = legs[k].stop_after || k + 1 == n
                   ? 0.0
                   : std::min({legs[k].v, legs[k + 1].v,
                               std::sqrt(b[k] * b[k] + 2.0 * legs[k].a * legs[k].len)});
  for (std::size_t k = n; k-- > 0;)
    b[k] = std::min(b[k], std::sqrt(b[k + 1] * b[k + 1] + 2.0 * legs[k].a * legs[k].len));
  double extra = 0.0;
  for (std::size_t k = 0; k < n; ++k)
    extra += leg_time(legs[k].len, legs[k].v, b[k], b[k + 1], legs[k].a) -
             legs[k].len / legs[k].v;
  return extra;
}

}  // namespace lathectl::optimize
