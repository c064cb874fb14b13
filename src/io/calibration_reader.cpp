// A gauge's measured calibration CSV (calibration_reader.hpp says the format).
#include "lathectl/io/calibration_reader.hpp"

#include <charconv>
#include <cmath>
#include <string>

#include "lathectl/io/errors.hpp"
#include "lathectl/io/input_file.hpp"

namespace lathectl::io {

namespace {

const char* kHeader = "allowance_um,voltage_V";

bool blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// One field of a line: its text without the spaces around it and its 1-based column.
struct Field {
  std::string_view text;
  int column = 0;
};

std::vector<Field> fields_of(std::string_view line) {
  std::vector<Field> out;
  std::size_t s = 0;
  while (true) {
    const std::size_t c = line.find(',', s);
    std::size_t b = s, e = c == std::string_view::npos ? line.size() : c;
    while (b < e && blank(line[b])) ++b;
    while (e > b && blank(line[e - 1])) --e;
    out.push_back({line.substr(b, e - b), static_cast<int>(b) + 1});
    if (c == std::string_view::npos) return out;
    s = c + 1;
  }
}

}  // namespace

std::vector<design::CalibrationPoint> parse_calibration_csv(std::string_view text,
                                                            const std::string& file) {
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
  std::vector<design::CalibrationPoint> points;
  int x_col = -1, v_col = -1, header_line = 0, number = 0;
  std::size_t columns = 0;
  for (std::size_t pos = 0; pos < text.size();) {
    const std::size_t end = text.find('\n', pos);
    std::string_view line = text.substr(pos, end == std::string_view::npos ? end : end - pos);
    pos = end == std::string_view::npos ? text.size() : end + 1;
    ++number;
    const auto f = fields_of(line);
    if (f.size() == 1 && (f[0].text.empty() || f[0].text.front() == '#')) continue;
    if (!f.empty() && !f[0].text.empty() && f[0].text.front() == '#') continue;
    if (header_line == 0) {
      header_line = number;
      columns = f.size();
      for (std::size_t k = 0; k < f.size(); ++k) {
        int* slot = f[k].text == "allowance_um" ? &x_col : f[k].text == "voltage_V" ? &v_col : nullptr;
        if (!slot)
          throw InputError(located(file, number, f[k].column,
                                   "column '" + std::string(f[k].text) + "': expected the header " +
                                       kHeader));
        if (*slot >= 0)
          throw InputError(located(file, number, f[k].column,
                                   "column '" + std::string(f[k].text) + "' given twice"));
        *slot = static_cast<int>(k);
      }
      if (x_col < 0 || v_col < 0)
        throw InputError(located(file, number, 0,
                                 std::string("missing column '") +
                                     (x_col < 0 ? "allowance_um" : "voltage_V") +
                                     "': expected the header " + kHeader));
      continue;
    }
    if (f.size() != columns)
      throw InputError(located(file, number, 0,
                               std::to_string(f.size()) + " fields, the header has " +
                                   std::to_string(columns)));
    double v[2] = {0.0, 0.0};
    const int cols[2] = {x_col, v_col};
    const char* names[2] = {"allowance_um", "voltage_V"};
    for (int k = 0; k < 2; ++k) {
      const Field& fd = f[static_cast<std::size_t>(cols[k])];
      const char* b = fd.text.data();
      const char* e = b + fd.text.size();
      if (b != e && *b == '+') ++b;
      const auto r = std::from_chars(b, e, v[k]);
      if (fd.text.empty() || r.ec != std::errc() || r.ptr != e || !std::isfinite(v[k]))
        throw InputError(located(file, number, fd.column,
                                 std::string("column '") + names[k] + "': '" +
                                     std::string(fd.text) + "' is not a finite number"));
    }
    const int xc = f[static_cast<std::size_t>(x_col)].column;
    if (v[0] < 0.0)
      throw InputError(located(file, number, xc, "column 'allowance_um': " + std::string(
                                                     f[static_cast<std::size_t>(x_col)].text) +
                                                     " µm: an allowance is ≥ 0"));
    if (!points.empty() && !(v[0] * 1e-6 > points.back().allowance_m))
      throw InputError(located(file, number, xc,
                               "column 'allowance_um': " +
                                   std::string(f[static_cast<std::size_t>(x_col)].text) +
                                   " µm after " + std::to_string(points.back().allowance_m * 1e6) +
                                   " µm: the allowances must strictly ascend"));
    if (points.size() == kMaxCalibrationPoints)
      throw InputError(located(file, number, 0,
                               "more than " + std::to_string(kMaxCalibrationPoints) +
                                   " calibration points"));
    points.push_back({v[0] * 1e-6, v[1]});
  }
  if (header_line == 0)
    throw InputError(located(file, 0, 0, std::string("empty: expected the header ") + kHeader));
  if (points.size() < design::kMinCalibrationPoints)
    throw InputError(located(file, number, 0,
                             "at least " + std::to_string(design::kMinCalibrationPoints) +
                                 " calibration points expected, " +
                                 std::to_string(points.size()) + " given"));
  return points;
}

std::vector<design::CalibrationPoint> read_calibration_file(const std::filesystem::path& path) {
  const std::string text =
      read_input_file(path, "a gauge calibration (.csv: allowance_um,voltage_V)",
                      kMaxCalibrationBytes);
  return parse_calibration_csv(text, path.string());
}

}  // namespace lathectl::io
