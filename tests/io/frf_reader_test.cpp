// Measured FRF files (io/frf_reader.hpp): CSV with its unit conversions, and universal file
// format dataset 58 written here from the format's published description, independently of the
// reader, read back to the same numbers; errors located at the file and line.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <string>
#include <vector>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/frf_reader.hpp"

using namespace lathectl;

namespace {
constexpr double kPi = std::numbers::pi;

// A receptance to write: one mode, 1e7 N/m, ζ = 0.03, 400 Hz, sampled 300..500 Hz.
std::complex<double> h_of(double f) {
  const double r = f / 400.0;
  return 1.0 / (1e7 * std::complex<double>(1.0 - r * r, 0.06 * r));
}

std::string message(const std::string& text) {
  try {
    (void)io::parse_frf(text, "tap.csv");
  } catch (const io::InputError& e) {
    return e.what();
  }
  return "no error";
}

// Universal Dataset Number 58 (SDRC I-DEAS "Universal File Datasets Summary"; the same layout in
// pyuff's and LMS' documentation): two lines "-1" and "58" in I6, five 80-character ID records,
// record 6 (2(I5,I10),2(1X,10A1,I10,I4)), record 7 (3I10,3E13.5), records 8–11
// (I10,3I5,2(1X,20A1)), data, "-1". Each record written here with printf from those formats.
std::string record_8_to_11(int type, int len_exp, int force_exp, const char* label,
                           const char* units) {
  char b[120];
  std::snprintf(b, sizeof b, "%10d%5d%5d%5d %-20s %-20s\n", type, len_exp, force_exp, 0, label,
                units);
  return b;
}
std::string uff58_header(int ord_type, int points, int even, double x0, double dx,
                         const char* y_units, int y_type = 8) {
  char b[200];
  std::string s = "    -1\n    58\n";
  s += "Tap test, tool tip xx                                                           \n";
  s += "NONE\nNONE\nNONE\nNONE\n";
  std::snprintf(b, sizeof b, "%5d%10d%5d%10d %-10s%10d%4d %-10s%10d%4d\n", 4, 1, 1, 0, "TOOL", 1, 1,
                "TOOL", 1, 1);
  s += b;
  std::snprintf(b, sizeof b, "%10d%10d%10d%13.5E%13.5E%13.5E\n", ord_type, points, even, x0, dx,
                0.0);
  s += b;
  s += record_8_to_11(18, 0, 0, "Frequency", "Hz");
  s += record_8_to_11(y_type, 1, 0, "Displacement", y_units);
  s += record_8_to_11(13, 0, 1, "Force", "N");
  s += record_8_to_11(0, 0, 0, "NONE", "NONE");
  return s;
}
}  // namespace

TEST(FrfCsv, ReceptanceMobilityAccelerance) {
  std::string x = "# a tap test\nfrequency_Hz,real_m_per_N,imag_m_per_N\n";
  std::string v = "frequency_Hz,real_m_per_s_per_N,imag_m_per_s_per_N\n";
  std::string a = "frequency_Hz,real_g_per_N,imag_g_per_N\n";
  std::string mm = "frequency_Hz,imag_mm_per_N,real_mm_per_N\n";  // columns in any order
  std::vector<double> fs;
  char b[160];
  for (int k = 0; k <= 20; ++k) {
    const double f = 300.0 + 10.0 * k;
    fs.push_back(f);
    const auto h = h_of(f);
    const auto jw = std::complex<double>(0.0, 2.0 * kPi * f);
    const auto vel = jw * h, acc = jw * jw * h / 9.80665;
    std::snprintf(b, sizeof b, "%.17g,%.17g,%.17g\n", f, h.real(), h.imag());
    x += b;
    std::snprintf(b, sizeof b, "%.17g,%.17g,%.17g\n", f, vel.real(), vel.imag());
    v += b;
    std::snprintf(b, sizeof b, "%.17g,%.17g,%.17g\n", f, acc.real(), acc.imag());
    a += b;
    std::snprintf(b, sizeof b, "%.17g,%.17g,%.17g\n", f, h.imag() * 1e3, h.real() * 1e3);
    mm += b;
  }
  for (const auto& text : {x, v, a, mm}) {
    const auto frf = io::parse_frf_csv(text, "tap.csv");
    ASSERT_EQ(frf.frequency_Hz.size(), fs.size());
    for (std::size_t k = 0; k < fs.size(); ++k) {
      EXPECT_EQ(frf.frequency_Hz[k], fs[k]);
      EXPECT_NEAR(std::abs(frf.receptance_m_per_N[k] - h_of(fs[k])) / std::abs(h_of(fs[k])), 0.0,
                  1e-12);
    }
  }
}

