// Base64 of the interactive plots' data (base64.hpp).
#include "lathectl/io/base64.hpp"

#include <cstdint>
#include <cstring>

namespace lathectl::io {

std::string base64(const void* data, std::size_t size) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* p = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 3 <= size; i += 3) {
    const std::uint32_t v = (std::uint32_t{p[i]} << 16) | (std::uint32_t{p[i + 1]} << 8) | p[i + 2];
    out += kAlphabet[(v >> 18) & 63U];
    out += kAlphabet[(v >> 12) & 63U];
    out += kAlphabet[(v >> 6) & 63U];
    out += kAlphabet[v & 63U];
  }
  if (i < size) {
    std::uint32_t v = std::uint32_t{p[i]} << 16;
    if (i + 1 < size) v |= std::uint32_t{p[i + 1]} << 8;
    out += kAlphabet[(v >> 18) & 63U];
    out += kAlphabet[(v >> 12) & 63U];
    out += i + 1 < size ? kAlphabet[(v >> 6) & 63U] : '=';
    out += '=';
  }
  return out;
}

std::string base64_floats(const std::vector<float>& v) {
  std::vector<unsigned char> bytes(v.size() * 4);
  for (std::size_t i = 0; i < v.size(); ++i) {
    std::uint32_t u = 0;
    std::memcpy(&u, &v[i], 4);
    for (std::size_t k = 0; k < 4; ++k)
      bytes[i * 4 + k] = static_cast<unsigned char>((u >> (8 * k)) & 0xFFU);  // little-endian
  }
  return base64(bytes.data(), bytes.size());
}

}  // namespace lathectl::io
