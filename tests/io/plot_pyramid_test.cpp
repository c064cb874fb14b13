// The interactive plots' data: the min/max pyramid, its base64, the report's data
// block and size budget, and channels.csv read back for `lathectl compare`.
#include "lathectl/io/base64.hpp"
#include "lathectl/sim/plot_pyramid.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "lathectl/io/channels_reader.hpp"
#include "lathectl/io/errors.hpp"
#include "lathectl/io/output.hpp"
#include "lathectl/io/report.hpp"
#include "lathectl/sim/recorder.hpp"

namespace lathectl::io {
namespace {
using sim::PlotPyramid;

PlotPyramid build(const std::vector<double>& x, const std::vector<double>& y,
                  PlotPyramid::Options o = {}) {
  PlotPyramid p(o);
  for (std::size_t i = 0; i < x.size(); ++i) p.push(x[i], y[i]);
  p.finish();
  return p;
}

TEST(PlotPyramid, LevelsHoldTheSamplesThenEachBucketsExtremesInOrder) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  const std::size_t n = 10000;  // not a multiple of 4^k: partial last buckets
  std::vector<double> x(n), y(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = 0.5 + 1e-3 * static_cast<double>(i);
    y[i] = noise(rng);
  }
  PlotPyramid::Options o;
  o.coarsest_values = 100;
  const auto p = build(x, y, o);
  EXPECT_TRUE(p.uniform());
  EXPECT_TRUE(p.monotonic());
  EXPECT_NEAR(p.dx(), 1e-3, 1e-12);
  const auto& L = p.levels();
  ASSERT_GE(L.size(), 3U);
  ASSERT_EQ(L[0].bucket, 1U);
  ASSERT_EQ(L[0].y.size(), n);
  for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(L[0].y[i], static_cast<float>(y[i]));
  for (std::size_t k = 1; k < L.size(); ++k) {
    const std::size_t b = L[k].bucket;
    ASSERT_EQ(b, L[k - 1].bucket * 4);
    const std::size_t buckets = (n + b - 1) / b;
    ASSERT_EQ(L[k].y.size(), 2 * buckets) << "level " << k;
    EXPECT_TRUE(L[k].x.empty());  // uniform: positions follow from the index
    for (std::size_t j = 0; j < buckets; ++j) {  // brute force: min and max, in their order
      const auto first = y.begin() + static_cast<long>(j * b);
      const auto last = y.begin() + static_cast<long>(std::min(n, (j + 1) * b));
      const auto lo = std::min_element(first, last), hi = std::max_element(first, last);
      const float a = static_cast<float>(lo <= hi ? *lo : *hi);
      const float c = static_cast<float>(lo <= hi ? *hi : *lo);
      ASSERT_EQ(L[k].y[2 * j], a) << "level " << k << " bucket " << j;
      ASSERT_EQ(L[k].y[2 * j + 1], c) << "level " << k << " bucket " << j;
    }
  }
  EXPECT_LE(L.back().y.size(), o.coarsest_values);  // stops at the first level that small
  EXPECT_GT(L[L.size() - 2].y.size(), o.coarsest_values);
}

TEST(PlotPyramid, UnevenSpacingKeepsXAndGapsStayGaps) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> x, y;
  for (int i = 0; i < 40; ++i) {
    x.push_back(i < 20 ? i : 20 + 2 * (i - 20));  // the step doubles halfway
    y.push_back(i >= 8 && i < 16 ? nan : i);       // two whole buckets of 4 without data
  }
  x.push_back(std::numeric_limits<double>::infinity());  // cannot be placed: skipped
  y.push_back(1.0);
  PlotPyramid::Options o;
  o.coarsest_values = 4;
  const auto p = build(x, y, o);
  EXPECT_FALSE(p.uniform());
  EXPECT_EQ(p.samples(), 40U);
  const auto& L = p.levels();
  ASSERT_EQ(L[0].x.size(), 40U);
  EXPECT_EQ(L[0].x[39], 58.0f);
  EXPECT_TRUE(std::isnan(L[0].y[10]));
  // Level 1 (buckets of 4): buckets 2 and 3 are gaps; bucket 4 holds 16..19 (min 16 at x 16).
  ASSERT_EQ(L[1].y.size(), 20U);
  EXPECT_TRUE(std::isnan(L[1].y[4]) && std::isnan(L[1].y[7]));
  EXPECT_EQ(L[1].y[8], 16.0f);
  EXPECT_EQ(L[1].x[8], 16.0f);
  EXPECT_EQ(L[1].y[9], 19.0f);
  EXPECT_EQ(L[1].x[9], 19.0f);
}

TEST(PlotPyramid, ALevelOverItsBudgetIsDroppedAndTheCoarserOnesCarryOn) {
  std::vector<double> x(100000), y(100000);
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = static_cast<double>(i);
    y[i] = std::sin(0.01 * x[i]);
  }
  PlotPyramid::Options o;
  o.max_values_per_level = 30000;
  const auto p = build(x, y, o);
  const auto& L = p.levels();
  ASSERT_FALSE(L.empty());
  EXPECT_EQ(L[0].bucket, 16U);  // samples (100000) and pairs per 4 (50000) were over 30000
  for (const auto& l : L) EXPECT_LE(l.y.size(), o.max_values_per_level);
  EXPECT_EQ(L[0].y.size(), 2 * ((100000 + 15) / 16));
}

