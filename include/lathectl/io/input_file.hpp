#pragma once
// Reading a user's input file: only a regular file, and only up to a size the reader can hold.
// A device (/dev/zero, /dev/urandom), a FIFO, a socket or a directory given where a file is
// expected, or a file larger than its kind may be, is refused before a byte is read, with one
// line naming the file (InputError: exit 2), never an unbounded read, a blocked one or
// std::bad_alloc.

#include <cstdint>
#include <filesystem>
#include <string>

namespace lathectl::io {

// Upper bounds of the inputs lathectl reads whole.
inline constexpr std::uintmax_t kMaxTomlBytes = 16u << 20;       // scenario, machine, materials, tools
// operation log, summary.json: held parsed with each value's place, about 14 bytes of memory a
// byte (a 23 MB log: 310 MB), so 32 MiB is about 0.45 GB (256 MiB was 3.5 GB; issue 49).
inline constexpr std::uintmax_t kMaxJsonBytes = 32u << 20;
inline constexpr std::uintmax_t kMaxProgramBytes = 64u << 20;    // an NC program
inline constexpr std::uintmax_t kMaxFrfBytes = 512u << 20;       // a measured FRF (CSV, UFF 58)
// channels.csv, read as a stream (`lathectl compare` holds a bounded plot of it, not its
// columns: memory does not grow with the file; this bounds the time, about 5 s a GB)
inline constexpr std::uintmax_t kMaxCsvBytes = 8ull << 30;

// Throws InputError "PATH: ..." unless `path` names a regular file of at most `max_bytes`.
// `what` names the kind of file in the message ("a scenario file (.toml)").
void check_input_file(const std::filesystem::path& path, const std::string& what,
                      std::uintmax_t max_bytes);

// check_input_file, then the whole file; a read error or a file that grew past `max_bytes` while
// it was read is an InputError too.
[[nodiscard]] std::string read_input_file(const std::filesystem::path& path,
                                          const std::string& what, std::uintmax_t max_bytes);

}  // namespace lathectl::io
