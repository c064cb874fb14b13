// Proves that controllers do not allocate in update(): global operator new is replaced by a
// counting version (as Drake's LimitMalloc does) and thousands of update() calls must leave the
// count at zero — including through sensor faults and alarm paths. The same for the lathe plant
// that LinuxCNC's servo thread steps.

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include "lathectl/control/adaptive_feed_controller.hpp"
#include "lathectl/control/adaptive_input.hpp"
#include "lathectl/control/adaptive_machine.hpp"
#include "lathectl/control/gauge_machine.hpp"
#include "lathectl/control/modulated_feed.hpp"
#include "lathectl/control/modulation_machine.hpp"
#include "lathectl/control/operation_control.hpp"
#include "lathectl/control/pulse_feed_controller.hpp"
#include "lathectl/control/slide_machine.hpp"
#include "lathectl/cutting/lathe_plant.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/scenario.hpp"
#include "lathectl/sensors/vibration_chain.hpp"
#include "lathectl/sensors/vibro_contact_gauge.hpp"
#include "support/sample_controller.hpp"
#include "systems/a_pulse_feed/metrics.hpp"
#include "systems/a_pulse_feed/settings.hpp"
#include "systems/e_adaptive/settings.hpp"
#include "systems/registry.hpp"

namespace {
std::atomic<long> g_allocations{0};
}

void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  return operator new(n);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}

using lathectl::control::PulseFeedController;

static PulseFeedController::Params params(PulseFeedController::Modulation m,
                                          PulseFeedController::Mode mode) {
  return lathectl::testing::sample_pulse_feed_params(m, mode);
}

TEST(NoAlloc, PulseFeedControllerUpdateNeverAllocates) {
  for (auto m :
       {PulseFeedController::Modulation::Amplitude, PulseFeedController::Modulation::Frequency})
    for (auto mode : {PulseFeedController::Mode::Finishing, PulseFeedController::Mode::Roughing}) {
      PulseFeedController c;
      c.configure(params(m, mode));  // may allocate
      PulseFeedController::Output out;
      const long before = g_allocations.load();
      for (int k = 0; k < 20000; ++k) {
        double u = 1.0 + 0.5 * std::sin(k * 0.01);
        if (k > 15000 && k < 15010) u = std::nan("");  // fault path
        PulseFeedController::Input in{u};
        c.update(in, out);
        if (k == 16000) c.reset_alarm();
      }
      EXPECT_EQ(g_allocations.load() - before, 0) << "update() allocated";
      EXPECT_TRUE(std::isfinite(out.slot_m));
    }
}

using lathectl::control::AdaptiveFeedController;

// What lathectl_adaptive runs around the controller every servo period: per-operation settings
// (valid and refused), the idle tare learning and its fit, a teach cut, the operation record.
// System A's machine side through every path: laws along the travel, program changes, off/on,
// overload, breakage, sensor faults, alarm resets.
TEST(NoAlloc, SlideMachineUpdateNeverAllocates) {
  using lathectl::control::SlideMachine;
  for (auto m :
       {PulseFeedController::Modulation::Amplitude, PulseFeedController::Modulation::Frequency}) {
    SlideMachine::Params p;
    p.controller = params(m, PulseFeedController::Mode::Roughing);
    p.feed_law = {{0.0, 1e-3}, {0.01, 2e-3}, {0.02, 0.5e-3}};
    p.force_law = {{0.0, 200.0}, {0.02, 150.0}};
    SlideMachine sm;
    sm.configure(p);  // may allocate
    sm.start(200.0);
    const long before = g_allocations.load();
    for (int k = 0; k < 20000; ++k) {
      SlideMachine::Input in;
      const double force = k < 12000 ? 200.0 + 150.0 * std::sin(k * 0.01) : 400.0;
      in.sensor_V = 5e-3 * force;
      if (k > 15000 && k < 15010) in.sensor_V = std::nan("");
      if (k > 17000 && k < 17010) in.sensor_V = 0.0;  // collapse: breakage
      in.mode = (k / 3000) % 2 ? PulseFeedController::Mode::Finishing
                               : PulseFeedController::Mode::Roughing;
      in.enable = (k / 1000) % 7 != 3;
      in.position_m = 1e-6 * k;
      in.reset_alarm = k % 2500 == 0;
      sm.update(in);
    }
    EXPECT_EQ(g_allocations.load() - before, 0) << "update() allocated";
    EXPECT_TRUE(std::isfinite(sm.output().slot_m));
  }
}

