#pragma once
// A vibro-contact gauge's measured calibration (`lathectl design gauge --calibration FILE.csv`,
// design/gauge_calibration.hpp): a CSV file of the filtered voltage at known allowances.
//
//   allowance_um,voltage_V        the header: these two columns, in either order
//   0,6.02                        one row per setting master, allowance strictly ascending, ≥ 0
//
// A UTF-8 byte-order mark (Excel's "CSV UTF-8") is skipped, CRLF line ends are read as LF, lines
// starting with '#' and blank lines are skipped, spaces around a field are ignored. At most
// kMaxCalibrationBytes and kMaxCalibrationPoints. Errors are InputError "FILE:LINE:COL: column
// 'NAME': ..." naming what is wrong.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "lathectl/design/gauge_calibration.hpp"

namespace lathectl::io {

inline constexpr std::uintmax_t kMaxCalibrationBytes = 1u << 20;
inline constexpr std::size_t kMaxCalibrationPoints = 5000;

// Points in SI (allowance in m).
std::vector<design::CalibrationPoint> parse_calibration_csv(std::string_view text,
                                                            const std::string& file);
// On the checked path (io::read_input_file): a FIFO, a device, a directory, a missing or a too
// large file is an InputError naming it before a byte is read.
std::vector<design::CalibrationPoint> read_calibration_file(const std::filesystem::path& path);

}  // namespace lathectl::io
