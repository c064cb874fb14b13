// The plot layout's text boxes (report_layout.cpp): the estimates, and marker labels that would
// overprint (system D's "relay trips" and "cut ends" 0.1 s apart) or sit on the data.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "io/report_plot.hpp"

namespace lathectl::io::detail {
namespace {

TEST(ReportLayout, TextWidthFromTheFontTable) {
  // DejaVu Sans: '0'–'9' are 0.636 em; "10" at 12 px is 2 × 0.636 × 12.
  EXPECT_NEAR(text_width("10", text_style("tick")), 2 * 0.636 * 12, 0.01);
  // Bold titles are wider than the same text in the book weight.
  EXPECT_GT(text_width("Feed", text_style("title")), text_width("Feed", {15.0, false}));
  // A non-ASCII letter counts as one character (UTF-8 decoded), at the conservative 0.70 em.
  EXPECT_NEAR(text_width("µ", text_style("tick")), 0.70 * 12, 1e-9);
}

TEST(ReportLayout, RotatedBoxRunsUpFromItsOrigin) {
  const Box b = text_box(100.0, 50.0, "end", true, "ab", text_style("mark"));
  const double w = text_width("ab", text_style("mark"));
  EXPECT_NEAR(b.y0, 50.0, 1e-9);      // anchored at its end: the text reads up to the origin…
  EXPECT_NEAR(b.y1, 50.0 + w, 1e-9);  // …from w below it
  EXPECT_LT(b.x0, 100.0);
  EXPECT_GT(b.x1, 100.0);
}

std::vector<PlacedText> render(const Plot& p) {
  std::string out;
  std::vector<PlacedText> placed;
  render_plot(out, p, 0, 2000, &placed);
  return placed;
}

void expect_apart(const std::vector<PlacedText>& placed) {
  for (std::size_t i = 0; i < placed.size(); ++i)
    for (std::size_t j = i + 1; j < placed.size(); ++j)
      EXPECT_FALSE(placed[i].box.overlaps(placed[j].box))
          << placed[i].text << " / " << placed[j].text;
}

TEST(ReportLayout, CloseMarkersDoNotOverprint) {
  Plot p{"One part", "time [s]", "S [V]", {}, {{7.45, "relay trips"}, {7.5, "cut ends"}}};
  Series s{"S(t)", {}, {}, "", false, false};
  for (int i = 0; i <= 800; ++i) {
    s.x.push_back(i * 0.01);
    s.y.push_back(std::sin(i * 0.05));
  }
  p.series.push_back(s);
  const auto placed = render(p);
  int marks = 0;
  for (const auto& t : placed) marks += t.cls == "mark" ? 1 : 0;
  EXPECT_EQ(marks, 2);
  expect_apart(placed);
}

TEST(ReportLayout, MarkerLabelLeavesTheDataWhenItCan) {
  // Data along the top half only: the label goes below it, not over it.
  Plot p{"Band", "time [s]", "y", {}, {{5.0, "steady window"}}};
  Series s{"y", {}, {}, "", false, false};
  for (int i = 0; i <= 1000; ++i) {
    s.x.push_back(i * 0.01);
    s.y.push_back(i % 2 == 0 ? 1.0 : 0.6);  // a band between 0.6 and 1 on an axis from 0
  }
  Series floor{"", {0.0, 10.0}, {0.0, 0.0}, "", false, false};
  p.series = {s, floor};
  const auto placed = render(p);
  const Box* mark = nullptr;
  const Box* top_tick = nullptr;
  for (const auto& t : placed) {
    if (t.cls == "mark") mark = &t.box;
    if (t.cls == "tick" && t.text == "0.6") top_tick = &t.box;
  }
  ASSERT_NE(mark, nullptr);
  ASSERT_NE(top_tick, nullptr);
  EXPECT_GT(mark->y0, top_tick->y1);  // entirely below the band's lower edge (y = 0.6)
}

TEST(ReportLayout, TimelineLanesAreNamed) {
  Plot p{"Reasons", "time [s]", "", {{"", {0, 1, 2, 3}, {0, 1, 1, 30}, "", false, false}}, {}};
  p.lanes = {{0.0, "in limits (0)"}, {1.0, "force limit (1)"}, {30.0, "approach (30)"}};
  std::string out;
  std::vector<PlacedText> placed;
  render_plot(out, p, 0, 2000, &placed);
  int named = 0;
  for (const auto& t : placed) named += t.cls == "tick" && t.text.back() == ')' ? 1 : 0;
  EXPECT_EQ(named, 3);
  EXPECT_NE(out.find("<rect x="), std::string::npos);
  expect_apart(placed);
}

TEST(ReportLayout, LogAxisTicksAreDecades) {
  Plot p{"Vibration", "feed", "µm", {{"a", {1, 2, 3}, {0.001, 0.1, 500}, "", false, true}}, {}};
  p.log_y = true;
  std::vector<std::string> ticks;
  for (const auto& t : render(p))
    if (t.cls == "tick") ticks.push_back(t.text);
  for (const char* d : {"0.001", "0.01", "0.1", "1", "10", "100"})
    EXPECT_NE(std::find(ticks.begin(), ticks.end(), d), ticks.end()) << d;
}

}  // namespace
}  // namespace lathectl::io::detail