TEST(FrfCsv, LocatedErrors) {
  const std::string head = "frequency_Hz,real_m_per_N,imag_m_per_N\n";
  EXPECT_NE(message(head + "100,1e-8,-1e-8\n90,1e-8,-1e-8\n").find("tap.csv:3:"), std::string::npos);
  EXPECT_NE(message(head + "100,1e-8,-1e-8\n90,1e-8,-1e-8\n").find("frequency out of order"),
            std::string::npos);
  EXPECT_NE(message("frequency_Hz,real_m_per_N\n100,1\n").find("missing column 'imag_<unit>'"),
            std::string::npos);
  EXPECT_NE(message("freq,real_m_per_N,imag_m_per_N\n").find("tap.csv:1:"), std::string::npos);
  const auto units = message("frequency_Hz,real_inch_per_lbf,imag_inch_per_lbf\n100,1,1\n");
  EXPECT_NE(units.find("cannot tell the units of column 'real_inch_per_lbf'"), std::string::npos);
  EXPECT_NE(message("frequency_Hz,real_m_per_N,imag_mm_per_N\n").find("differ in units"),
            std::string::npos);
  EXPECT_NE(message(head + "100,abc,1\n").find("tap.csv:2: column 'real_m_per_N': 'abc'"),
            std::string::npos);
  EXPECT_NE(message(head + "100,1,1,4\n").find("4 fields, the header has 3"), std::string::npos);
  EXPECT_NE(message(head + "100,1,1\n").find("at least two frequencies"), std::string::npos);
}

// Complex double, even spacing: 4E20.12 per line (two points a line), in mm.
TEST(FrfUff58, AsciiEvenDoubleReadBack) {
  const int n = 21;
  std::string s = uff58_header(6, n, 1, 300.0, 10.0, "mm");
  std::vector<double> v;
  for (int k = 0; k < n; ++k) {
    const auto h = h_of(300.0 + 10.0 * k) * 1e3;  // mm/N
    v.push_back(h.real());
    v.push_back(h.imag());
  }
  char b[40];
  for (std::size_t i = 0; i < v.size(); ++i) {
    std::snprintf(b, sizeof b, "%20.12E", v[i]);
    s += b;
    if (i % 4 == 3 || i + 1 == v.size()) s += "\n";
  }
  s += "    -1\n";
  const auto frf = io::parse_frf(s, "tap.uff");
  ASSERT_EQ(frf.frequency_Hz.size(), 21u);
  for (int k = 0; k < n; ++k) {
    const auto i = static_cast<std::size_t>(k);
    EXPECT_DOUBLE_EQ(frf.frequency_Hz[i], 300.0 + 10.0 * k);
    EXPECT_NEAR(std::abs(frf.receptance_m_per_N[i] / h_of(300.0 + 10.0 * k) - 1.0), 0.0, 1e-11);
  }
}

// Complex double, uneven spacing: E13.5,2E20.12 per line (frequency, real, imaginary), in m,
// after a dataset 164 (units) and a dataset 151 (header) that the reader skips.
TEST(FrfUff58, AsciiUnevenDoubleAfterOtherDatasets) {
  std::string s = "    -1\n   151\nmodel\nNONE\nNONE\n    -1\n";
  s += "    -1\n   164\n         1SI - mks (Newton)      2\n"
       "  1.00000000000000000E+00  1.00000000000000000E+00  1.00000000000000000E+00\n"
       "  2.73150000000000000E+02\n    -1\n";
  const std::vector<double> fs{300.0, 301.5, 320.25, 399.0, 400.0, 455.5};
  s += uff58_header(6, static_cast<int>(fs.size()), 0, 0.0, 0.0, "m");
  char b[80];
  for (const double f : fs) {
    const auto h = h_of(f);
    std::snprintf(b, sizeof b, "%13.5E%20.12E%20.12E\n", f, h.real(), h.imag());
    s += b;
  }
  s += "    -1\n";
  const auto frf = io::parse_frf(s, "tap.unv");
  ASSERT_EQ(frf.frequency_Hz.size(), fs.size());
  for (std::size_t k = 0; k < fs.size(); ++k) {
    EXPECT_NEAR(frf.frequency_Hz[k], fs[k], 1e-9);
    EXPECT_NEAR(std::abs(frf.receptance_m_per_N[k] / h_of(fs[k]) - 1.0), 0.0, 1e-11);
  }
}

