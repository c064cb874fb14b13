// A gauge's calibration CSV (io/calibration_reader.hpp): the format with a BOM, CRLF, comments
// and the columns swapped, and each bad file refused with FILE:LINE:COL naming the column.
#include "lathectl/io/calibration_reader.hpp"

#include <gtest/gtest.h>

#include <string>

#include "lathectl/io/errors.hpp"

namespace {

using lathectl::io::InputError;
using lathectl::io::parse_calibration_csv;

std::string message_of(const std::string& text) {
  try {
    (void)parse_calibration_csv(text, "cal.csv");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(CalibrationReader, ReadsExcelsCsvWithCommentsAndSwappedColumns) {
  const auto p = parse_calibration_csv(
      "\xEF\xBB\xBF# setting masters, 2026-12-06\r\nvoltage_V, allowance_um\r\n\r\n6.0,0\r\n"
      "5.7,10\r\n# re-measured\r\n5.4,+20\r\n5.1,30\r\n4.8,4e1",
      "cal.csv");
  ASSERT_EQ(p.size(), 5u);
  EXPECT_DOUBLE_EQ(p[2].allowance_m, 20e-6);
  EXPECT_DOUBLE_EQ(p[4].allowance_m, 40e-6);
  EXPECT_DOUBLE_EQ(p[4].voltage_V, 4.8);
}

TEST(CalibrationReader, NamesFileLineColumnAndWhatIsWrong) {
  const std::string h = "allowance_um,voltage_V\n";
  EXPECT_EQ(message_of(""), "cal.csv: empty: expected the header allowance_um,voltage_V");
  EXPECT_EQ(message_of("allowance_mm,voltage_V\n"),
            "cal.csv:1:1: column 'allowance_mm': expected the header allowance_um,voltage_V");
  EXPECT_EQ(message_of("allowance_um\n"),
            "cal.csv:1: missing column 'voltage_V': expected the header allowance_um,voltage_V");
  EXPECT_EQ(message_of(h + "0,6\n10, six\n"),
            "cal.csv:3:5: column 'voltage_V': 'six' is not a finite number");
  EXPECT_EQ(message_of(h + "0,6\n10,nan\n"),
            "cal.csv:3:4: column 'voltage_V': 'nan' is not a finite number");
  EXPECT_EQ(message_of(h + "0,6\n10\n"), "cal.csv:3: 1 fields, the header has 2");
  EXPECT_EQ(message_of(h + "-1,6\n"), "cal.csv:2:1: column 'allowance_um': -1 µm: an allowance is ≥ 0");
  EXPECT_EQ(message_of(h + "0,6\n20,5\n10,5.5\n"),
            "cal.csv:4:1: column 'allowance_um': 10 µm after 20.000000 µm: the allowances must "
            "strictly ascend");
  EXPECT_EQ(message_of(h + "0,6\n10,5\n"),
            "cal.csv:3: at least 5 calibration points expected, 2 given");
}

TEST(CalibrationReader, ReadsOnlyARegularFileOfBoundedSize) {
  EXPECT_THROW((void)lathectl::io::read_calibration_file("/dev/zero"), InputError);
  EXPECT_THROW((void)lathectl::io::read_calibration_file("/nonexistent/cal.csv"), InputError);
}

}  // namespace
