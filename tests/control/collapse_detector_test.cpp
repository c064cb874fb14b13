// control::CollapseDetector: the one "load collapses within a window" detector. Its two questions
// are checked against the three hand-written detectors it replaced, kept here as references, on
// long random sequences (bit for bit: the same decisions in every period).

#include "lathectl/control/collapse_detector.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <limits>
#include <random>

namespace lathectl::control {
namespace {

// AdaptiveFeedController's and PathBreakage's: the time since the load was last above half the
// limit (the limit then in force), and a fall below air within the window.
struct SinceHighReference {
  double high_since_s = 1e9;
  bool update(double load, double limit, double air, double window_s, double elapsed) {
    high_since_s = load > 0.5 * limit ? 0.0 : high_since_s + elapsed;
    return load < air && high_since_s <= window_s;
  }
};

// SlideMachine's: a fall of more than `drop` below the largest of the last n samples, once n are
// there.
struct RingReference {
  static constexpr std::size_t kN = 256;
  std::array<double, kN> hist{};
  std::size_t n = 1, head = 0, filled = 0;
  bool update(double est, double drop) {
    bool fired = false;
    if (filled >= n) {
      double peak = est;
      for (std::size_t k = 1; k <= n; ++k) peak = std::max(peak, hist[(head + kN - k) % kN]);
      fired = peak - est > drop;
    }
    hist[head] = est;
    head = (head + 1) % kN;
    if (filled < n) ++filled;
    return fired;
  }
};

TEST(CollapseDetector, FellToIsTheTimeSinceLoadedRule) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (double window : {0.0, 0.004, 0.01, 0.05}) {
    CollapseDetector d(window);
    SinceHighReference ref;
    int fired = 0;
    for (int i = 0; i < 200000; ++i) {
      const double limit = i % 5000 < 2500 ? 1000.0 : 800.0;  // a new operation's limit
      // a loaded cut with collapses to air, periods of 1 ms, some late or early
      const double load = u(rng) < 0.02 ? 20.0 * u(rng) : 400.0 + 300.0 * u(rng);
      const double elapsed = u(rng) < 0.05 ? 0.0004 + 0.004 * u(rng) : 0.001;
      if (i % 997 == 0) {
        d.reset();
        ref.high_since_s = 1e9;
      }
      if (u(rng) < 0.01) {  // a period not judged: time passes
        d.pass(elapsed);
        ref.high_since_s += elapsed;
        continue;
      }
      const double air = 0.1 * limit;
      const bool want = ref.update(load, limit, air, window, elapsed);
      if (load > 0.5 * limit)
        d.push(load, elapsed);
      else
        d.pass(elapsed);
      ASSERT_EQ(d.fell_to(load, air), want) << "window " << window << ", period " << i;
      fired += want;
    }
    if (window > 0.0) {
      EXPECT_GT(fired, 100);
    }
  }
}

TEST(CollapseDetector, FellByIsTheSlidesRingRule) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::size_t n : {1u, 3u, 10u, 255u}) {
    CollapseDetector d(static_cast<double>(n));
    RingReference ref;
    ref.n = n;
    int fired = 0;
    for (int i = 0; i < 100000; ++i) {
      if (i % 1499 == 0) {  // the slide switched on again
        d.reset();
        ref.filled = 0;
      }
      // a slowly wandering force with sudden falls and rises
      const double est = u(rng) < 0.01 ? 100.0 * u(rng) : 800.0 + 200.0 * u(rng);
      const double drop = 0.6 * 1000.0;
      const bool want = ref.update(est, drop);
      d.push(est, 1.0);
      ASSERT_EQ(d.pushed() > n && d.fell_by(est, drop), want) << "n " << n << ", sample " << i;
      fired += want;
    }
    EXPECT_GT(fired, 100);
  }
}

TEST(CollapseDetector, AFullQueueKeepsTheNewestSample) {
  // A window far longer than the capacity, a load falling slowly past it: the newest loaded
  // sample is still there, so the level question stays exact.
  CollapseDetector d(10.0);
  for (int i = 0; i < 1000; ++i) d.push(1000.0 - i, 0.001);
  EXPECT_EQ(d.peak(), 1000.0 - 999.0 + 255.0);  // the oldest 744 were forgotten
  d.pass(5.0);
  EXPECT_TRUE(d.fell_to(0.0, 1.0));
  d.pass(5.1);
  EXPECT_FALSE(d.fell_to(0.0, 1.0));
}

TEST(CollapseDetector, NonFiniteSamplesOnlyAge) {
  CollapseDetector d(2.0);
  d.push(5.0, 1.0);
  d.push(std::numeric_limits<double>::quiet_NaN(), 1.0);
  EXPECT_EQ(d.pushed(), 2u);
  EXPECT_EQ(d.peak(), 5.0);
  EXPECT_FALSE(d.fell_by(std::numeric_limits<double>::quiet_NaN(), 1.0));
  EXPECT_TRUE(d.fell_by(1.0, 3.0));
  d.pass(1.5);  // age 2.5 > 2
  EXPECT_FALSE(d.any());
}

}  // namespace
}  // namespace lathectl::control
