#pragma once
// Internal to the scenario reader (toml_reader.cpp, toml_reader_params.cpp, key_names.cpp): how
// its messages write numbers and lists of choices.

#include <string>
#include <vector>

namespace lathectl::io::detail {

std::string fmt_num(double v);                                  // as std::ostream writes it
std::string quoted_list(const std::vector<std::string>& choices);  // "a", "b" or "c"

}  // namespace lathectl::io::detail
