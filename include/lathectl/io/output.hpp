#pragma once
// Result files. Every write is atomic: the content goes to a temporary file in the same
// directory, which is then renamed over the target, so an interrupted run leaves no half file.

#include <filesystem>
#include <string>

#include "lathectl/sim/recorder.hpp"

namespace lathectl::io {

void write_file_atomic(const std::filesystem::path& path, const std::string& content);
std::string channels_csv(const sim::Recorder& rec);

}  // namespace lathectl::io
