// io::Study: the phases run in their order, the summary and the report get what Study adds
// (system, scenario, file, claims, notes), and an extra study's tables and plots follow the
// report's own.
#include "lathectl/io/study.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace lathectl::io {
namespace {

class Recording final : public Study {
 public:
  explicit Recording(const Scenario& sc) : Study(sc) {}
  std::vector<std::string> order;

 private:
  void run_controllers() override { order.emplace_back("run_controllers"); }
  void check_claims(Claims& claims) override {
    order.emplace_back("check_claims");
    claims.check("ratio", 0.5, Compare::AtMost, 1.0);
  }
  void extra_studies(RunOutput& out, Claims& claims) override {
    order.emplace_back("extra_studies");
    claims.note("extra note");
    out.summary["extra"] = 1;
    out.report.tables.push_back(Table{"extra table", {}, {}});
    out.report.plots.push_back(Plot{"extra plot", "x", "y", {}, {}});
  }
  void summary(nlohmann::json& s) override {
    order.emplace_back("summary");
    s["metrics"] = {{"m", 2.0}};
  }
  void report(Report& rep) override {
    order.emplace_back("report");
    rep.tables.push_back(Table{"own table", {}, {}});
    rep.plots.push_back(Plot{"own plot 1", "x", "y", {}, {}});
    rep.plots.push_back(Plot{"own plot 2", "x", "y", {}, {}});
  }
  void finish(RunOutput& out) override {
    order.emplace_back("finish");
    out.headline = "done";
  }
};

TEST(Study, RunsThePhasesInOrderAndPutsTheExtraStudiesAfterTheReportsOwn) {
  Scenario sc;
  sc.system = "A";
  sc.name = "probe";
  sc.file = "probe.toml";
  sc.description = "what it is";
  Recording study(sc);
  const RunOutput out = study.run();
  EXPECT_EQ(study.order,
            (std::vector<std::string>{"run_controllers", "check_claims", "extra_studies", "summary",
                                      "report", "finish"}));
  EXPECT_EQ(out.summary["system"], "A");
  EXPECT_EQ(out.summary["scenario"], "probe");
  EXPECT_EQ(out.summary["file"], "probe.toml");
  EXPECT_EQ(out.summary["extra"], 1);
  EXPECT_EQ(out.summary["metrics"]["m"], 2.0);
  ASSERT_EQ(out.summary["claims"].size(), 1u);
  EXPECT_EQ(out.summary["claims"][0]["met"], true);
  EXPECT_EQ(out.report.description, "what it is");
  ASSERT_EQ(out.report.notes.size(), 2u);
  EXPECT_EQ(out.report.notes[1], "extra note");
  EXPECT_EQ(out.report.note_ids, (std::vector<std::string>{"claim-0", ""}));
  ASSERT_EQ(out.report.tables.size(), 2u);
  EXPECT_EQ(out.report.tables[0].title, "own table");
  EXPECT_EQ(out.report.tables[1].title, "extra table");
  ASSERT_EQ(out.report.plots.size(), 3u);
  EXPECT_EQ(out.report.plots[0].title, "own plot 1");
  EXPECT_EQ(out.report.plots[1].title, "own plot 2");
  EXPECT_EQ(out.report.plots[2].title, "extra plot");
  EXPECT_EQ(out.headline, "done");
}

}  // namespace
}  // namespace lathectl::io
