// Systems C and D streamed: the paths the golden summaries do not take give the same
// numbers. C's cone waviness from a second run of the rig (when a cone's window has more rows
// than TracerMetrics keeps) equals the one from the kept rows; D's linearised parts machined again
// block by block (beyond LinearParts' budget) equal the parts machined at once. The path the
// examples take is compared with the summaries the recorded columns gave (tests/golden).

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>

#include "lathectl/io/scenario.hpp"
#include "support/library.hpp"
#include "support/scenario_text.hpp"
#include "systems/c_tracer/settings.hpp"
#include "systems/c_tracer/study.hpp"
#include "systems/d_gauging/rig.hpp"

namespace lathectl {
namespace {

TEST(SystemCStreamed, WavinessFromASecondRunEqualsTheKeptRows) {
  const auto sc = io::parse_scenario(test::example_text("c_stepped_tapered_fast"), "mem.toml",
                                     test::library(), systems::c_tracer::kSection);
  const auto kept = systems::c_tracer::run(sc);
  const auto again = systems::c_tracer::run(sc, 0);
  EXPECT_EQ(kept.summary.dump(), again.summary.dump());
  EXPECT_GT(kept.summary["metrics"]["cone_waviness_um"].get<double>(), 0.0);
  EXPECT_EQ(kept.channels_csv, again.channels_csv);  // no stage: in memory
  EXPECT_GT(kept.channels_csv.size(), 1000u);
}

std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v); }

TEST(SystemDStreamed, PartsMachinedAgainBlockByBlockAreTheSameParts) {
  using F = sensors::VibroContactGauge::Params::Filter;
  systems::d_gauging::GaugingProcess p;  // the defaults: noise D = 4 µm², β = 5/s
  p.backstop_m = 45e-6;
  for (F f : {F::FirstOrder, F::Synchronous}) {
    const systems::d_gauging::LinearGauge g{19844.0, 298e-6, 0.1, f, 50.0};
    const double th = systems::d_gauging::threshold_23(g, p);
    const auto all = systems::d_gauging::monte_carlo_linear(p, g, th, 3000, 7);
    systems::d_gauging::LinearParts again(p, g, th, 3000, 7, /*kept=*/0, /*block=*/1024);
    for (int pass = 0; pass < 2; ++pass) {
      std::size_t n = 0;
      again.for_each([&](std::size_t i, const systems::d_gauging::PartResult& r) {
        ASSERT_EQ(i, n++);
        EXPECT_EQ(bits(r.trip_s), bits(all[i].trip_s)) << i;
        EXPECT_EQ(bits(r.stop_s), bits(all[i].stop_s)) << i;
        EXPECT_EQ(bits(r.finished_m), bits(all[i].finished_m)) << i;
        EXPECT_EQ(bits(r.noise_at_nominal_V), bits(all[i].noise_at_nominal_V)) << i;
        EXPECT_EQ(r.backstop, all[i].backstop) << i;
      });
      EXPECT_EQ(n, all.size());
    }
  }
}

}  // namespace
}  // namespace lathectl
