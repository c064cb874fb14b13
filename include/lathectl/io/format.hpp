#pragma once
// Numbers in messages and reports.

#include <string>

namespace lathectl::io {

// printf-style number, "—" for NaN.
std::string fmt(double v, const char* format = "%.4g");

}  // namespace lathectl::io
