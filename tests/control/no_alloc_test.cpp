// Proves that controllers do not allocate in update(): global operator new is replaced by a
// counting version (as Drake's LimitMalloc does) and thousands of update() calls must leave the
// count at zero — including through sensor faults and alarm paths.

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include "lathectl/control/pulse_feed_controller.hpp"
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
