// io::JsonFile (lathectl report's operation log, lathectl compare's summary.json) and
// io::read_operation_log: a wrong value is one message naming the file, the line and column
// where it is written, and the key.
#include "lathectl/io/json_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/operation_log.hpp"

namespace lathectl::io {
namespace {

std::string error_of(const std::string& text, bool oplog = false) {
  try {
    const JsonFile f("f.json", text);
    if (oplog) (void)read_operation_log(f);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The same text read as `lathectl report` reads a log, a chunk at a time (cut anywhere, from one
// byte a chunk), its rows streamed: the error message with the file's directory left out, "" when
// the log reads; `tools` the rows' tool numbers as they were handed on.
std::string streamed_error(const std::string& text, std::size_t chunk,
                           std::vector<int>* tools = nullptr) {
  const auto dir =
      std::filesystem::temp_directory_path() /
      ("json_file_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  std::filesystem::create_directories(dir);
  const auto file = dir / "f.json";
  std::ofstream(file, std::ios::binary) << text;
  std::string msg;
  try {
    (void)read_operation_log(
        file,
        [&](const OperationLog::Operation& o) {
          if (tools) tools->push_back(o.tool);
        },
        chunk);
  } catch (const InputError& e) {
    msg = e.what();
    const std::string prefix = dir.string() + "/";
    if (msg.rfind(prefix, 0) == 0) msg.erase(0, prefix.size());
  }
  std::filesystem::remove_all(dir);
  return msg;
}

const char* kRow =
    "{\"line\": 17, \"tool\": 1, \"operation\": 0, \"mode\": \"adaptive\", \"limit\": 1400.0,\n"
    "  \"load_mean\": 1285.0, \"load_peak\": 1433.6, \"feed_min\": 0.17, \"feed_mean\": 0.69,\n"
    "  \"time_in_cut_s\": 4.85, \"reasons\": \"none\", \"alarm\": \"\"}";

TEST(JsonFile, ValuesAreLocatedAtTheirKeys) {
  const JsonFile f("f.json", "{\n  \"a\": {\"b\": [1,\n    2, {\"c\": true}]},\n \"d\": -3e2\n}\n");
  EXPECT_EQ(f.doc()["a"]["b"][2]["c"], true);
  EXPECT_EQ(f.locate("a", "m"), "f.json:2:3: key 'a': m");
  EXPECT_EQ(f.locate("a.b", "m"), "f.json:2:9: key 'a.b': m");
  EXPECT_EQ(f.locate("a.b[0]", "m"), "f.json:2:15: key 'a.b[0]': m");
  EXPECT_EQ(f.locate("a.b[1]", "m"), "f.json:3:5: key 'a.b[1]': m");
  EXPECT_EQ(f.locate("a.b[2].c", "m"), "f.json:3:9: key 'a.b[2].c': m");
  EXPECT_EQ(f.locate("d", "m"), "f.json:4:2: key 'd': m");
  EXPECT_EQ(f.locate("", "m"), "f.json:1:1: m");
  // A key the file does not write: at the nearest enclosing value that it does.
  EXPECT_EQ(f.locate("a.b[2].e", "expected a number"),
            "f.json:3:8: key 'a.b[2].e' (missing in a.b[2]): expected a number");
  EXPECT_EQ(f.number(f.doc(), "", "d"), -300.0);
  EXPECT_EQ(error_of("{\"d\": \"x\"}").empty(), true);
}

TEST(JsonFile, SyntaxErrorsNameLineAndColumn) {
  EXPECT_EQ(error_of("{\"rows\": [\n"),
            "f.json:2:1: not JSON: syntax error while parsing value - unexpected end of input; "
            "expected '[', '{', or a literal");
  EXPECT_EQ(error_of("{\n  \"a\": 1,\n  \"b\": tru\n}").rfind("f.json:3:", 0), 0U);
  EXPECT_EQ(error_of("{} x").rfind("f.json:1:4: not JSON", 0), 0U);
  EXPECT_EQ(error_of("").rfind("f.json:1:1: not JSON", 0), 0U);
}

TEST(JsonFile, NestingIsBounded) {
  // (lathectl compare flattens a summary recursively: a file nested without bound is refused)
  std::string deep(JsonFile::kMaxDepth + 1, '[');
  deep += std::string(JsonFile::kMaxDepth + 1, ']');
  EXPECT_EQ(error_of(deep), "f.json:1:65: nested deeper than 64 levels");
  std::string ok(JsonFile::kMaxDepth, '[');
  ok += std::string(JsonFile::kMaxDepth, ']');
  EXPECT_EQ(error_of(ok), "");
}

TEST(OperationLog, ReadsTheRowsAndLocatesABadValue) {
  const std::string log = std::string("{\"unit\": \"W\", \"program\": \"p.ngc\", \"rows\": [") +
                          kRow +
                          "],\n \"taught\": [{\"tool\": 2, \"operation\": 1, "
                          "\"reference\": 1000.1, \"unit\": \"W\"}],\n \"messages\": []}";
  const auto l = read_operation_log(JsonFile("f.json", log));
  ASSERT_EQ(l.rows.size(), 1U);
  EXPECT_EQ(l.unit, "W");
  EXPECT_EQ(l.program, "p.ngc");
  EXPECT_EQ(l.rows[0].tool, 1);
  EXPECT_EQ(l.rows[0].load_peak, 1433.6);
  EXPECT_EQ(l.taught.at(0).reference, 1000.1);
  std::string bad = std::string("{\"rows\": [") + kRow + ",\n" + kRow + "]}";
  bad.replace(bad.rfind("1433.6"), 6, "\"high\"");
  EXPECT_EQ(error_of(bad, true), "f.json:5:24: key 'rows[1].load_peak': expected a number");
  std::string tool = std::string("{\"rows\": [") + kRow + "]}";
  tool.replace(tool.find("\"tool\": 1"), 9, "\"tool\": 1e300");
  EXPECT_EQ(error_of(tool, true),
            "f.json:1:24: key 'rows[0].tool': expected a tool number (a whole number ≥ 0)");
  EXPECT_EQ(error_of("{\"rows\": [\n  3]}", true), "f.json:2:3: key 'rows[0]': expected an object");
  EXPECT_EQ(error_of("[]", true), "f.json:1:1: expected an object with the key 'rows'");
  EXPECT_EQ(error_of("{\"rows\": [], \"unit\": \"kW\"}", true),
            "f.json:1:14: key 'unit': expected N or W");
  EXPECT_EQ(error_of("{\"rows\": [], \"taught\": [{\"tool\": 1}]}", true),
            "f.json:1:25: key 'taught[0].operation' (missing in taught[0]): expected a number");
}

TEST(OperationLog, StreamedInChunksReadsAndLocatesAsWhole) {
  std::string good = std::string("{\"unit\": \"W\",\r\n \"rows\": [") + kRow + ",\n" + kRow +
                     "],\n \"messages\": []}";
  good.replace(good.rfind("\"tool\": 1"), 9, "\"tool\": 4");
  std::string bad_row = std::string("{\"rows\": [") + kRow + ",\n" + kRow + "]}";
  bad_row.replace(bad_row.rfind("1433.6"), 6, "\"high\"");
  const std::vector<std::string> texts = {
      good, bad_row, "{\"rows\": [\n", "{\n  \"a\": 1,\n  \"b\": tru\n}", "{} x", "",
      "{\"rows\": [\n  3]}", "[]", "{\"rows\": [], \"unit\": \"kW\"}",
      "{\"rows\": [], \"taught\": [{\"tool\": 1}]}",
      // a wrong row and a wrong unit after it: the unit first, as when read whole
      "{\"rows\": [\n  3], \"unit\": \"kW\"}",
      // a wrong row and a syntax error after it: the syntax error first
      "{\"rows\": [\n  3], \"unit\": }",
      // the shapes whose values a streamed read leaves out (null), with the same messages
      "[{\"a\": [1, 2]}]", "{\"rows\": {\"a\": [1]}}", "{\"unit\": {\"a\": 1}, \"rows\": []}",
      std::string("{\"x\": {\"deep\": [1, {\"y\": 2}]}, \"rows\": [") + kRow + "]}",
      "{\"x\": " + std::string(JsonFile::kMaxDepth, '[') + std::string(JsonFile::kMaxDepth, ']') +
          ", \"rows\": []}"};
  for (const std::string& text : texts) {
    const std::string whole = error_of(text, true);
    for (const std::size_t chunk : {1, 2, 3, 5, 7, 64, 1 << 20}) {
      SCOPED_TRACE(text + " in chunks of " + std::to_string(chunk));
      std::vector<int> tools;
      EXPECT_EQ(streamed_error(text, chunk, &tools), whole);
      if (whole.empty()) {
        std::vector<int> read_whole;
        for (const auto& o : read_operation_log(JsonFile("f.json", text)).rows)
          read_whole.push_back(o.tool);
        EXPECT_EQ(tools, read_whole);
        EXPECT_FALSE(tools.empty() && text == good);
      }
    }
  }
  EXPECT_EQ(error_of(bad_row, true), "f.json:5:24: key 'rows[1].load_peak': expected a number");
}

}  // namespace
}  // namespace lathectl::io
