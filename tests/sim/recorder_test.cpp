// sim::Recorder streamed: rows go to the sinks as they come and into a bounded
// min/max pyramid per channel; the row-by-row forms of the whole-record metrics give the
// same numbers bit for bit.

#include "lathectl/sim/recorder.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "lathectl/io/channel_stream.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/sim/metrics.hpp"
#include "lathectl/control/per_revolution.hpp"

namespace lathectl::sim {
namespace {

TEST(Recorder, StreamedKeepsABoundedPyramidPerChannelWithTheExtremes) {
  // 64 values per level at most: 100 000 rows keep no level over 64 (level 0 dropped), and the
  // static plot's points (at most 128, from the finest level that fits) keep the extremes, a
  // one-row spike included.
  Recorder r = Recorder::streamed({{"time_s", "s"}, {"v", ""}}, {}, 64);
  std::vector<double> x, y;
  for (int i = 0; i < 64; ++i) {
    const double row[2] = {static_cast<double>(i), std::sin(i)};
    r.push_row(row);
  }
  r.plot_points("v", x, y);
  ASSERT_EQ(x.size(), 64u);  // the samples themselves while they fit (as floats)
  for (int i = 0; i < 64; ++i) {
    EXPECT_EQ(y[static_cast<std::size_t>(i)], static_cast<float>(std::sin(i)));
    EXPECT_DOUBLE_EQ(x[static_cast<std::size_t>(i)], i);
  }
  float lo = 1e9f, hi = -1e9f;
  for (int i = 0; i < 100000; ++i) {
    const double v = i < 64 ? std::sin(i) : i == 77777 ? 50.0 : std::sin(0.001 * i);
    lo = std::min(lo, static_cast<float>(v));
    hi = std::max(hi, static_cast<float>(v));
    if (i < 64) continue;
    const double row[2] = {static_cast<double>(i), v};
    r.push_row(row);
  }
  const auto p = r.plot_pyramid("v");
  ASSERT_TRUE(p);
  EXPECT_EQ(p->samples(), 100000u);
  ASSERT_FALSE(p->levels().empty());
  EXPECT_GT(p->levels().front().bucket, 1u);  // level 0 went over 64 values
  for (const auto& l : p->levels()) EXPECT_LE(l.y.size(), 64u);
  p->points(x, y, 128);
  EXPECT_LE(x.size(), 128u);
  EXPECT_TRUE(std::is_sorted(x.begin(), x.end()));
  EXPECT_EQ(*std::min_element(y.begin(), y.end()), lo);
  EXPECT_EQ(*std::max_element(y.begin(), y.end()), hi);
  EXPECT_EQ(*std::max_element(y.begin(), y.end()), 50.0);
}

TEST(Recorder, StreamedHandsRowsToSinksAndWritesTheSameCsv) {
  const std::vector<Channel> ch{{"time_s", "s"}, {"a", ""}, {"b", ""}};
  Recorder cols(ch, 1000);
  io::ChannelStream stream(ch);
  Recorder streamed = Recorder::streamed(ch, {&stream});
  for (int i = 0; i < 1000; ++i) {
    const double row[3] = {0.01 * i, std::exp(-0.01 * i), i % 7 == 0 ? NAN : 1e-9 * i};
    cols.push_row(row);
    streamed.push_row(row);
  }
  EXPECT_EQ(streamed.rows(), 1000u);
  EXPECT_TRUE(streamed.column("a").empty());  // nothing kept
  EXPECT_EQ(stream.text(), io::channels_csv(cols));
  std::vector<double> x, y;
  streamed.plot_points("a", x, y);
  EXPECT_LE(x.size(), 4096u);
  EXPECT_EQ(y.front(), 1.0);
}

TEST(Recorder, StreamedWithoutPlotsOnlyHandsRowsToSinks) {
  const std::vector<Channel> ch{{"time_s", "s"}, {"a", ""}};
  io::ChannelStream stream(ch);
  Recorder r = Recorder::streamed(ch, {&stream}, 0);  // a run that is only measured
  for (int i = 0; i < 100; ++i) {
    const double row[2] = {0.01 * i, 1.0 * i};
    r.push_row(row);
  }
  EXPECT_EQ(r.rows(), 100u);
  std::vector<double> x{1.0}, y{1.0};
  r.plot_points("a", x, y);
  EXPECT_TRUE(x.empty() && y.empty());
  EXPECT_EQ(r.plot_pyramid("a"), nullptr);
  EXPECT_EQ(std::count(stream.text().begin(), stream.text().end(), '\n'), 101);
}

TEST(OnlineMetrics, MatchTheWholeRecordFormsBitForBit) {
  std::vector<double> t, x, rpm, alarm;
  for (int i = 0; i < 5000; ++i) {
    t.push_back(0.002 * (i + 1));
    x.push_back(1000.0 + 300.0 * std::sin(0.37 * i) + 0.1 * i);
    rpm.push_back(i < 2000 ? 600.0 : 900.0 + 0.1 * i);
    alarm.push_back((i / 700) % 2 ? 1.0 : 0.0);
  }
  const auto batch_rev = control::per_revolution_mean(x, rpm, t[1] - t[0]);
  control::PerRevolutionMean rev;  // the interval given at the second sample, as a run learns it
  const auto batch_avg = moving_average(x, 37);
  MovingAverage avg(37);
  MeanBetween mb{1.0, 7.5};
  const std::vector<sensors::SensorFault> faults{sensors::SensorFault{}};
  AlarmOnsets onsets(faults);
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (i == 1) rev.configure(t[1] - t[0]);
    ASSERT_EQ(rev.push(x[i], rpm[i]), batch_rev[i]) << i;
    ASSERT_EQ(avg.push(x[i]), batch_avg[i]) << i;
    mb.push(t[i], x[i]);
    onsets.push(t[i], alarm[i], 3.0);
  }
  EXPECT_EQ(mb.value(), mean_between(t, x, 1.0, 7.5));
  double first = 0.0;
  EXPECT_EQ(onsets.events().size(),
            alarm_onsets(t, alarm, std::vector<double>(t.size(), 3.0), faults, first).size());
  EXPECT_EQ(onsets.first_delay_s(), first);
}

}  // namespace
}  // namespace lathectl::sim