// push_row (a streamed recorder's row: x's bookkeeping once) gives each series what pushing it
// alone gives, bit for bit: uneven x, a non-finite x, gaps, ties, a short row.
TEST(PlotPyramid, ARowOfSeriesEqualsEachSeriesPushedAlone) {
  std::vector<PlotPyramid> alone(3), row(3);
  for (std::size_t r = 0; r < 5000; ++r) {
    const double t = 1e-3 * static_cast<double>(r) + (r > 3000 ? 1e-4 : 0.0);
    const double x = r == 700 ? std::nan("") : t;
    const double y[3] = {x, r % 97 == 0 ? std::nan("") : std::sin(1e-2 * static_cast<double>(r)),
                         std::floor(static_cast<double>(r % 13) / 4.0)};
    const std::size_t n = r == 2000 ? 2 : 3;  // the third series misses a row
    for (std::size_t i = 0; i < n; ++i) alone[i].push(x, y[i]);
    PlotPyramid::push_row(row, x, std::span<const double>(y, n));
  }
  for (std::size_t i = 0; i < 3; ++i) {
    alone[i].finish();
    row[i].finish();
    EXPECT_EQ(row[i].samples(), alone[i].samples());
    EXPECT_EQ(row[i].uniform(), alone[i].uniform());
    EXPECT_EQ(row[i].dx(), alone[i].dx());
    EXPECT_EQ(row[i].x_last(), alone[i].x_last());
    const auto &a = alone[i].levels(), &b = row[i].levels();
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < a.size(); ++k) {
      ASSERT_EQ(a[k].y.size(), b[k].y.size());
      ASSERT_EQ(a[k].x, b[k].x);
      for (std::size_t j = 0; j < a[k].y.size(); ++j)  // NaN (a gap) where the other has NaN
        ASSERT_TRUE(a[k].y[j] == b[k].y[j] || (std::isnan(a[k].y[j]) && std::isnan(b[k].y[j])));
    }
  }
  EXPECT_FALSE(row[0].uniform());  // the step at row 3000
  EXPECT_EQ(row[2].samples(), row[0].samples() - 1);
}

TEST(PlotPyramid, Base64IsRfc4648) {
  // RFC 4648 §10 test vectors.
  EXPECT_EQ(base64("", 0), "");
  EXPECT_EQ(base64("f", 1), "Zg==");
  EXPECT_EQ(base64("fo", 2), "Zm8=");
  EXPECT_EQ(base64("foo", 3), "Zm9v");
  EXPECT_EQ(base64("foob", 4), "Zm9vYg==");
  EXPECT_EQ(base64("fooba", 5), "Zm9vYmE=");
  EXPECT_EQ(base64("foobar", 6), "Zm9vYmFy");
  // 1.0f is 0x3f800000: little-endian bytes 00 00 80 3f.
  EXPECT_EQ(base64_floats({1.0f}), "AACAPw==");
}

Report time_report(std::size_t plots, std::size_t series, std::size_t n) {
  Report r;
  r.title = "t";
  for (std::size_t p = 0; p < plots; ++p) {
    Plot plot{"plot", "time [s]", "y", {}, {}};
    for (std::size_t s = 0; s < series; ++s) {
      Series ser;
      ser.name = "s" + std::to_string(s);
      for (std::size_t i = 0; i < n; ++i) {
        ser.x.push_back(1e-3 * static_cast<double>(i));
        ser.y.push_back(std::sin(1e-3 * static_cast<double>(i * (p * series + s + 1))));
      }
      plot.series.push_back(std::move(ser));
    }
    r.plots.push_back(std::move(plot));
  }
  return r;
}

nlohmann::json plot_data_of(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"lathectl-plot-data\">";
  const auto a = html.find(open);
  if (a == std::string::npos) return nullptr;
  const auto b = html.find("</script>", a);
  return nlohmann::json::parse(html.substr(a + open.size(), b - a - open.size()));
}

