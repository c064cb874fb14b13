// Rig B's stepping written by hand (see hand_loops.hpp): systems/b_chatter/rig.cpp with the
// models it steps (dynamics/twin_turret.cpp's cut, its Kienzle forces from cutting_model.cpp,
// drives/spindle_drive.cpp, sensors/vibration_chain.cpp's high-pass) written out in one
// function, the same operations in the same order, for one tool or feed division without
// process damping or tool modes. The CNC's side (servo, update every module period, sense every
// sample) is control::ModulationMachine, called as the rig calls it. Rows go to a flat array.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "hand_loops.hpp"
#include "lathectl/control/modulation_machine.hpp"
#include "lathectl/dynamics/beam.hpp"
#include "systems/b_chatter/machine_params.hpp"

namespace lathectl::bench {

HandRun hand_loop_b(const systems::b_chatter::RigConfig& cfg, double dt, double record_interval,
                    double max_duration) {
  using systems::b_chatter::TwinSetup;
  if (cfg.setup == TwinSetup::DepthDivision || cfg.process_damping.on() ||
      !cfg.tool_modes.empty())
    throw std::invalid_argument("hand_loop_b: a set-up the hand loop does not cover");
  constexpr double kPi = std::numbers::pi;
  constexpr double kRpm = 2.0 * std::numbers::pi / 60.0;  // rad/s per rpm
  const auto lr = [](double v) { return std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(v))); };
  const std::size_t record_every = lr(record_interval / dt);
  const std::size_t chain_every = lr(systems::b_chatter::kSamplePeriod_s / dt);
  const std::size_t control_every = lr(systems::b_chatter::kModulePeriod_s / dt);
  const auto pp = systems::b_chatter::cut_params(cfg);
  const int n_tools = cfg.setup == TwinSetup::Single ? 1 : 2;
  const double D = pp.part.diameter_m;
  // Kienzle's Fc and Fp (CuttingModel::forces, no hardness or wear factor).
  const auto& mat = pp.cutting.material;
  const double kmp = std::pow(mat.strength / mat.strength_base, mat.kmp_exponent);
  const double kk = kmp * 1.0 * 1.0 / kmp;
  const double sin_k = std::sin(pp.cutting.approach_angle_deg * std::numbers::pi / 180.0);
  // The surface: one ring of cells (TwinTurretCut::size_surface_memory, no tool-2 lag).
  const std::size_t cells = std::max<std::size_t>(64, static_cast<std::size_t>(std::lround(60.0 / pp.rpm_nominal / dt)));
  const auto m = static_cast<long long>(cells * 2);
  std::vector<double> ring_d(cells * 2, 0.0), ring_z(cells * 2, pp.z_start_mm);
  auto wrap = [m](long long c) {
    const long long i = c % m;
    return static_cast<std::size_t>(i < 0 ? i + m : i);
  };
  auto read = [&](const std::vector<double>& v, double cell) {
    const double fl = std::floor(cell);
    const std::size_t i = wrap(static_cast<long long>(fl));
    const double f = cell - fl;
    return v[i] * (1.0 - f) + v[i + 1 == ring_d.size() ? 0 : i + 1] * f;
  };
  struct Edge {
    double sigma, alpha, t0, lag, fc = 0.0, fp = 0.0, b = 0.0, s = 0.0;
    long long last_cell = 0;
    bool cutting = false;
  } edges[2] = {{1.0, 0.0, pp.depth_mm[0], 1.0}, {-1.0, kPi, pp.depth_mm[1], cfg.setup == TwinSetup::FeedDivision ? 0.0 : 1.0}};
  for (Edge& e : edges)
    e.last_cell = static_cast<long long>(std::floor(-e.alpha / (2.0 * kPi) * static_cast<double>(cells)));
  // The part's modes at the cut (TwinTurretCut::update_modes), stepped exactly.
  double q[6] = {}, qd[6] = {}, p11[6], p12[6], p21[6], p22[6], g1[6], g2[6], shape[6] = {};
  double modes_at = -1e9;
  auto update_modes = [&](double x) {
    const double x_mm = std::clamp(pp.modes_follow_tool ? x : pp.z_start_mm, 1.0, pp.part.length_m * 1e3 - 1.0);
    if (std::abs(x_mm - modes_at) < 0.5) return;
    modes_at = x_mm;
    for (int j = 0; j < pp.modes; ++j) {
      const auto bm = dynamics::beam_mode_at(pp.part, x_mm * 1e-3, j + 1);
      if (shape[j] != 0.0) {
        const double r = bm.shape / shape[j];
        q[j] *= r;
        qd[j] *= r;
      }
      shape[j] = bm.shape;
      const double wn = 2.0 * kPi * bm.mode.natural_frequency_Hz, z = bm.mode.damping_ratio;
      const double wd = wn * std::sqrt(1.0 - z * z), s = z * wn;
      const double e = std::exp(-s * dt), c = std::cos(wd * dt), sn = std::sin(wd * dt);
      p11[j] = e * (c + s / wd * sn);
      p12[j] = e * sn / wd;
      p21[j] = -wn * wn * p12[j];
      p22[j] = e * (c - s / wd * sn);
      g1[j] = (1.0 - p11[j]) / bm.mode.stiffness_N_per_m;
      g2[j] = p12[j] / bm.mass_kg;
    }
  };
  update_modes(pp.z_start_mm);
  bool seed_pending = pp.initial_disturbance_um != 0.0;  // applied at the first contact
  double y = 0.0;
  bool sound = true;
  // The turrets' drives, the spindle (SpindleDrive::reset), the high-pass (HighPass2).
  double z[2], z0[2] = {cfg.z_start_mm - cfg.approach_mm, cfg.z_start_mm - cfg.approach_mm};
  if (cfg.setup != TwinSetup::Single) z0[1] -= cfg.tool2_lag_mm;
  double v[2] = {0.0, 0.0}, cmd[2] = {0.0, 0.0};
  z[0] = z0[0];
  z[1] = z0[1];
  const double drive_gain = 1.0 - std::exp(-2.0 * kPi * cfg.feed_drive_bandwidth_Hz * dt);
  const auto& sp = cfg.spindle;
  double w = cfg.rpm * kRpm, w_cmd = w, integral = sp.viscous_N_m_s * w, tm = integral;
  auto power_el = [&] {
    const double mech = tm * w, n = std::abs(w / kRpm);
    return (mech >= 0.0 ? mech / sp.efficiency : mech * sp.efficiency) +
           (sp.idle_p0_W + sp.idle_p1_W_per_rpm * n + sp.idle_p2_W_per_rpm2 * n * n);
  };
  const double hk = std::tan(kPi * cfg.vibration.highpass_Hz * dt), hq = std::numbers::sqrt2;
  const double hn = 1.0 / (1.0 + hq * hk + hk * hk);
  const double hb0 = hn, hb1 = -2.0 * hn, hb2 = hn, ha1 = 2.0 * (hk * hk - 1.0) * hn,
               ha2 = (1.0 - hq * hk + hk * hk) * hn;
  double hx1 = 0.0, hx2 = 0.0, hy1 = 0.0, hy2 = 0.0, y_hp = 0.0;
  // The CNC's side, as the rig configures it.
  control::ModulationMachine machine;
  machine.configure(systems::b_chatter::machine_params(
      cfg, {.module_period_s = dt * static_cast<double>(control_every),
            .sample_period_s = dt * static_cast<double>(chain_every)}));
  const double cut_time = (cfg.z_end_mm - cfg.z_start_mm + cfg.approach_mm + cfg.tool2_lag_mm) /
                          (cfg.feed_mm_per_rev * cfg.rpm / 60.0);
  const double max_t = std::min(max_duration, cfg.idle_block_s + 1.5 * cut_time + 1.0);

  HandRun r;
  r.channels = 28;
  r.values.reserve((static_cast<std::size_t>(max_t / dt) / record_every + 2) * r.channels);
  double t = 0.0, theta = 0.0;
  for (std::size_t step = 0; t < max_t && sound; ++step) {
    const bool idle_block = t < cfg.idle_block_s, feed_block = !idle_block;
    if (step % control_every == 0) {
      control::ModulationMachine::Servo sv;
      sv.dt_s = dt * static_cast<double>(control_every);
      sv.feed_block = feed_block;
      sv.turret = cfg.turret;
      machine.servo(sv);
      const double rpm = w / kRpm;
      control::ModulationMachine::Input in;
      in.motor_power_W = power_el();
      in.idle_block = idle_block;
      in.rpm = rpm;
      in.speed_m_per_min = kPi * cfg.part.diameter_m * rpm;
      in.feed_requested = cfg.feed_mm_per_rev;
      in.feed_per_rev = true;
      in.feed_rpm = cfg.rpm;
      in.turrets = n_tools;
      in.path_mm[0] = z[0] - z0[0];
      in.path_mm[1] = z[1] - z0[1];
      in.feed_block = feed_block;
      in.source = cfg.source;
      in.turret = machine.turret();
      in.programmed = cfg.programmed;
      machine.update(in);
      for (int i = 0; i < 2; ++i)
        cmd[i] = feed_block && i < n_tools ? machine.output().feed_mm_per_min[i] : 0.0;
    }
    for (int i = 0; i < n_tools; ++i) {
      v[i] = v[i] + drive_gain * (cmd[i] - v[i]);
      z[i] += v[i] / 60.0 * dt;
    }
    {  // SpindleDrive::step at the programmed speed under the cutting torque
      double torque = 0.0;
      for (int i = 0; i < n_tools; ++i) torque += edges[i].fc * 0.5 * D;
      const double target = std::clamp(cfg.rpm, sp.min_rpm, sp.max_rpm) * kRpm;
      const double dw_max = sp.max_accel_rpm_per_s * kRpm * dt;
      w_cmd += std::clamp(target - w_cmd, -dw_max, dw_max);
      const double w_base = sp.max_power_W / sp.max_torque_N_m;
      const double t_lim = std::min(sp.max_torque_N_m, sp.max_power_W / std::max(std::abs(w), w_base));
      const double e = w_cmd - w;
      const double p_term = sp.kp_N_m_s * e;
      const double i_next = integral + sp.kp_N_m_s / sp.ti_s * e * dt;
      const double u_next = p_term + i_next;
      if (!(std::abs(u_next) > t_lim && u_next * e > 0.0)) integral = i_next;
      integral = std::clamp(integral, -t_lim, t_lim);
      tm = std::clamp(p_term + integral, -t_lim, t_lim);
      w = (sp.inertia_kg_m2 * w + dt * (tm - torque)) / (sp.inertia_kg_m2 + dt * sp.viscous_N_m_s);
    }
    theta += w * dt;
    const double rpm = w / kRpm;
    update_modes(z[0]);
    if (seed_pending && (z[0] > pp.z_start_mm || z[n_tools - 1] > pp.z_start_mm)) {
      seed_pending = false;
      q[0] += pp.initial_disturbance_um * 1e-6;
      y += pp.initial_disturbance_um * 1e-6;
    }
    double fy = 0.0;
    for (int i = 0; i < n_tools; ++i) {  // TwinTurretCut::cut
      Edge& e = edges[i];
      const double n_rev = static_cast<double>(cells);
      const double cell = (theta - e.alpha) / (2.0 * kPi) * n_rev;
      const double at = cell - e.lag * n_rev + (e.lag == 0.0 ? 1.0 : 0.0);
      e.s = z[i] - read(ring_z, at);
      const double d_read = read(ring_d, at);
      const double pen = e.sigma * y - 0.0;
      e.b = e.t0 + (pen + pp.overlap * d_read) * 1e3;
      e.cutting = e.b > 0.0 && e.s > 0.0;
      if (e.cutting) {
        const double b = e.b / sin_k, h = e.s * sin_k;
        e.fc = mat.Fc.k11_N_per_mm2 * b * std::pow(h, 1.0 - mat.Fc.m) * kk;
        e.fp = mat.Fp.k11_N_per_mm2 * b * std::pow(h, 1.0 - mat.Fp.m) * kk;
      } else {
        e.fc = e.fp = 0.0;
      }
      const auto back = static_cast<long long>(e.lag) * static_cast<long long>(cells);
      const auto now = static_cast<long long>(std::floor(cell));
      for (long long c = std::max(e.last_cell + 1, now - m + 1); c <= now; ++c) {
        const std::size_t k = wrap(c);
        if (e.cutting) {
          ring_d[k] = -pen;
          ring_z[k] = z[i];
        } else if (back > 0) {
          const std::size_t k0 = wrap(c - back);
          ring_d[k] = ring_d[k0];
          ring_z[k] = ring_z[k0];
        }
      }
      if (now > e.last_cell) e.last_cell = now;
      fy -= e.sigma * (e.fp + 0.0);
    }
    y = 0.0;
    for (int j = 0; j < pp.modes; ++j) {
      const double qn = p11[j] * q[j] + p12[j] * qd[j] + g1[j] * fy;
      const double qdn = p21[j] * q[j] + p22[j] * qd[j] + g2[j] * fy;
      q[j] = qn;
      qd[j] = qdn;
      y += qn;
    }
    if (!std::isfinite(y) || std::abs(y) > 0.05) sound = false;
    y_hp = hb0 * y + hb1 * hx1 + hb2 * hx2 - ha1 * hy1 - ha2 * hy2;
    hx2 = hx1;
    hx1 = y;
    hy2 = hy1;
    hy1 = y_hp;
    if (step % chain_every == 0) machine.sense(y);
    if (step % record_every == 0) {
      const auto& mo = machine.output();
      const auto& pl = mo.plan;
      const double cut_power = (0.0 + edges[0].fc * (kPi * D * rpm / 60.0)) +
                               (n_tools > 1 ? edges[1].fc * (kPi * D * rpm / 60.0) : 0.0);
      const double row[28] = {
          t, z[0], z[1], y * 1e6, y_hp * 1e6, machine.chain().a0_m() * 1e6,
          machine.chain().omega_d() / (2.0 * kPi), v[0], v[1], cmd[0], cmd[1],
          edges[0].cutting ? edges[0].s : 0.0, n_tools > 1 && edges[1].cutting ? edges[1].s : 0.0,
          edges[0].cutting ? edges[0].b : 0.0, n_tools > 1 && edges[1].cutting ? edges[1].b : 0.0,
          edges[0].fp, n_tools > 1 ? edges[1].fp : 0.0, cut_power, machine.power().cutting_W(),
          power_el(), rpm, mo.engaged ? 1.0 : 0.0, static_cast<double>(mo.reason),
          pl.s_min_mm_per_min, pl.ds_mm_per_min, pl.dl_mm, static_cast<double>(pl.n_s), 0.0};
      r.values.insert(r.values.end(), row, row + 28);
    }
    t += dt;
    if (z[0] >= cfg.z_end_mm && (n_tools == 1 || z[1] >= cfg.z_end_mm)) break;
  }
  r.rows = r.values.size() / r.channels;
  r.t_s = t;
  r.x = z[0];
  r.force_N = edges[0].fp;
  r.y_m = y;
  r.sound = sound;
  return r;
}

}  // namespace lathectl::bench
