#pragma once
// Measured frequency response functions (tap tests) for `lathectl lobes`' [[frf]] tables, in the
// field's two exchange formats, as receptance [m/N] (dynamics::Frf):
//
// CSV (a UTF-8 byte-order mark, as Excel's "CSV UTF-8" writes, is skipped): a header line, then
// one row per frequency, strictly ascending, > 0 (lines starting with '#' and blank lines are
// skipped; a first row at 0 Hz, a spectrum's DC bin, is skipped with a note in either format:
// the conversions from mobility and accelerance divide by ω). The header names the columns:
//   frequency_Hz,real_<unit>,imag_<unit>
// <unit> says what was measured and in which unit, converted to receptance X(ω):
//   m_per_N, mm_per_N, um_per_N                 receptance (displacement/force)
//   m_per_s_per_N, mm_per_s_per_N               mobility V: X = V/(jω)
//   m_per_s2_per_N, mm_per_s2_per_N, g_per_N    accelerance A: X = −A/ω²  (g = 9.80665 m/s²)
//
// Universal file format, dataset 58 ("function at nodal DOF"), ASCII or 58b binary (IEEE,
// either byte order), as published by SDRC/Siemens ("Universal Dataset Number 58", I-DEAS):
//   line "    -1", line "    58" (58b: "    58b", byte order, format, 11 ASCII lines, bytes;
//   the binary block ends in LF or CRLF),
//   records 1–5 text, record 6 (2(I5,I10),2(1X,10A1,I10,I4)): function type (4 = FRF), ...,
//   response and reference node and direction; record 7 (3I10,3E13.5): ordinate data type
//   (5 complex single, 6 complex double), points, abscissa spacing (1 even, 0 uneven),
//   abscissa minimum and increment; records 8–11 (I10,3I5,2(1X,20A1)): the abscissa's, the
//   ordinate numerator's, its denominator's and the z axis' data characteristics (specific data
//   type: 18 frequency, 8 displacement, 11 velocity, 12 acceleration, 13 excitation force),
//   unit exponents, axis label, units label; record 12 the data: complex single 6E13.5 per line,
//   complex double even 4E20.12, uneven E13.5,2E20.12 (frequency, real, imaginary); line "    -1".
// The units are read from the units labels (m, mm, um, m/s, mm/s, m/s^2, mm/s^2, g; N), or, when
// the labels are empty or NONE, from a dataset 164 earlier in the file (units code 1: SI, m and
// N; 10: mm and N). The first dataset 58 of the file is read.
//
// Errors are InputError "FILE:LINE: ..." naming what is wrong: a frequency out of order, a
// missing column, units the reader cannot tell, a value that is not a number, too few points.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "lathectl/dynamics/lobes.hpp"

namespace lathectl::io {

// `notes`, when given, receives what was read but not kept ("FILE:LINE: the 0 Hz row skipped").
dynamics::Frf parse_frf_csv(std::string_view text, const std::string& file,
                            std::vector<std::string>* notes = nullptr);
dynamics::Frf parse_frf_uff(std::string_view bytes, const std::string& file,
                            std::vector<std::string>* notes = nullptr);
// By the file's content: a UFF file starts (after blank space) with "-1"; anything else is CSV.
dynamics::Frf parse_frf(std::string_view bytes, const std::string& file,
                        std::vector<std::string>* notes = nullptr);
// On the checked path (io::read_input_file, at most kMaxFrfBytes): a FIFO, a device, a directory
// or a missing file is an InputError naming it before a byte is read.
dynamics::Frf read_frf_file(const std::filesystem::path& path,
                            std::vector<std::string>* notes = nullptr);

}  // namespace lathectl::io
