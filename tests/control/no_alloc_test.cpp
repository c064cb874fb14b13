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
#include "lathectl/control/pulse_feed_controller.hpp"
#include "lathectl/io/materials.hpp"
#include "lathectl/io/scenario.hpp"
#include "lathectl/sim/lathe_plant.hpp"
#include "support/sample_controller.hpp"

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
        (void)c.update(in, out);
        if (k == 16000) c.reset_alarm();
      }
      EXPECT_EQ(g_allocations.load() - before, 0) << "update() allocated";
      EXPECT_TRUE(std::isfinite(out.slot_m));
    }
}

using lathectl::control::AdaptiveFeedController;

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
        p.force_limit = 2500.0;
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
          AdaptiveFeedController::Input in;
          in.feed_block = block;
          in.rpm = 600.0 + 100.0 * std::sin(k * 1e-3);
          in.speed_m_per_min = 150.0 * in.rpm / 600.0;
          in.feed_rate_mm_per_min = feed * in.rpm;
          // plant: force ∝ feed (with runout), plus a heavier zone that drives the power limit
          const double k_plant = (k / 2500) % 2 ? 9000.0 : 6000.0;
          in.force = !block || in_air
                         ? 5.0 * std::sin(k * 0.7)
                         : k_plant * std::max(feed, 0.05) * (1.0 + 0.2 * std::sin(k * 0.2));
          in.cut_power_W = in.force * in.speed_m_per_min / 60.0;
          if (k >= 12000 && k < 12005) in.force = std::nan("");  // fault path
          (void)c.update(in, out);
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

// The LinuxCNC plant component's model runs in the servo thread too.
TEST(NoAlloc, LathePlantStepNeverAllocates) {
  const auto lib = lathectl::io::MaterialLibrary::load(LATHECTL_SOURCE_DIR "/data/materials.toml");
  auto sc = lathectl::io::load_scenario(
      LATHECTL_SOURCE_DIR "/examples/linuxcnc/step_allowance_sensor_fault.toml", lib);
  lathectl::sim::LathePlant plant;
  plant.configure(sc.e, {});  // may allocate
  lathectl::sim::LathePlant::Output out;
  const long before = g_allocations.load();
  for (int k = 0; k < 20000; ++k) {  // 20 s: air, cut, the collar, the sensor fault, unhomed
    lathectl::sim::LathePlant::Input in{18.0, 2.0 - 0.005 * k, 1000.0};
    if (k > 19000) in.x_mm = std::nan("");
    plant.step(in, 1e-3, out);
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_GT(out.time_in_cut_s, 10.0);
}