// Complex single, even: 6E13.5 per line; accelerance in g; an empty units label with the SI
// dataset 164 would do as well, tested on displacement.
TEST(FrfUff58, AsciiSingleAccelerationInG) {
  const int n = 7;
  std::string s = uff58_header(5, n, 1, 380.0, 5.0, "g", 12);
  char b[40];
  std::vector<double> v;
  for (int k = 0; k < n; ++k) {
    const double f = 380.0 + 5.0 * k, w = 2.0 * kPi * f;
    const auto acc = -w * w * h_of(f) / 9.80665;
    v.push_back(acc.real());
    v.push_back(acc.imag());
  }
  for (std::size_t i = 0; i < v.size(); ++i) {
    std::snprintf(b, sizeof b, "%13.5E", v[i]);
    s += b;
    if (i % 6 == 5 || i + 1 == v.size()) s += "\n";
  }
  s += "    -1\n";
  const auto frf = io::parse_frf(s, "tap.uff");
  ASSERT_EQ(frf.frequency_Hz.size(), 7u);
  for (int k = 0; k < n; ++k)
    EXPECT_NEAR(std::abs(frf.receptance_m_per_N[static_cast<std::size_t>(k)] /
                             h_of(380.0 + 5.0 * k) -
                         1.0),
                0.0, 2e-5);  // E13.5 keeps 6 significant digits
}

// 58b: the second line "    58b" with byte ordering, floating-point format 2 (IEEE 754),
// 11 ASCII lines and the number of bytes; then records 1–11 in ASCII and the values in binary.
TEST(FrfUff58, BinaryBothByteOrders) {
  const int n = 9;
  for (const int order : {1, 2}) {
    std::string ascii = uff58_header(6, n, 1, 360.0, 10.0, "m");
    const auto second = ascii.find("    58\n");
    char b[100];
    std::snprintf(b, sizeof b, "%6d%c%6d%6d%12d%12d%6d%6d%12d%12d\n", 58, 'b', order, 2, 11, n * 16,
                  0, 0, 0, 0);
    ascii.replace(second, 7, b);
    std::string data;
    for (int k = 0; k < n; ++k) {
      const auto h = h_of(360.0 + 10.0 * k);
      for (double x : {h.real(), h.imag()}) {
        unsigned char c[8];
        std::memcpy(c, &x, 8);
        const bool little = std::endian::native == std::endian::little;
        if ((order == 1) != little) std::reverse(c, c + 8);
        data.append(reinterpret_cast<const char*>(c), 8);
      }
    }
    const std::string file = ascii + data + "\n    -1\n";
    const auto frf = io::parse_frf(file, "tap.uff");
    ASSERT_EQ(frf.frequency_Hz.size(), 9u) << "order " << order;
    for (int k = 0; k < n; ++k)
      EXPECT_EQ(frf.receptance_m_per_N[static_cast<std::size_t>(k)], h_of(360.0 + 10.0 * k));
  }
}