// Rig A's plant under an outside controller, as lathectl_slide_plant steps it in LinuxCNC's base
// thread: streamed rows into A's metrics, the valve's pulses and the eccentric's command given.
TEST(NoAlloc, SlidePlantStepNeverAllocates) {
  namespace a = lathectl::systems::a_pulse_feed;
  const auto lib = lathectl::io::MaterialLibrary::load(LATHECTL_SOURCE_DIR "/data/materials.toml");
  auto sc = lathectl::systems::load_scenario(
      LATHECTL_SOURCE_DIR "/examples/linuxcnc/slide_finishing.toml", lib);
  a::Rig rig;
  rig.set_streamed(true, false);
  rig.set_external(true);
  rig.configure(sc.get<a::Settings>().rig, sc.run.step_s, sc.run.record_interval_s, 2.0);
  a::MetricsAccumulator acc(rig, rig.last_record_time());
  acc.set_plot(false);
  rig.attach(&acc);  // may allocate
  const long before = g_allocations.load();
  for (int k = 0; k < 20000; ++k) {  // 2 s at 100 µs
    a::Rig::Actuation act;
    act.valve_open = k % 500 < 50;  // 20 Hz, 5 ms pulses
    act.slot_cmd_m = 45e-6;
    act.frequency_Hz = 20.0;
    rig.actuate(act);
    rig.step();
  }
  EXPECT_EQ(g_allocations.load() - before, 0) << "the plant's step allocated";
  EXPECT_GT(rig.position(), 0.0);
}

TEST(NoAlloc, OperationControlNeverAllocates) {
  AdaptiveFeedController c;
  c.configure({});
  lathectl::control::IdleTare tare;
  tare.configure({});
  lathectl::control::TeachIn teach;
  lathectl::control::OperationStats stats;
  const lathectl::control::OperationRating rating{5000.0, 0.8, 200.0};
  AdaptiveFeedController::Output out;
  int refs = 0;
  const long before = g_allocations.load();
  teach.start();
  for (int k = 0; k < 20000; ++k) {
    const double rpm = 300.0 + 250.0 * (k / 1000 % 8);
    const bool cut = k % 4000 > 1500;
    const double load = cut ? 1000.0 + 50.0 * std::sin(k * 0.3) : 0.0;
    (void)c.set_operation(k % 3000 < 1500 ? 1200.0 : -1.0, 0.05, 0.6, k % 7000 < 5000);
    (void)lathectl::control::check_limit(k % 2 ? 6000.0 : 1000.0, rating);
    (void)lathectl::control::split_feed_override(0.001 * (k % 3000), 1.0, 1.5, 0.001, 1.0, 1.0,
                                                 k % 5 != 0);
    (void)lathectl::control::check_feeds(0.05, k % 2 ? 0.9 : 0.4, rating);
    tare.update(rpm, 300.0 + 0.3 * rpm + 1e-4 * rpm * rpm, 0.002, !cut);
    (void)tare.idle_W(rpm);
    (void)tare.covers(rpm);
    refs += teach.sample(load, rpm, 0.002, cut) ? 1 : 0;
    if (!teach.running()) teach.start();
    stats.sample(load, load, cut, 0.8, 0.002, cut);
    if (k % 4000 == 0) stats.reset();
    AdaptiveFeedController::Input in;
    in.force = load;
    in.rpm = rpm;
    in.feed_block = cut;
    c.update(in, out);
  }
  EXPECT_EQ(g_allocations.load() - before, 0) << "allocated";
  EXPECT_GT(refs, 0);
  EXPECT_TRUE(tare.ready());
}

