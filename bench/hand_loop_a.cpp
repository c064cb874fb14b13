// Rig A's stepping written by hand (see hand_loops.hpp): systems/a_pulse_feed/rig.cpp with the
// models it steps (cutting_model.cpp's radial force and tool life, disturbances.cpp's depth
// profile, inductive_sensor.cpp, pulse_regulator.cpp, eccentric_drive.cpp, feed_slide.cpp)
// written out in one function, the same operations in the same order. The ring of positions
// wraps by a compare, not by `%`. Rows go to a flat array.

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>

#include "hand_loops.hpp"
#include "lathectl/control/slide_machine.hpp"
#include "lathectl/cutting/feed_range.hpp"
#include "systems/a_pulse_feed/machine_params.hpp"

namespace lathectl::bench {

namespace {
using systems::a_pulse_feed::ControllerKind;
using systems::a_pulse_feed::RegulatorKind;
using systems::a_pulse_feed::RigConfig;

void require_supported(const RigConfig& c) {
  const auto& d = c.part;
  if (c.regulator_kind != RegulatorKind::Pulsed || c.controller_kind == ControllerKind::Fim ||
      c.cutting.form != cutting::ForceForm::Handbook || d.runout_mm > 0.0 ||
      d.random_sigma_mm > 0.0 || !d.hardness.empty() || d.wear_force_gain_per_mm != 0.0 ||
      !c.faults.empty() || c.regulator.obliteration.layer_max_m > 0.0 ||
      c.cutting.material.tool_life_ranges == 0)
    throw std::invalid_argument("hand_loop_a: a set-up the hand loop does not cover");
}

// The eccentric's profile, linear between points (eccentric_drive.cpp's interp).
double interp(const std::vector<double>& xs, const std::vector<double>& ys, double x) noexcept {
  if (x <= xs.front()) return ys.front();
  if (x >= xs.back()) return ys.back();
  const auto it = std::upper_bound(xs.begin(), xs.end(), x);
  const auto i = static_cast<std::size_t>(it - xs.begin());
  const double t = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
  return ys[i - 1] + t * (ys[i] - ys[i - 1]);
}
}  // namespace

HandRun hand_loop_a(const RigConfig& cfg, double dt, double record_interval, double duration) {
  require_supported(cfg);
  constexpr double kPi = std::numbers::pi;
  const bool aim = cfg.controller_kind == ControllerKind::Aim;
  const auto mp = systems::a_pulse_feed::machine_params(cfg, {});
  const auto& sp = cfg.slide;
  const auto& rp = cfg.regulator;
  const auto& sn = cfg.sensor;
  const auto& mat = cfg.cutting.material;
  const auto& ep = cfg.eccentric;
  const double feed = cfg.controller.feed_m_per_s;
  const double pw = cfg.pulse_width_s;
  const std::size_t record_every =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(record_interval / dt)));
  const double rev_per_s = cfg.spindle_rpm / 60.0;
  const double speed = kPi * cfg.diameter_m * cfg.spindle_rpm;
  const double kmp = std::pow(mat.strength / mat.strength_base, mat.kmp_exponent);
  const double k_force = kmp * 1.0 * 1.0;  // × hardness_kp(1) × wear factor 1
  const double speed_term = std::pow(std::max(speed, 1.0), mat.Py.n);
  const double Fn = systems::a_pulse_feed::nominal_force_N(cfg);
  const double first_change =
      cfg.part.depth_steps.empty() ? std::numeric_limits<double>::infinity()
                                   : cfg.part.depth_steps.front().at_mm;
  auto depth_profile = [&](double x) {
    double depth = cfg.part.depth_mm;
    for (const auto& s : cfg.part.depth_steps) {
      if (x <= s.at_mm) break;
      const double ramp = cfg.part.step_ramp_mm > 0.0
                              ? std::min((x - s.at_mm) / cfg.part.step_ramp_mm, 1.0)
                              : 1.0;
      depth += (s.value - depth) * ramp;
    }
    return depth;
  };
  // The slide in steady motion (FeedSlide::set_steady).
  double v = feed, x = 0.0, vd = 0.0, pc = 0.0, pd = 0.0;
  {
    const double drive = Fn + sp.viscous_friction_N_s_per_m * feed +
                         (feed > 0.0 ? sp.coulomb_friction_N : 0.0);
    pc = std::max(drive / sp.piston_area_m2, 0.0);
    const double q = sp.piston_area_m2 * feed + sp.leak_m3_per_s_Pa * pc;
    pd = pc + (sp.damper_capacitance_m3_per_Pa > 0.0 ? q * sp.damper_resistance_Pa_s_per_m3 : 0.0);
  }
  double delivered = 0.0, leaked = 0.0;
  auto slide_step = [&](double q_in, double load) {  // FeedSlide::step
    const double F = sp.piston_area_m2;
    const double drv = F * pc - load;
    const double fc = sp.coulomb_friction_N, m = sp.mass_kg, b = sp.viscous_friction_N_s_per_m;
    if (v == 0.0 && std::abs(drv) <= fc) {
      v = 0.0;
    } else {
      const double sgn = v != 0.0 ? (v > 0.0 ? 1.0 : -1.0) : (drv > 0.0 ? 1.0 : -1.0);
      const double v_new = (m * v + dt * (drv - fc * sgn)) / (m + dt * b);
      v = (v != 0.0 && v_new * v < 0.0) ? 0.0 : v_new;
    }
    x += v * dt;
    double q_d = q_in;
    if (sp.damper_capacitance_m3_per_Pa > 0.0) {
      q_d = std::min((pd - pc) / sp.damper_resistance_Pa_s_per_m3,
                     q_in + sp.damper_capacitance_m3_per_Pa * pd / dt);
      pd += dt * (q_in - q_d) / sp.damper_capacitance_m3_per_Pa;
      pd = std::max(pd, 0.0);
    }
    const double vol = sp.dead_volume_m3 + F * std::max(x, 0.0);
    const double swept = F * v * dt;
    const double leak = sp.leak_m3_per_s_Pa * pc;
    delivered += q_in * dt;
    leaked += leak * dt;
    if (vd > 0.0) {
      vd -= q_d * dt - swept;
      if (vd < 0.0) {
        pc = -vd * sp.bulk_modulus_Pa / vol;
        vd = 0.0;
      }
    } else {
      pc += dt * sp.bulk_modulus_Pa / vol * (q_d - F * v - leak);
      if (pc < 0.0) {
        vd = -pc * vol / sp.bulk_modulus_Pa;
        pc = 0.0;
      }
    }
  };
  // The pulse regulator (PulseRegulator::step and move, no obliteration layer).
  const double gain = rp.orifice.gain_per_m();
  const double inf = std::numeric_limits<double>::infinity();
  const double v_open = rp.opening_time_s > 0.0 ? (rp.lap_m + rp.max_slot_m) / rp.opening_time_s : inf;
  const double v_close = rp.closing_time_s > 0.0 ? (rp.lap_m + rp.max_slot_m) / rp.closing_time_s : inf;
  double phase = 0.0, y = -rp.lap_m;
  auto regulator_step = [&](double h, double f) {
    h = std::clamp(h, 0.0, rp.max_slot_m);
    if (y > h) y = h;
    const double closed = -rp.lap_m;
    const double duty = f > 0.0 ? std::clamp(pw * f, 0.0, 1.0) : 0.0;
    const bool pulsing = duty > 0.0 && duty < 1.0;
    double area = 0.0, remaining = dt;
    while (remaining > 0.0) {
      bool on = duty >= 1.0;
      double seg = remaining, t_edge = 0.0;
      if (pulsing) {
        on = phase < duty;
        t_edge = ((on ? duty : 1.0) - phase) / f;
        if (t_edge <= 1e-15) {
          phase = on ? duty : 0.0;
          continue;
        }
        seg = std::min(remaining, t_edge);
      }
      const double target = on ? h : closed, vs = on ? v_open : v_close;
      const double t_reach = std::isinf(vs) ? 0.0 : std::abs(target - y) / vs;
      auto pos_area = [](double y0, double y1, double tau) {
        if (y0 >= 0.0 && y1 >= 0.0) return 0.5 * (y0 + y1) * tau;
        if (y0 <= 0.0 && y1 <= 0.0) return 0.0;
        const double hi = std::max(y0, y1);
        return 0.5 * hi * (hi / std::abs(y1 - y0)) * tau;
      };
      if (t_reach >= seg) {
        const double y1 = y + (target > y ? 1.0 : -1.0) * vs * seg;
        area += pos_area(y, y1, seg);
        y = y1;
      } else {
        area += pos_area(y, target, t_reach) + std::max(target, 0.0) * (seg - t_reach);
        y = target;
      }
      if (pulsing) phase = seg == t_edge ? (on ? duty : 0.0) : phase + seg * f;
      remaining -= seg;
    }
    if (area <= 0.0 || h <= 0.0) return 0.0;
    return gain * area / dt * (h / h);
  };
  // The machine side and its first command (Rig::set_fixed_actuator, start_machine).
  const double q_needed = feed * sp.piston_area_m2 + sp.leak_m3_per_s_Pa *
                                                         (Fn + mp.controller.friction_N) /
                                                         sp.piston_area_m2;
  const double fixed = q_needed / (mp.controller.regulator_gain_per_m * pw * cfg.frequency_Hz);
  control::SlideMachine machine;
  machine.configure(mp);
  machine.start(Fn);
  control::SlideMachine::Output out{};
  out.slot_m = aim ? std::clamp(machine.controller().actuator_for(feed, Fn),
                                mp.controller.slot_min_m, mp.controller.slot_max_m)
                   : fixed;
  out.pulses = true;
  const std::size_t control_every = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::llround(mp.controller.period_s / dt)));
  // The eccentric drive (EccentricDrive::set_slot, step).
  const auto& pa = ep.profile_angle_rad;
  const auto& ps = ep.profile_slot_m;
  double theta = 0.0, omega = 0.0, slot = 0.0, last_cmd = -1.0, target_angle = 0.0;
  theta = interp(ps, pa, out.slot_m);
  slot = interp(pa, ps, theta);
  const double motor_decay =
      ep.motor_time_constant_s > 0.0 ? std::exp(-dt / ep.motor_time_constant_s) : 0.0;
  // Warm-up at the nominal load (Rig::warm_up).
  const double warm_s = std::max(0.5, 10.0 / cfg.frequency_Hz);
  for (double tw = 0.0; tw < warm_s; tw += dt) slide_step(regulator_step(out.slot_m, cfg.frequency_Hz), Fn);
  x = 0.0;
  delivered = leaked = 0.0;
  // The path before t = 0 (Rig::prime_history), the sensor steady (InductiveSensor).
  const std::size_t rev_steps = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::llround(1.0 / rev_per_s / dt)));
  const std::size_t window_steps = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::llround(cfg.feed_window_s / dt)));
  const std::size_t n_hist = std::max(rev_steps, 2 * window_steps) + 1;
  std::vector<double> hist(n_hist, 0.0);
  for (std::size_t k = 0; k < n_hist; ++k)
    hist[(n_hist - k) % n_hist] = -feed * dt * static_cast<double>(k);
  std::size_t head = 0;
  auto ago = [&](std::size_t s) { return hist[head >= s ? head - s : head + n_hist - s]; };
  double force = Fn, depth = depth_profile(0.0);
  const double vpn = sn.gain_V_per_m / sn.holder_stiffness_N_per_m;
  double u = sn.offset_V + sn.gain_V_per_m * Fn / sn.holder_stiffness_N_per_m;
  double sensor_u = sn.offset_V + vpn * Fn;
  const double sensor_decay = sn.time_constant_s > 0.0 ? std::exp(-dt / sn.time_constant_s) : 0.0;
  std::mt19937_64 rng(sn.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  auto sample = [&] {
    const double noise = sn.noise_V > 0.0 ? sn.noise_V * normal(rng) : 0.0;
    return std::clamp(u + noise, 0.0, sn.saturation_V);
  };
  // The recorded feed's window: whole pulse periods at the fixed frequency (Rig::record_row).
  const double periods = std::max(1.0, std::round(cfg.feed_window_s * cfg.frequency_Hz));
  const std::size_t w = std::clamp<std::size_t>(
      static_cast<std::size_t>(std::llround(periods / cfg.frequency_Hz / dt)), 1, n_hist - 1);
  // The power laws' last bases (CuttingModel's LastPow).
  double depth_b = std::numeric_limits<double>::quiet_NaN(), depth_x = 0.0;
  double life_depth_b = depth_b, life_depth_e = depth_b, life_depth = 0.0;
  double life_feed_b = depth_b, life_feed_e = depth_b, life_feed = 0.0;

  HandRun r;
  r.channels = 17;
  const auto steps = static_cast<std::size_t>(std::llround(duration / dt));
  r.values.reserve((steps / record_every + 1) * r.channels);
  double t = 0.0, phi = 0.0, life = 0.0, life_td = 0.0, t_dist = -1.0, flow_acc = 0.0,
         force_acc = 0.0;
  std::size_t acc_n = 0;
  for (std::size_t step = 1; step <= steps; ++step) {
    t += dt;
    phi += 2.0 * kPi * rev_per_s * dt;
    if (phi > 2.0 * kPi) phi -= 2.0 * kPi;
    const double x_mm = x * 1000.0;
    if (t_dist < 0.0 && x_mm >= first_change) t_dist = t;
    depth = std::max(depth_profile(x_mm), 0.0);
    const double chip = std::max((x - ago(rev_steps)) * 1000.0, 0.0);
    double life_s = inf;
    if (!(depth > 0.0) || !(chip > 0.0)) {
      force = 0.0;
    } else {
      if (depth != depth_b) depth_x = std::pow(depth_b = depth, mat.Py.x);
      force = 10.0 * mat.Py.Cp * depth_x * std::pow(chip, mat.Py.y) * speed_term * k_force;
      const auto& lr = cutting::feed_range(mat.tool_life, mat.tool_life_ranges, chip);
      if (!(depth == life_depth_b && lr.xv == life_depth_e))
        life_depth = std::pow(life_depth_b = depth, life_depth_e = lr.xv);
      if (!(chip == life_feed_b && lr.yv == life_feed_e))
        life_feed = std::pow(life_feed_b = chip, life_feed_e = lr.yv);
      life_s = 60.0 * std::pow(lr.Cv * 1.0 / (speed * life_depth * life_feed), 1.0 / lr.m);
    }
    const double used = dt / life_s;
    life += used;
    if (t_dist >= 0.0) life_td += used;
    const double target_u = sn.offset_V + sn.gain_V_per_m * force / sn.holder_stiffness_N_per_m;
    u = target_u + (u - target_u) * sensor_decay;
    double q = 0.0;
    if (aim) {
      if (step % control_every == 0) {
        sensor_u = sample();
        control::SlideMachine::Input in;
        in.sensor_V = sensor_u;
        in.mode = cfg.controller.mode;
        in.feed_m_per_s = feed;
        in.force_set_N = cfg.controller.force_set_N;
        in.position_m = x;
        machine.update(in);
        out = machine.output();
      }
      if (out.slot_m != last_cmd) target_angle = interp(ps, pa, last_cmd = out.slot_m);
      const double w_cmd =
          std::clamp(ep.position_gain_per_s * (target_angle - theta) * ep.gear_ratio,
                     -ep.motor_max_speed_rad_per_s, ep.motor_max_speed_rad_per_s);
      const double w_new = w_cmd + (omega - w_cmd) * motor_decay;
      theta += 0.5 * (omega + w_new) / ep.gear_ratio * dt;
      omega = w_new;
      if (theta <= pa.front() || theta >= pa.back()) {
        theta = std::clamp(theta, pa.front(), pa.back());
        omega = 0.0;
      }
      slot = interp(pa, ps, theta);
      q = regulator_step(slot, out.pulses ? cfg.frequency_Hz : 0.0);
    } else {
      q = regulator_step(fixed, cfg.frequency_Hz);
    }
    slide_step(q, force);
    if (!std::isfinite(v) || !std::isfinite(pc)) r.sound = false;
    head = head + 1 == n_hist ? 0 : head + 1;
    hist[head] = x;
    flow_acc += q;
    force_acc += force;
    ++acc_n;
    if (step % record_every != 0) continue;
    const double n = static_cast<double>(acc_n);
    if (!aim) sensor_u = sample();
    const double estimate = (sensor_u - sn.offset_V) / vpn;
    const double row[17] = {t, x * 1000.0, (x - ago(w)) / (static_cast<double>(w) * dt) * 60000.0,
                            std::max((x - ago(rev_steps)) * 1000.0, 0.0), force_acc / n,
                            aim ? out.force_estimate_N : estimate, depth, sensor_u,
                            (aim ? slot : fixed) * 1e6, cfg.frequency_Hz,
                            flow_acc / n * (1e6 * 60.0), sp.leak_m3_per_s_Pa * pc * (1e6 * 60.0),
                            pc * 1e-6, static_cast<double>(out.reason), out.alarm ? 1.0 : 0.0,
                            0.0 * 1e6, 1.0};
    r.values.insert(r.values.end(), row, row + 17);
    flow_acc = force_acc = 0.0;
    acc_n = 0;
  }
  r.rows = r.values.size() / r.channels;
  r.t_s = t;
  r.x = x;
  r.force_N = force;
  r.life_used = life;
  r.life_used_td = life_td;
  r.t_disturbance_s = t_dist;
  r.delivered_m3 = delivered;
  r.leaked_m3 = leaked;
  return r;
}

}  // namespace lathectl::bench
