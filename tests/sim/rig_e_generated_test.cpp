// System E on parts nobody wrote by hand: the generator of valid scenarios
// (sim/e_part_generator.hpp), each read as a user's scenario file is and run closed-loop in the
// rig `lathectl run` uses.
//
// Invariants on every part (a sound tool, so any alarm is false):
//   - the part is finished;
//   - no alarm, unless the limit cannot be held even at the minimum feed (overload, code 20,
//     is then the clear reason the acceptance asks for: checked against the handbook's force at
//     the part's deepest cut and hardest spot);
//   - the per-revolution force (or power) within 5 % of its limit: the goal is every part. With
//     the feed-forward from the stock model the steps and corners the model knows are met at
//     the feed their depth takes (without it: 96 % within 5 %, the worst 31 % over, on power at a
//     shoulder's corner). Measured with it: 98 % within 5 %, the worst 6.3 % over, most of them
//     entries from air into a full-depth cut, where the feed's ramp outran the per-revolution
//     mean that ends it. With the ramp also stopped by the present sample above the limit:
//     199 of 200 within 5 %, the worst 5.6 % over (an entry on power, seed 1156); with power
//     readings held while the spindle's acceleration cannot be separated from them (an
//     inertia still to be learned): all 200, the worst 4.8 % over. Widened (issue 47: every
//     fifth part a forged shaft run off into its neck, eccentric with a hard spot, on the
//     spindle's power at its limit, 160-300 m/min): 80.5 %, the worst 21.2 % over; with the
//     runout capped at an earlier pass's surface, the integral counted in revolutions above
//     600 rpm, the program's speed in air and the per-revolution mean over one revolution
//     exactly: 81 %, the worst 12.6 % (the 160 others 99.4 %, 6.8 %). With a braking drive's
//     friction taken off on the shaft's side, the integral driven by the specific force's trend
//     (a hardness ramp) and the metric summed every simulation step (Rig::load_rev: seed 1146's
//     6.8 % was 5.6 % on its 20 ms record) and the idle tare's prior law through its nearest bin
//     (a one-bin constant read a braking cut 6 % low): 94.5 %, the worst 6.4 % (forged: 30 of 40
//     within, median 4.6 %; the 160 others 99.4 %, 5.6 %). With the plant's runout decided where
//     the nose meets fresh material and a pass within the runout above the blank's mean radius
//     marking its high side (without the mark seed 1157 went 10.6 % over): the 160 all within,
//     the worst 4.4 %; forged 24 of 40, the worst 6.3 %. With the regulator comparing the
//     per-revolution mean one revolution ahead while it rises with the limit (its trend from the
//     load at the same angle a revolution ago: a hardness ramp or a deeper random allowance had
//     shown in the mean a revolution late; on the earlier plant 184 -> 199 of 200): all 200 within
//     5 %, the worst 4.7 % (forged: 40 of 40, median 3.2 %; the 160 others all within, 3.0 %).
//     With the feed's own commanded change taken out of that trend (it had driven a limit cycle,
//     e_worn_tool's prior art 0.14 <-> 0.18 mm/rev every 2.6 revolutions) and the rise already in
//     flight counted instead: 199 of 200 within 5 %, the worst 5.3 % (forged: 39 of 40, median
//     3.9 %; the 160 others all within, the worst 4.1 %).
//     The test holds 99 % within 5 % and every part within 7.5 % on the whole generator and on
//     the 160 round-3 parts alone, so a regression shows, and prints the distribution and the
//     worst parts of both kinds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "lathectl/control/types.hpp"
#include "lathectl/core/parallel.hpp"
#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/cutting/force_parameter.hpp"
#include "lathectl/io/scenario.hpp"
#include "sim/e_part_generator.hpp"
#include "support/library.hpp"
#include "systems/e_adaptive/metrics.hpp"
#include "systems/e_adaptive/rig.hpp"
#include "systems/e_adaptive/settings.hpp"
#include "systems/registry.hpp"