// Seed 004's controller through every path: the three modes, the per-revolution mean and the raw
// sample, the depth-corrected law, air cut, contact, regulation with runout, the power and speed
// limits, rapids, a NaN fault with its latched alarm, and reset_alarm().
TEST(NoAlloc, AdaptiveFeedControllerUpdateNeverAllocates) {
  using Mode = AdaptiveFeedController::Mode;
  for (Mode mode : {Mode::Fixed, Mode::ForceFeed, Mode::ForceFeedSpeed})
    for (bool per_rev : {true, false})
      for (double xv : {0.0, 0.15}) {
        AdaptiveFeedController::Params p;
        p.mode = mode;
        p.load_limit = 2500.0;
        p.feed_programmed_mm_per_rev = 0.5;
        p.feed_min_mm_per_rev = 0.05;
        p.feed_max_mm_per_rev = 0.8;
        p.air_feed_mm_per_rev = 0.5;
        p.depth_exponent_xv = xv;
        p.force_model_C = 3000.0;
        p.cut_power_max_W = 8000.0;
        p.rpm_min = 20.0;
        p.rpm_max = 3000.0;
        p.average_per_revolution = per_rev;
        p.sensor_monitor = {-500.0, 20000.0, 0.05, 0.0};
        AdaptiveFeedController c;
        c.configure(p);  // may allocate (the per-revolution ring)
        AdaptiveFeedController::Output out;
        double feed = 0.0;
        int alarms = 0, rapids = 0, air = 0, cut = 0;
        const long before = g_allocations.load();
        for (int k = 0; k < 20000; ++k) {
          const int phase = k % 5000;  // per block: air, cut, rapid
          const bool block = phase < 4500;
          const bool in_air = phase < 300;
          lathectl::control::AdaptiveSignals in;  // as the rig and the HAL component build it
          in.feed_block = block;
          in.rpm = 600.0 + 100.0 * std::sin(k * 1e-3);
          in.speed_m_per_min = 150.0 * in.rpm / 600.0;
          in.feed_rate_mm_per_min = feed * in.rpm;
          // plant: force ∝ feed (with runout), plus a heavier zone that drives the power limit
          const double k_plant = (k / 2500) % 2 ? 9000.0 : 6000.0;
          in.force = !block || in_air
                         ? 5.0 * std::sin(k * 0.7)
                         : k_plant * std::max(feed, 0.05) * (1.0 + 0.2 * std::sin(k * 0.2));
          in.idle_power_W = 500.0;
          in.spindle_power_W = 500.0 + in.force * in.speed_m_per_min / 60.0;
          if (k >= 12000 && k < 12005) in.force = std::nan("");  // fault path
          c.update(
              lathectl::control::adaptive_input(lathectl::cutting::ForceParameter::Pz, in), out);
          feed = out.feed_per_rev_mm;
          alarms += out.alarm ? 1 : 0;
          rapids += block ? 0 : 1;
          air += block && !out.in_cut ? 1 : 0;
          cut += out.in_cut ? 1 : 0;
          if (k == 12500) c.reset_alarm();
        }
        EXPECT_EQ(g_allocations.load() - before, 0) << "update() allocated";
        EXPECT_TRUE(std::isfinite(out.feed_per_rev_mm));
        EXPECT_GT(rapids, 0);
        if (mode != Mode::Fixed) {  // the paths were really taken
          EXPECT_GT(alarms, 0);
          EXPECT_GT(air, 0);
          EXPECT_GT(cut, 0);
          EXPECT_FALSE(out.alarm);
        }
      }
}

// The Input builder the rig and the HAL component share, for every force parameter.
TEST(NoAlloc, AdaptiveInputNeverAllocates) {
  using lathectl::cutting::ForceParameter;
  double sum = 0.0;
  const long before = g_allocations.load();
  for (int k = 0; k < 3000; ++k) {
    lathectl::control::AdaptiveSignals s;
    s.force = k % 100 == 0 ? std::nan("") : 1000.0 + k;
    s.spindle_power_W = 4000.0;
    s.idle_power_W = 500.0;
    s.speed_m_per_min = 120.0;
    for (auto p : {ForceParameter::Pz, ForceParameter::Py, ForceParameter::Power})
      sum += lathectl::control::adaptive_input(p, s).cut_power_W;
  }
  EXPECT_EQ(g_allocations.load() - before, 0) << "adaptive_input() allocated";
  EXPECT_GT(sum, 0.0);
}