TEST(FrfUff58, LocatedErrors) {
  auto msg = [](const std::string& text) {
    try {
      (void)io::parse_frf(text, "tap.uff");
    } catch (const io::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // Units the reader cannot tell: an empty label and no dataset 164.
  const std::string unknown = uff58_header(6, 2, 1, 300.0, 10.0, "NONE") +
                              "  1.0E-08  1.0E-08  1.0E-08  1.0E-08\n    -1\n";
  EXPECT_NE(msg(unknown).find("tap.uff:11: record 9: cannot tell the ordinate's units"),
            std::string::npos);
  // Real data is no FRF.
  EXPECT_NE(msg(uff58_header(4, 2, 1, 300.0, 10.0, "m")).find("record 7: ordinate data type 4"),
            std::string::npos);
  // Uneven frequencies out of order.
  std::string s = uff58_header(6, 2, 0, 0.0, 0.0, "m");
  s += "  4.00000E+02  1.000000000000E-08  1.000000000000E-08\n";
  s += "  3.00000E+02  1.000000000000E-08  1.000000000000E-08\n    -1\n";
  EXPECT_NE(msg(s).find("frequency out of order"), std::string::npos);
  // Too few points.
  std::string few = uff58_header(6, 3, 1, 300.0, 10.0, "m");
  few += "  1.000000000000E-08  1.000000000000E-08\n    -1\n";
  EXPECT_NE(msg(few).find("closes after 1 of its 3 points"), std::string::npos);
}

// Valid exports a reader once refused (issue 49): Excel's "CSV UTF-8" (a byte-order mark before
// the comment's '#'), and a mobility spectrum from 0 Hz (the DC row skipped with a note naming
// the file and line: V/(jω) has no value there).
TEST(FrfCsv, ByteOrderMarkAndZeroHertzRow) {
  std::string text = "\xEF\xBB\xBF# exported\nfrequency_Hz,real_m_per_s_per_N,imag_m_per_s_per_N\n";
  text += "0,0,0\n";
  char b[160];
  for (const double f : {390.0, 400.0, 410.0}) {
    const auto v = std::complex<double>(0.0, 2.0 * kPi * f) * h_of(f);
    std::snprintf(b, sizeof b, "%.17g,%.17g,%.17g\n", f, v.real(), v.imag());
    text += b;
  }
  std::vector<std::string> notes;
  const auto frf = io::parse_frf(text, "tap.csv", &notes);
  ASSERT_EQ(frf.frequency_Hz.size(), 3u);
  EXPECT_EQ(frf.frequency_Hz[0], 390.0);
  EXPECT_NEAR(std::abs(frf.receptance_m_per_N[1] / h_of(400.0) - 1.0), 0.0, 1e-12);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("tap.csv:3: the 0 Hz row skipped"), std::string::npos) << notes[0];
  // Any other frequency ≤ 0 is still refused.
  EXPECT_NE(message("frequency_Hz,real_m_per_N,imag_m_per_N\n-1,1,1\n5,1,1\n").find("> 0"),
            std::string::npos);
}

// A 58b whose records end in CRLF, as measurement systems export it (the binary block then ends
// in "\r\n" before the closing "-1"), evenly spaced from 0 Hz: the 0 Hz point skipped.
TEST(FrfUff58, BinaryWithCrlfRecordsFromZeroHertz) {
  const int n = 5;
  std::string ascii = uff58_header(6, n, 1, 0.0, 100.0, "m");
  char b[100];
  std::snprintf(b, sizeof b, "%6d%c%6d%6d%12d%12d%6d%6d%12d%12d\n", 58, 'b', 1, 2, 11, n * 16, 0,
                0, 0, 0);
  ascii.replace(ascii.find("    58\n"), 7, b);
  std::string crlf;
  for (const char c : ascii) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  std::string data;
  for (int k = 0; k < n; ++k) {
    const auto h = k == 0 ? std::complex<double>(1e-7, 0.0) : h_of(100.0 * k);
    for (double x : {h.real(), h.imag()}) {
      unsigned char c[8];
      std::memcpy(c, &x, 8);
      if (std::endian::native != std::endian::little) std::reverse(c, c + 8);
      data.append(reinterpret_cast<const char*>(c), 8);
    }
  }
  std::vector<std::string> notes;
  const auto frf = io::parse_frf(crlf + data + "\r\n    -1\r\n", "tap.uff", &notes);
  ASSERT_EQ(frf.frequency_Hz.size(), 4u);
  for (int k = 1; k < n; ++k)
    EXPECT_EQ(frf.receptance_m_per_N[static_cast<std::size_t>(k - 1)], h_of(100.0 * k));
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("the 0 Hz row skipped"), std::string::npos) << notes[0];
}
