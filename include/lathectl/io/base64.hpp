#pragma once
// Base64 of the interactive plots' data (report_interactive.cpp), decoded by the page with atob().

#include <cstddef>
#include <string>
#include <vector>

namespace lathectl::io {

// Standard base64 (RFC 4648, with padding) of raw bytes; the page decodes it with atob().
std::string base64(const void* data, std::size_t size);
// The floats as little-endian IEEE-754 binary32, base64: what the page reads as a Float32Array.
std::string base64_floats(const std::vector<float>& v);

}  // namespace lathectl::io