// The LinuxCNC plant component's model runs in the servo thread too.
TEST(NoAlloc, LathePlantStepNeverAllocates) {
  const auto lib = lathectl::io::MaterialLibrary::load(LATHECTL_SOURCE_DIR "/data/materials.toml");
  auto sc = lathectl::systems::load_scenario(
      LATHECTL_SOURCE_DIR "/examples/linuxcnc/step_allowance_sensor_fault.toml", lib);
  lathectl::cutting::LathePlant plant;
  plant.configure(sc.get<lathectl::systems::e_adaptive::Settings>().rig, {});  // may allocate
  lathectl::cutting::LathePlant::Output out;
  const long before = g_allocations.load();
  for (int k = 0; k < 20000; ++k) {  // 20 s: air, cut, the collar, the sensor fault, unhomed
    lathectl::cutting::LathePlant::Input in{18.0, 2.0 - 0.005 * k, 1000.0};
    if (k > 19000) in.x_mm = std::nan("");
    plant.step(in, 1e-3, out);
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_GT(out.time_in_cut_s, 10.0);
}

// System E's machine side through every path: force and power sensors, the stock model's
// path-aware breakage, the program's settings (good, bad, taught percentages), teach-in, the
// tool table's overload levels, tool changes, the tool data changing in a feed move, rapids,
// arcs, G94 and G95, the operator's knob, resets, and operation records.
TEST(NoAlloc, AdaptiveMachineUpdateNeverAllocates) {
  using lathectl::control::AdaptiveMachine;
  const auto lib = lathectl::io::MaterialLibrary::load(LATHECTL_SOURCE_DIR "/data/materials.toml");
  auto sc = lathectl::systems::load_scenario(
      LATHECTL_SOURCE_DIR "/examples/linuxcnc/step_allowance_sensor_fault.toml", lib);
  const auto& rig = sc.get<lathectl::systems::e_adaptive::Settings>().rig;
  for (bool power : {false, true}) {
    AdaptiveMachine::Params mp;
    mp.controller = rig.controller;
    mp.controller.period_s = 0.002;
    mp.power_sensor = power;
    mp.spindle = rig.spindle;
    mp.power_lag_s = 0.02;
    mp.rating = {5000.0, 0.8, 200.0};
    mp.tools = {{.number = 1, .limit = 1200.0, .warn_pct = 110.0, .hold_pct = 300.0},
                {.number = 2, .adaptive = false}};
    mp.taught = {{1, 3, 1000.0}};
    mp.stock_model = true;
    mp.process = rig;
    mp.z_origin_mm = 0.0;
    AdaptiveMachine m;
    m.configure(mp);  // may allocate
    AdaptiveMachine::Output out;
    int records = 0;
    const long before = g_allocations.load();
    for (int k = 0; k < 40000; ++k) {  // 40 s at 1 ms
      AdaptiveMachine::Input in;
      in.nominal_period_s = 0.001;
      in.elapsed_s = k % 997 == 0 ? 0.004 : 0.001;  // a late period now and then
      const int phase = k / 2000;  // 2 s each
      const bool cut = k % 2000 > 300;
      in.motion_type = cut ? (phase % 5 == 4 ? 3 : 2) : 1;
      in.per_rev = phase % 3 != 2;
      in.rpm = 800.0 + 100.0 * (phase % 4);
      in.rpm_programmed = phase % 7 == 6 ? -in.rpm : in.rpm;
      in.requested_vel = in.per_rev ? 0.3 : 4.0;
      in.feed_upm = 240.0;
      in.current_vel_mm_s = 4.0;
      in.x_mm = 18.0;
      in.z_mm = 2.0 - 0.004 * (k % 2000);
      in.force = cut ? 1000.0 + 60.0 * std::sin(k * 0.3) : (phase == 9 ? 0.0 : 5.0);
      in.spindle_power_W = 500.0 + (cut ? 4000.0 : 0.0) + 10.0 * std::sin(k * 0.7);
      in.mode_cmd = phase % 6 == 1 ? 3.0 : phase % 6 == 2 ? 4.0 : phase % 6 == 3 ? 0.5 : 0.0;
      in.operation_cmd = 3.0;
      in.limit_cmd = phase % 8 == 5 ? -1.0 : 0.0;
      in.tool_number = phase % 5 == 3 ? 2 : 1;
      in.program_line = 10 + phase;
      in.tool_diameter = phase == 12 && k % 2000 == 1000 ? 0.5 : 0.0;
      in.knob = phase % 4 == 1 ? 0.5 : 1.0;
      in.max_override = 1.5;
      in.scale_in_motion = 1.0;
      in.reset = k % 5000 == 0;
      in.enable = phase != 15;
      m.update(in, out);
      records = out.op.seq;
    }
    m.end_operation(out);
    EXPECT_EQ(g_allocations.load() - before, 0) << (power ? "power" : "force");
    EXPECT_GT(records, 10);
  }
}

// Seed 001's module and its measurement chain through every path: below the dead zone, engaging,
// re-planning as the vibration grows, the limited plan, the turret flag changing (a new block),
// the programmed variant, no power, the end of the block.
TEST(NoAlloc, ModulatedFeedControllerAndVibrationChainNeverAllocate) {
  using namespace lathectl::control;
  using lathectl::sensors::PowerSensor;
  using lathectl::sensors::VibrationChain;
  ModulatedFeedController::Params p;
  p.desync_fraction = 1.0;
  ModulatedFeedController m;
  m.configure(p);
  VibrationChain chain;
  chain.configure({});
  PowerSensor power;
  PowerSensor::Params pp;
  pp.idle_table_rpm = {100.0, 1000.0, 3000.0};
  pp.idle_table_W = {300.0, 500.0, 1500.0};
  power.configure(pp, 1e-3);
  ModulatedFeedController::Output out;
  ModulatedFeedController::Input in;
  in.feed_programmed_mm_per_min[0] = in.feed_programmed_mm_per_min[1] = 100.0;
  in.speed_m_per_min = 100.0;
  in.rpm = 800.0;
  int engaged = 0;
  const long before = g_allocations.load();
  for (int k = 0; k < 40000; ++k) {
    const double amp = k < 5000 ? 1e-6 : (k < 20000 ? 1e-5 * (1.0 + k / 5000.0) : 50e-6);
    for (int s = 0; s < 10; ++s)
      chain.update(amp * std::sin(2.0 * 3.14159265 * 230.0 * (k * 10 + s) * 1e-4));
    power.update(2000.0 + 100.0 * std::sin(k * 0.01), 800.0, k < 1000);
    in.a0_m = chain.a0_m();
    in.omega_d_rad_per_s = chain.omega_d();
    in.cut_power_W = k % 7000 < 100 ? 0.0 : power.cutting_W();
    in.feed_block = k % 9000 > 50;
    in.turret = (k / 9000) % 2 ? Turret::Left : Turret::Right;
    in.source = k > 30000 ? ModulationSource::Programmed : ModulationSource::Automatic;
    in.programmed = {50.0, 10.0, 0.05, 4};
    in.path_mm[0] += 100.0 / 60.0 * 1e-3;
    in.path_mm[1] += 100.0 / 60.0 * 1e-3;
    m.update(in, out);
    engaged += out.engaged;
  }
  EXPECT_EQ(g_allocations.load() - before, 0) << "update() allocated";
  EXPECT_GT(engaged, 1000);
  VibrationChain accelerometer;  // a real sensor's input
  accelerometer.configure({});
  const long at = g_allocations.load();
  for (int k = 0; k < 10000; ++k) accelerometer.update_acceleration(20.0 * std::sin(k * 0.14));
  EXPECT_EQ(g_allocations.load() - at, 0) << "update_acceleration() allocated";
}

// System B's machine side as the rig and lathectl_modfeed run it: the chain fed at its sample
// rate, the idle block, growing chatter, re-plans, the planner's own thread posting (a planner
// that has run), the turret flag changing, external detectors, the programmed variant.
TEST(NoAlloc, ModulationMachineNeverAllocates) {
  using namespace lathectl::control;
  for (bool with_planner : {false, true}) {
    ModulationMachine::Params p;
    p.module.desync_fraction = 1.0;
    ModulationMachine m;
    m.configure(p);  // may allocate
    ModulationPlanner planner;
    if (with_planner) m.use_planner(&planner);
    ModulationMachine::Input in;
    in.feed_requested = 0.125;  // G95: 0.125 mm/rev at 800 rpm, 100 mm/min
    in.feed_per_rev = true;
    in.feed_rpm = 800.0;
    in.speed_m_per_min = 100.0;
    in.rpm = 800.0;
    int engaged = 0;
    const long before = g_allocations.load();
    for (int k = 0; k < 30000; ++k) {
      const double amp = k < 5000 ? 1e-6 : (k < 15000 ? 1e-5 * (1.0 + k / 5000.0) : 50e-6);
      for (int s = 0; s < 10; ++s)
        m.sense(amp * std::sin(2.0 * 3.14159265 * 230.0 * (k * 10 + s) * 1e-4));
      in.idle_block = k > 100 && k < 1000;
      in.motor_power_W = 2000.0 + (in.idle_block ? 0.0 : 1500.0) + 100.0 * std::sin(k * 0.01);
      in.feed_block = !in.idle_block && k % 9000 > 50;
      in.turret = (k / 9000) % 2 ? Turret::Left : Turret::Right;
      in.external_detectors = k > 20000 && k < 25000;
      in.a0_m = 20e-6;
      in.omega_d_rad_per_s = 1400.0;
      in.source = k > 25000 ? ModulationSource::Programmed : ModulationSource::Automatic;
      in.programmed = {50.0, 10.0, 0.05, 4};
      in.path_mm[0] += 100.0 / 60.0 * 1e-3;
      in.path_mm[1] += 100.0 / 60.0 * 1e-3;
      m.update(in);
      if (with_planner && k % 10 == 0) (void)planner.run(m.controller());
      engaged += m.output().engaged;
    }
    EXPECT_EQ(g_allocations.load() - before, 0) << "update() allocated";
    EXPECT_GT(engaged, 1000);
  }
}

TEST(NoAlloc, GaugeMachineAndVibroContactGaugeNeverAllocate) {
  // Every filter and every path: steps, their relay, the backstop, a lost and a NaN signal, rearm,
  // bridged interruptions, interruptions too close for the bridge.
  using lathectl::control::GaugeMachine;
  using lathectl::sensors::GaugeFilterKind;
  for (auto kind : {GaugeFilterKind::FirstOrder, GaugeFilterKind::SecondOrder,
                    GaugeFilterKind::Synchronous}) {
    lathectl::sensors::VibroContactGauge::Params tp;
    tp.filter = kind;
    tp.filter_time_constant_s = 0.02;
    lathectl::sensors::VibroContactGauge gauge;
    gauge.configure(tp, 2e-5);
    GaugeMachine m;
    GaugeMachine::Params p;
    p.period_s = 2e-5;
    p.filter = lathectl::sensors::VibroContactGauge::filter_params(tp);
    const double free = gauge.free_signal_V();
    p.steps = {{0.3 * free, GaugeMachine::Command::Fine},
               {0.5 * free, GaugeMachine::Command::SparkOut},
               {0.7 * free, GaugeMachine::Command::Size}};
    p.arm_after_s = 0.05;
    p.backstop_m = -1.0;
    p.signal_lost_V = 0.01 * free;
    p.free_signal_V = free;
    p.initial_signal_V = free;
    p.gate_guard_s = 0.01;
    m.configure(p);
    // Interruptions too close for the bridge: gauge_no_round_surface.
    GaugeMachine dense;
    dense.configure(p);
    int stops = 0, trips = 0, no_round = 0;
    const long before = g_allocations.load();
    for (int k = 0; k < 60000; ++k) {
      const double t = k * 2e-5;
      const double x = gauge.free_amplitude_m() * (0.9 - 0.8 * std::fmod(t, 0.4) / 0.4);
      GaugeMachine::Input in;
      in.generator_V = gauge.step_generator(x);
      if (k % 20000 > 19000) in.generator_V = 0.0;                      // lost
      if (k % 20000 == 19990) in.generator_V = std::nan("");            // not finite
      in.position_m = k % 20000 > 18000 ? -2.0 : 0.0;                   // backstop
      in.rearm = k % 20000 < 2;  // each ramp a part
      in.gate = k % 5000 < 400;  // an interruption bridged, then its guard
      m.update(in);
      stops += m.output().stop;
      trips += m.output().tripped;
      in.gate = k % 1000 < 100;  // every 20 ms: never two supply periods of round surface
      dense.update(in);
      no_round += dense.output().reason == lathectl::control::Reason::GaugeNoRoundSurface;
    }
    EXPECT_EQ(g_allocations.load() - before, 0) << "update() allocated";
    EXPECT_GT(no_round, 0);
    EXPECT_GT(stops, 1000);
    EXPECT_GT(trips, 0) << static_cast<int>(kind);
  }
}