namespace lathectl::systems::e_adaptive {
namespace {

using lathectl::test::library;
using generated::Part;
using generated::generate;

struct Outcome {
  unsigned seed = 0;
  bool finished = false;
  std::vector<sim::AlarmEvent> alarms;
  double over_pct = 0.0;       // per-revolution peak above the limit
  bool reachable = true;       // the limit can be held at the minimum feed
  std::string what, error;
};

Outcome run_part(unsigned seed) {
  const Part part = generate(seed);
  Outcome o;
  o.seed = seed;
  o.what = part.what;
  try {
    const io::Scenario sc = systems::parse_scenario(part.text, "generated.toml", library());
    const RigConfig& cfg = sc.get<Settings>().rig;
    Rig rig;
    rig.configure(cfg, sc.run.step_s, sc.run.record_interval_s, sc.run.duration_s);
    MetricsAccumulator acc(rig);
    rig.attach(&acc);
    rig.run();
    const Metrics m = acc.result(rig);
    o.finished = m.finished;
    o.alarms = m.alarms;
    o.over_pct = 100.0 * (m.force_peak_rev_mean / cfg.controller.load_limit - 1.0);
    o.reachable = generated::limit_reachable(cfg);
  } catch (const std::exception& e) {
    o.error = e.what();
  }
  return o;
}

// A failing part's scenario is left beside the test (ctest's working directory) for
// `lathectl run generated_SEED.toml`.
std::string keep(const Outcome& o) {
  std::ofstream("generated_" + std::to_string(o.seed) + ".toml") << generate(o.seed).text;
  return o.what;
}

bool is_forged(const Outcome& o) { return o.seed % 5 == 0; }  // generate(): every fifth seed

struct Stats {
  std::size_t parts = 0, reachable = 0;
  double within = 0.0, median = 0.0, p90 = 0.0, worst = 0.0;
  std::vector<const Outcome*> worst3;
};

enum class Kind { Other, Forged, All };

// Per-revolution peak over the limit, of the parts of one kind whose limit is reachable.
Stats stats(const std::vector<Outcome>& out, Kind which) {
  Stats st;
  std::vector<const Outcome*> kind;
  for (const auto& o : out) {
    if (which != Kind::All && is_forged(o) != (which == Kind::Forged)) continue;
    ++st.parts;
    if (o.reachable) kind.push_back(&o);
  }
  st.reachable = kind.size();
  if (kind.empty()) return st;
  std::sort(kind.begin(), kind.end(),
            [](const Outcome* a, const Outcome* b) { return a->over_pct < b->over_pct; });
  auto q = [&](double p) {
    return kind[static_cast<std::size_t>(p * static_cast<double>(kind.size() - 1))]->over_pct;
  };
  st.within = static_cast<double>(std::count_if(kind.begin(), kind.end(),
                                                [](const Outcome* o) { return o->over_pct <= 5.0; })) /
              static_cast<double>(kind.size());
  st.median = q(0.5);
  st.p90 = q(0.9);
  st.worst = kind.back()->over_pct;
  for (std::size_t i = 0; i < std::min<std::size_t>(3, kind.size()); ++i)
    st.worst3.push_back(kind[kind.size() - 1 - i]);
  return st;
}

// The worst three are left beside the test too, to be run and looked at.
void print(const char* kind, const Stats& st) {
  std::printf("%s: %zu (%zu with a limit not reachable at the minimum feed); per-rev peak over the "
              "limit: median %.1f %%, 90th %.1f %%, max %.1f %%; within 5 %%: %.0f %%\n",
              kind, st.parts, st.parts - st.reachable, st.median, st.p90, st.worst,
              100.0 * st.within);
  for (const Outcome* o : st.worst3) {
    std::printf("  %.1f %% over: %s\n", o->over_pct, o->what.c_str());
    keep(*o);
  }
}

TEST(RigEGenerated, EveryGeneratedPartIsFinishedWithNoFalseAlarm) {
  constexpr unsigned kParts = 200;
  std::vector<Outcome> out(kParts);
  core::parallel_for(kParts, [&](std::size_t i) { out[i] = run_part(1000u + static_cast<unsigned>(i)); });
  // Every part finished, with no alarm but an overload where the limit is out of reach.
  for (const auto& o : out) {
    ASSERT_TRUE(o.error.empty()) << keep(o) << ": " << o.error;
    EXPECT_TRUE(o.finished) << keep(o);
    for (const auto& a : o.alarms)
      EXPECT_TRUE(a.code == static_cast<int>(control::Reason::Overload) && !o.reachable)
          << keep(o) << ": alarm " << control::reason_name(static_cast<control::Reason>(a.code))
          << " at " << a.time_s << " s";
  }
  // The acceptance (≥ 99 % of parts within 5 % of the limit, the worst ≤ 7.5 %) holds on the
  // whole generator, issue 47's forged shafts on power (every fifth seed) with the round-3
  // kinds of part; and on the round-3 kinds alone, so a regression there is not hidden by the
  // forged class.
  const Stats other = stats(out, Kind::Other), forged = stats(out, Kind::Forged),
              all = stats(out, Kind::All);
  print("round-3 parts", other);
  print("forged shafts on power (issue 47)", forged);
  std::printf("all %zu parts: within 5 %%: %.1f %%, worst %.1f %%\n", all.parts,
              100.0 * all.within, all.worst);
  ASSERT_GT(other.reachable, 0u);
  ASSERT_GT(forged.reachable, 0u);
  EXPECT_GE(all.within, 0.99);
  EXPECT_LE(all.worst, 7.5);
  EXPECT_GE(other.within, 0.99);
  EXPECT_LE(other.worst, 7.5);
}

}  // namespace
}  // namespace lathectl::systems::e_adaptive
