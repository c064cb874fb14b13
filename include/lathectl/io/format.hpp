#pragma once
// Numbers in messages and reports.

#include <string>

namespace lathectl::io {

// printf-style number, "—" for NaN.
std::string fmt(double v, const char* format = "%.4g");
// Fixed-point with `digits` decimals, as iostream's std::fixed writes it ("nan" for NaN).
std::string fixed(double v, int digits);

}  // namespace lathectl::io