TEST(ReportInteractive, TimePlotsGetChartsDataAndTheLibraryInline) {
  Report r = time_report(2, 2, 5000);
  r.plots.push_back(Plot{"not over time", "speed [rpm]", "depth [mm]", {}, {}});
  r.plots.back().series.push_back(r.plots[0].series[0]);
  r.plots[1].series[0] = r.plots[0].series[0];  // the same channel twice: one pyramid
  const std::string html = render_html(r);
  const auto data = plot_data_of(html);
  ASSERT_TRUE(data.is_object());
  ASSERT_EQ(data["plots"].size(), 2U);  // the speed plot stays static
  EXPECT_EQ(data["plots"][0]["plot"], 0);
  EXPECT_EQ(data["plots"][1]["plot"], 1);
  EXPECT_EQ(data["blobs"].size(), 3U);
  EXPECT_EQ(data["plots"][1]["series"][0]["blob"], data["plots"][0]["series"][0]["blob"]);
  EXPECT_EQ(data["blobs"][0]["levels"][0]["b"], 1);  // the samples themselves
  EXPECT_NE(html.find("var uPlot="), std::string::npos);
  EXPECT_NE(html.find("window.lathectlPlots"), std::string::npos);
  EXPECT_NE(html.find("<div class=\"plot-box\" id=\"plot-2\">"), std::string::npos);
  EXPECT_NE(html.find("<polyline"), std::string::npos);  // the SVG fallback stays
  for (const char* net : {"<link", "@import", " src=", "fetch(", "XMLHttpRequest"})
    EXPECT_EQ(html.find(net), std::string::npos) << net;
}

TEST(ReportInteractive, ALongReportStaysUnderTenMegabytes) {
  // 40 series of 45 000 samples (B's longest run records 45 000 rows): over the budget with every
  // sample, so the finest levels are capped.
  const std::string html = render_html(time_report(10, 4, 45000));
  EXPECT_LT(html.size(), 10'000'000U);
  const auto data = plot_data_of(html);
  ASSERT_EQ(data["blobs"].size(), 40U);
  EXPECT_GT(data["blobs"][0]["levels"][0]["b"].get<int>(), 1);
  // Few series: every sample is kept.
  const auto small = plot_data_of(render_html(time_report(2, 2, 45000)));
  EXPECT_EQ(small["blobs"][0]["levels"][0]["b"], 1);
}

TEST(ChannelsReader, ReadsWhatARunWrites) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  sim::Recorder rec({{"time_s", "s"}, {"force_N", "N"}}, 4);
  rec.push_row(std::vector<double>{0.0, 1.25});
  rec.push_row(std::vector<double>{1e-3, nan});
  rec.push_row(std::vector<double>{2e-3, -inf});
  std::istringstream in(channels_csv(rec));
  const auto t = read_channels_csv(in, "c.csv");
  ASSERT_EQ(t.names, (std::vector<std::string>{"time_s", "force_N"}));
  ASSERT_EQ(t.columns[1].size(), 3U);
  EXPECT_EQ(t.columns[0][1], 1e-3);
  EXPECT_EQ(t.columns[1][0], 1.25);
  EXPECT_TRUE(std::isnan(t.columns[1][1]));
  EXPECT_EQ(t.columns[1][2], -inf);
}

TEST(ChannelsReader, BadInputNamesFileLineAndColumn) {
  const auto error = [](const std::string& text) {
    std::istringstream in(text);
    try {
      (void)read_channels_csv(in, "c.csv");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error(""), "c.csv:1: empty: no header line");
  EXPECT_EQ(error("t,,y\n"), "c.csv:1: column 2: empty column name");
  EXPECT_EQ(error("t,y,t\n"), "c.csv:1: column 3 't': named twice");
  EXPECT_EQ(error("t,y\n0,1\n1,x\n"), "c.csv:3: column 'y': expected a number, got 'x'");
  EXPECT_EQ(error("t,y\n0\n"), "c.csv:2: column 'y': missing (1 of 2 fields)");
  EXPECT_EQ(error("t,y\n0,1,2\n"), "c.csv:2: more fields than the 2 columns of the header");
  EXPECT_EQ(error("t,y\n0, 1\n"), "c.csv:2: column 'y': expected a number, got ' 1'");
  EXPECT_EQ(error("t,y\n\n0,1\n"), "c.csv:2: empty line");
  // A line is held whole: one over the bound (a sparse file, say) is refused at its number.
  EXPECT_EQ(error("t,y\n0,1\n" + std::string(kMaxChannelsLineBytes + 2, '1')),
            "c.csv:3: a line longer than 1 MiB: not a channels.csv (one row of numbers a line)");
}

// compare's reading: each row handed over as it is read (CRLF lines, a blank last line).
TEST(ChannelsReader, StreamsRowsToASink) {
  struct Sink final : ChannelRowSink {
    std::vector<std::string> names;
    std::vector<std::vector<double>> rows;
    void header(const std::vector<std::string>& n) override { names = n; }
    void row(std::span<const double> v) override { rows.emplace_back(v.begin(), v.end()); }
  } sink;
  std::istringstream in("time_s,y\r\n0,1.5\r\n0.25,-2\r\n1e-3,nan\r\n\r\n");
  read_channels_csv(in, "c.csv", sink);
  ASSERT_EQ(sink.names, (std::vector<std::string>{"time_s", "y"}));
  ASSERT_EQ(sink.rows.size(), 3U);
  EXPECT_EQ(sink.rows[1], (std::vector<double>{0.25, -2.0}));
  EXPECT_EQ(sink.rows[2][0], 1e-3);
  EXPECT_TRUE(std::isnan(sink.rows[2][1]));
}

}  // namespace
}  // namespace lathectl::io
