// Measured FRFs: CSV and universal file format dataset 58/58b (frf_reader.hpp says which fields).
#include "lathectl/io/frf_reader.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <complex>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <optional>
#include <vector>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/input_file.hpp"

namespace lathectl::io {

namespace {

constexpr double kG = 9.80665;  // standard gravity [m/s²]

enum class Measured { displacement, velocity, acceleration };
struct Unit {
  Measured kind = Measured::displacement;
  double scale = 1.0;  // file unit → SI (m, m/s, m/s²) per N
};

[[noreturn]] void fail(const std::string& file, int line, const std::string& message) {
  throw InputError(located(file, line, 0, message));
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r' || s.front() == '\n'))
    s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r' || s.back() == '\n'))
    s.remove_suffix(1);
  return s;
}

// A number in a field; Fortran's D exponent accepted.
std::optional<double> number(std::string_view field) {
  field = trim(field);
  if (field.empty() || field.size() > 64) return std::nullopt;
  char buf[65];
  std::memcpy(buf, field.data(), field.size());
  for (std::size_t i = 0; i < field.size(); ++i)
    if (buf[i] == 'D' || buf[i] == 'd') buf[i] = 'E';
  if (buf[0] == '+') buf[0] = ' ';
  const char* b = buf;
  while (b < buf + field.size() && *b == ' ') ++b;
  double v = 0.0;
  const auto r = std::from_chars(b, buf + field.size(), v);
  if (r.ec != std::errc() || r.ptr != buf + field.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

// The CSV column's unit suffix ("m_per_N", ...).
std::optional<Unit> csv_unit(std::string_view u) {
  if (u == "m_per_N") return Unit{Measured::displacement, 1.0};
  if (u == "mm_per_N") return Unit{Measured::displacement, 1e-3};
  if (u == "um_per_N") return Unit{Measured::displacement, 1e-6};
  if (u == "m_per_s_per_N") return Unit{Measured::velocity, 1.0};
  if (u == "mm_per_s_per_N") return Unit{Measured::velocity, 1e-3};
  if (u == "m_per_s2_per_N") return Unit{Measured::acceleration, 1.0};
  if (u == "mm_per_s2_per_N") return Unit{Measured::acceleration, 1e-3};
  if (u == "g_per_N") return Unit{Measured::acceleration, kG};
  return std::nullopt;
}

// Receptance X from the measured quantity per newton at f [Hz].
std::complex<double> receptance(std::complex<double> v, const Unit& u, double f) {
  const double w = 2.0 * std::numbers::pi * f;
  v *= u.scale;
  switch (u.kind) {
    case Measured::displacement: return v;
    case Measured::velocity: return v / std::complex<double>(0.0, w);
    case Measured::acceleration: return -v / (w * w);
  }
  return v;
}

const char* kCsvUnits =
    "m_per_N, mm_per_N, um_per_N (receptance), m_per_s_per_N, mm_per_s_per_N (mobility), "
    "m_per_s2_per_N, mm_per_s2_per_N, g_per_N (accelerance)";

// A spectrum's first row at 0 Hz (an analyser's DC bin) is skipped with a note: the conversions
// from mobility and accelerance divide by ω, and the lobes need no static point.
bool skip_zero(const std::string& file, int line, const dynamics::Frf& frf, double f,
               std::vector<std::string>* notes) {
  if (f != 0.0 || !frf.frequency_Hz.empty()) return false;
  if (notes)
    notes->push_back(located(file, line, 0,
                             "the 0 Hz row skipped (mobility and accelerance are converted to "
                             "receptance by dividing by ω; the lobes read frequencies > 0)"));
  return true;
}

void check_point(const std::string& file, int line, const dynamics::Frf& frf, double f) {
  if (!(f > 0.0))
    fail(file, line, "frequency " + std::to_string(f) + " Hz: frequencies must be > 0");
  if (!frf.frequency_Hz.empty() && !(f > frf.frequency_Hz.back()))
    fail(file, line,
         "frequency out of order: " + std::to_string(f) + " Hz after " +
             std::to_string(frf.frequency_Hz.back()) + " Hz (frequencies must strictly ascend)");
}

// Lines of a text with their numbers (1-based) and byte offsets.
struct Lines {
  std::string_view text;
  std::size_t pos = 0;
  int number = 0;
  bool next(std::string_view& line) {
    if (pos >= text.size()) return false;
    const std::size_t end = text.find('\n', pos);
    const std::size_t stop = end == std::string_view::npos ? text.size() : end;
    line = text.substr(pos, stop - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos = end == std::string_view::npos ? text.size() : end + 1;
    ++number;
    return true;
  }
};

// Excel's "CSV UTF-8" starts with a byte-order mark, which would hide a comment's '#'.
std::string_view without_bom(std::string_view text) {
  return text.starts_with("\xEF\xBB\xBF") ? text.substr(3) : text;
}

}  // namespace

dynamics::Frf parse_frf_csv(std::string_view text, const std::string& file,
                            std::vector<std::string>* notes) {
  Lines lines{without_bom(text)};
  std::string_view line;
  int header_line = 0;
  std::vector<std::string> names;
  while (lines.next(line)) {
    const auto t = trim(line);
    if (t.empty() || t.front() == '#') continue;
    header_line = lines.number;
    std::size_t s = 0;
    while (true) {
      const std::size_t c = t.find(',', s);
      names.emplace_back(trim(t.substr(s, c == std::string_view::npos ? c : c - s)));
      if (c == std::string_view::npos) break;
      s = c + 1;
    }
    break;
  }
  if (header_line == 0) fail(file, 0, "empty: expected a header frequency_Hz,real_m_per_N,imag_m_per_N");
  int fi = -1, ri = -1, ii = -1;
  std::string real_unit, imag_unit;
  for (std::size_t k = 0; k < names.size(); ++k) {
    const auto& n = names[k];
    int* slot = nullptr;
    if (n == "frequency_Hz") slot = &fi;
    else if (n.rfind("real_", 0) == 0) slot = &ri, real_unit = n.substr(5);
    else if (n.rfind("imag_", 0) == 0) slot = &ii, imag_unit = n.substr(5);
    else
      fail(file, header_line,
           "column '" + printable(n) + "': expected frequency_Hz, real_<unit> and imag_<unit>");
    if (*slot >= 0) fail(file, header_line, "column '" + printable(n) + "' given twice");
    *slot = static_cast<int>(k);
  }
  if (fi < 0) fail(file, header_line, "missing column 'frequency_Hz'");
  if (ri < 0) fail(file, header_line, "missing column 'real_<unit>' (e.g. real_m_per_N)");
  if (ii < 0) fail(file, header_line, "missing column 'imag_<unit>' (e.g. imag_m_per_N)");
  const auto unit = csv_unit(real_unit);
  if (!unit)
    fail(file, header_line,
         "cannot tell the units of column 'real_" + printable(real_unit) + "': expected one of " + kCsvUnits);
  if (imag_unit != real_unit)
    fail(file, header_line,
         "columns 'real_" + printable(real_unit) + "' and 'imag_" + printable(imag_unit) + "' differ in units");
  dynamics::Frf frf;
  while (lines.next(line)) {
    const auto t = trim(line);
    if (t.empty() || t.front() == '#') continue;
    std::vector<std::string_view> fields;
    std::size_t s = 0;
    while (true) {
      const std::size_t c = t.find(',', s);
      fields.push_back(t.substr(s, c == std::string_view::npos ? c : c - s));
      if (c == std::string_view::npos) break;
      s = c + 1;
    }
    if (fields.size() != names.size())
      fail(file, lines.number,
           std::to_string(fields.size()) + " fields, the header has " +
               std::to_string(names.size()));
    double v[3];
    const int idx[3] = {fi, ri, ii};
    for (int k = 0; k < 3; ++k) {
      const auto x = number(fields[static_cast<std::size_t>(idx[k])]);
      if (!x)
        fail(file, lines.number,
             "column '" + printable(names[static_cast<std::size_t>(idx[k])]) + "': '" +
                 printable(trim(fields[static_cast<std::size_t>(idx[k])])) +
                 "' is not a finite number");
      v[k] = *x;
    }
    if (skip_zero(file, lines.number, frf, v[0], notes)) continue;
    check_point(file, lines.number, frf, v[0]);
    frf.frequency_Hz.push_back(v[0]);
    frf.receptance_m_per_N.push_back(receptance({v[1], v[2]}, *unit, v[0]));
  }
  if (frf.frequency_Hz.size() < 2)
    fail(file, lines.number, "at least two frequencies expected, " +
                                 std::to_string(frf.frequency_Hz.size()) + " given");
  return frf;
}

namespace {

// A fixed-width integer field of a UFF record (blank: 0).
long field_int(std::string_view line, std::size_t at, std::size_t width, const std::string& file,
               int n, const char* what) {
  if (at >= line.size()) return 0;
  const auto f = trim(line.substr(at, width));
  if (f.empty()) return 0;
  long v = 0;
  const auto r = std::from_chars(f.data(), f.data() + f.size(), v);
  if (r.ec != std::errc() || r.ptr != f.data() + f.size())
    fail(file, n, std::string(what) + ": '" + printable(f) + "' is not an integer");
  return v;
}
double field_real(std::string_view line, std::size_t at, std::size_t width, const std::string& file,
                  int n, const char* what) {
  if (at >= line.size()) return 0.0;
  const auto f = trim(line.substr(at, width));
  if (f.empty()) return 0.0;
  const auto v = number(f);
  if (!v) fail(file, n, std::string(what) + ": '" + printable(f) + "' is not a number");
  return *v;
}
std::string field_text(std::string_view line, std::size_t at, std::size_t width) {
  if (at >= line.size()) return "";
  return std::string(trim(line.substr(at, width)));
}

bool none(const std::string& label) {
  std::string l = label;
  std::transform(l.begin(), l.end(), l.begin(), [](unsigned char c) { return std::toupper(c); });
  return l.empty() || l == "NONE";
}

// Units of the ordinate (numerator) from its label, or from the file's units code.
std::optional<Unit> uff_unit(long spec_type, std::string label, long units_code) {
  Measured kind;
  if (spec_type == 8) kind = Measured::displacement;
  else if (spec_type == 11) kind = Measured::velocity;
  else if (spec_type == 12) kind = Measured::acceleration;
  else return std::nullopt;
  label.erase(std::remove(label.begin(), label.end(), ' '), label.end());
  if (none(label)) {
    if (units_code == 1) return Unit{kind, 1.0};
    if (units_code == 10) return Unit{kind, 1e-3};
    return std::nullopt;
  }
  for (const char* suffix : {"/N", "/n"})
    if (label.size() > 2 && label.ends_with(suffix)) label.resize(label.size() - 2);
  const std::string m = label;
  switch (kind) {
    case Measured::displacement:
      if (m == "m") return Unit{kind, 1.0};
      if (m == "mm") return Unit{kind, 1e-3};
      if (m == "um" || m == "µm" || m == "micron") return Unit{kind, 1e-6};
      break;
    case Measured::velocity:
      if (m == "m/s") return Unit{kind, 1.0};
      if (m == "mm/s") return Unit{kind, 1e-3};
      break;
    case Measured::acceleration:
      if (m == "m/s^2" || m == "m/s2" || m == "m/s**2" || m == "m/s²") return Unit{kind, 1.0};
      if (m == "mm/s^2" || m == "mm/s2" || m == "mm/s**2") return Unit{kind, 1e-3};
      if (m == "g" || m == "G") return Unit{kind, kG};
      break;
  }
  return std::nullopt;
}

// Dataset 58b's binary header: (I6,1A1,I6,I6,I12,I12,...) after the "58b" of its second line.
struct BinaryHeader {
  long byte_order = 0, n_bytes = 0;
};
BinaryHeader binary_header(std::string_view h, const std::string& file, int kind_line) {
  BinaryHeader b;
  b.byte_order = field_int(h, 7, 6, file, kind_line, "58b byte ordering");
  const long fp = field_int(h, 13, 6, file, kind_line, "58b floating-point format");
  b.n_bytes = field_int(h, 31, 12, file, kind_line, "58b number of bytes");
  if (b.byte_order != 1 && b.byte_order != 2)
    fail(file, kind_line, "58b byte ordering " + std::to_string(b.byte_order) +
                              ": expected 1 (little endian) or 2 (big endian)");
  if (fp != 2) fail(file, kind_line, "58b floating-point format " + std::to_string(fp) +
                                         ": only 2 (IEEE 754) is read");
  if (b.n_bytes <= 0) fail(file, kind_line, "58b: the number of data bytes must be > 0");
  return b;
}

// Records 6 to 10 of a dataset 58: an FRF, its points and abscissa, its ordinate's unit.
struct Uff58 {
  long ord_type = 0, points = 0, even = 0;
  double x0 = 0.0, dx = 0.0;
  Unit unit;
  std::size_t per() const { return even == 1 ? 2 : 3; }  // values per point
  std::size_t values() const { return static_cast<std::size_t>(points) * per(); }
};
Uff58 uff58_records(Lines& lines, const std::string& file, long units_code) {
  std::string_view rec[12], line;
  int at[12] = {};
  for (int r = 1; r <= 11; ++r) {
    if (!lines.next(line)) fail(file, lines.number, "dataset 58 ends before record " + std::to_string(r));
    rec[r] = line;
    at[r] = lines.number;
  }
  const long func_type = field_int(rec[6], 0, 5, file, at[6], "record 6: function type");
  if (func_type != 4)
    fail(file, at[6], "record 6: function type " + std::to_string(func_type) +
                          " is not a frequency response function (4)");
  Uff58 u;
  u.ord_type = field_int(rec[7], 0, 10, file, at[7], "record 7: ordinate data type");
  u.points = field_int(rec[7], 10, 10, file, at[7], "record 7: number of points");
  u.even = field_int(rec[7], 20, 10, file, at[7], "record 7: abscissa spacing");
  u.x0 = field_real(rec[7], 30, 13, file, at[7], "record 7: abscissa minimum");
  u.dx = field_real(rec[7], 43, 13, file, at[7], "record 7: abscissa increment");
  if (u.ord_type != 5 && u.ord_type != 6)
    fail(file, at[7], "record 7: ordinate data type " + std::to_string(u.ord_type) +
                          ": an FRF needs complex values (5 single, 6 double precision)");
  if (u.points < 2 || u.points > 10'000'000)
    fail(file, at[7], "record 7: " + std::to_string(u.points) + " points (2 to 10⁷ expected)");
  if (u.even != 0 && u.even != 1)
    fail(file, at[7], "record 7: abscissa spacing " + std::to_string(u.even) + " (0 uneven, 1 even)");
  if (u.even == 1 && !(u.dx > 0.0))
    fail(file, at[7], "record 7: the abscissa increment must be > 0");
  const long x_type = field_int(rec[8], 0, 10, file, at[8], "record 8: abscissa data type");
  const std::string x_units = field_text(rec[8], 47, 20);
  if (x_type != 18 && !(x_type == 0 && (x_units == "Hz" || x_units == "HZ")))
    fail(file, at[8], "record 8: abscissa data type " + std::to_string(x_type) +
                          " is not frequency (18) in Hz");
  const long y_type = field_int(rec[9], 0, 10, file, at[9], "record 9: ordinate data type");
  const std::string y_units = field_text(rec[9], 47, 20);
  const auto unit = uff_unit(y_type, y_units, units_code);
  if (!unit)
    fail(file, at[9], "record 9: cannot tell the ordinate's units (specific data type " +
                          std::to_string(y_type) + ", units label '" + printable(y_units) +
                          "'): expected displacement (8) in m, mm or um, velocity (11) in "
                          "m/s or mm/s, or acceleration (12) in m/s^2, mm/s^2 or g — or an "
                          "empty label with a dataset 164 of SI units (1) before it");
  u.unit = *unit;
  const long d_type = field_int(rec[10], 0, 10, file, at[10], "record 10: denominator data type");
  const std::string d_units = field_text(rec[10], 47, 20);
  if ((d_type != 13 && d_type != 9) || !(d_units == "N" || none(d_units)))
    fail(file, at[10], "record 10: the denominator must be a force (13) in N, found data type " +
                           std::to_string(d_type) + " in '" + printable(d_units) + "'");
  return u;
}

// Record 12 in binary (58b): the values as stored, in the header's byte order.
std::vector<double> binary_values(std::string_view bytes, Lines& lines, const BinaryHeader& h,
                                  const Uff58& u, const std::string& file, int kind_line,
                                  int data_line) {
  const std::size_t want = u.values();
  std::vector<double> v;
  v.reserve(want);
  const std::size_t width = u.ord_type == 5 ? 4 : 8;
  if (static_cast<std::size_t>(h.n_bytes) != want * width)
    fail(file, kind_line, "58b: " + std::to_string(h.n_bytes) + " bytes declared, " +
                              std::to_string(u.points) + " points need " +
                              std::to_string(want * width));
  if (bytes.size() - lines.pos < want * width)
    fail(file, data_line, "58b: the file ends inside the binary data");
  const bool swap = (h.byte_order == 1) != (std::endian::native == std::endian::little);
  for (std::size_t k = 0; k < want; ++k) {
    unsigned char b[8];
    std::memcpy(b, bytes.data() + lines.pos + k * width, width);
    if (swap) std::reverse(b, b + width);
    double x = 0.0;
    if (width == 4) {
      float y = 0.0f;
      std::memcpy(&y, b, 4);
      x = y;
    } else {
      std::memcpy(&x, b, 8);
    }
    if (!std::isfinite(x)) fail(file, data_line, "58b: a value is not finite");
    v.push_back(x);
  }
  lines.pos += want * width;
  // The rest of the data's last line (LF or, as measurement systems write 58b, CRLF), then the
  // closing "-1".
  if (lines.pos < bytes.size() && bytes[lines.pos] == '\r') ++lines.pos;
  if (lines.pos < bytes.size() && bytes[lines.pos] == '\n') ++lines.pos;
  lines.number = data_line;
  return v;
}

// Record 12 in text, field widths per the record-12 formats.
std::vector<double> text_values(Lines& lines, const Uff58& u, const std::string& file) {
  const std::size_t want = u.values(), per = u.per();
  std::vector<double> v;
  v.reserve(want);
  std::vector<std::size_t> widths;
  if (u.ord_type == 5) widths = {13};
  else if (u.even == 1) widths = {20};
  else widths = {13, 20, 20};
  std::string_view line;
  while (v.size() < want) {
    if (!lines.next(line))
      fail(file, lines.number, "dataset 58 ends after " + std::to_string(v.size() / per) +
                                   " of its " + std::to_string(u.points) + " points");
    if (trim(line) == "-1")
      fail(file, lines.number, "dataset 58 closes after " + std::to_string(v.size() / per) +
                                   " of its " + std::to_string(u.points) + " points");
    std::size_t pos = 0;
    for (std::size_t k = 0; pos < line.size() && v.size() < want; ++k) {
      const std::size_t w = widths[k % widths.size()];
      const auto f = trim(line.substr(pos, w));
      pos += w;
      if (f.empty()) continue;
      const auto x = number(f);
      if (!x) fail(file, lines.number, "record 12: '" + printable(f) + "' is not a finite number");
      v.push_back(*x);
    }
    if (pos < line.size() && !trim(line.substr(pos)).empty())
      fail(file, lines.number, "record 12: more values than the " + std::to_string(u.points) +
                                   " points of record 7");
  }
  return v;
}

// A dataset 58 (58b when binary) after its id line: the FRF as receptance.
dynamics::Frf uff58(std::string_view bytes, Lines& lines, std::string_view id_line, bool binary,
                    long units_code, const std::string& file, std::vector<std::string>* notes) {
  const int kind_line = lines.number;
  // Record 6..11 follow five ID lines.
  const BinaryHeader h = binary ? binary_header(id_line, file, kind_line) : BinaryHeader{};
  const Uff58 u = uff58_records(lines, file, units_code);
  const int data_line = lines.number + 1;
  const std::vector<double> v = binary ? binary_values(bytes, lines, h, u, file, kind_line, data_line)
                                       : text_values(lines, u, file);
  std::string_view line;
  if (!lines.next(line) || trim(line) != "-1")
    fail(file, lines.number, "dataset 58 must close with '    -1' after its " +
                                 std::to_string(u.points) + " points");
  dynamics::Frf frf;
  for (std::size_t k = 0; k < static_cast<std::size_t>(u.points); ++k) {
    const double f = u.even == 1 ? u.x0 + u.dx * static_cast<double>(k) : v[k * 3];
    const std::complex<double> y = u.even == 1 ? std::complex<double>(v[2 * k], v[2 * k + 1])
                                               : std::complex<double>(v[3 * k + 1], v[3 * k + 2]);
    if (skip_zero(file, data_line, frf, f, notes)) continue;
    check_point(file, data_line, frf, f);
    frf.frequency_Hz.push_back(f);
    frf.receptance_m_per_N.push_back(receptance(y, u.unit, f));
  }
  return frf;
}

}  // namespace

dynamics::Frf parse_frf_uff(std::string_view bytes, const std::string& file,
                            std::vector<std::string>* notes) {
  Lines lines{bytes};
  std::string_view line;
  long units_code = 0;  // from a dataset 164
  // Datasets: "-1", its number, its records, "-1".
  while (lines.next(line)) {
    if (trim(line) != "-1") {
      if (trim(line).empty()) continue;
      fail(file, lines.number, "expected '    -1' opening a dataset (universal file format)");
    }
    if (!lines.next(line)) fail(file, lines.number, "the file ends after a dataset's '-1'");
    const auto id = trim(line);
    const bool binary = id.size() > 2 && id.substr(0, 3) == "58b";
    if (id == "164" && lines.next(line)) {
      units_code = field_int(line, 0, 10, file, lines.number, "dataset 164: units code");
    } else if (id == "58" || binary) {
      return uff58(bytes, lines, line, binary, units_code, file, notes);
    }
    // Any other dataset: skip to its closing "-1".
    while (lines.next(line) && trim(line) != "-1") {
    }
  }
  fail(file, lines.number, "no dataset 58 (function at nodal DOF) in the file");
}

dynamics::Frf parse_frf(std::string_view bytes, const std::string& file,
                        std::vector<std::string>* notes) {
  const auto t = trim(bytes.substr(0, std::min<std::size_t>(bytes.size(), 200)));
  if (t.substr(0, 2) == "-1") return parse_frf_uff(bytes, file, notes);
  return parse_frf_csv(bytes, file, notes);
}

dynamics::Frf read_frf_file(const std::filesystem::path& path, std::vector<std::string>* notes) {
  return parse_frf(read_input_file(path, "an FRF file (CSV or UFF 58)", kMaxFrfBytes),
                   path.string(), notes);
}

}  // namespace lathectl::io
