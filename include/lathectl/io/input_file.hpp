#pragma once
// Reading a user's input file: only a regular file, and only up to a size the reader can hold.
// A device (/dev/zero, /dev/urandom), a FIFO, a socket or a directory given where a file is
// expected, or a file larger than its kind may be, is refused before a byte is read, with one
// line naming the file (InputError: exit 2), never an unbounded read, a blocked one or
// std::bad_alloc.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

namespace lathectl::io {

// Upper bounds of the inputs lathectl reads whole.
inline constexpr std::uintmax_t kMaxTomlBytes = 16u << 20;       // scenario, machine, materials, tools
// a JSON file held parsed with each value's place (summary.json), about 14 bytes of memory a
// byte (a 23 MB operation log: 310 MB), so 32 MiB is about 0.45 GB (256 MiB was 3.5 GB;
// issue 49; the operation log is now streamed: kMaxOperationLogBytes).
inline constexpr std::uintmax_t kMaxJsonBytes = 32u << 20;
inline constexpr std::uintmax_t kMaxProgramBytes = 64u << 20;    // an NC program
inline constexpr std::uintmax_t kMaxFrfBytes = 512u << 20;       // a measured FRF (CSV, UFF 58)
// channels.csv, read as a stream (`lathectl compare` holds a bounded plot of it, not its
// columns: memory does not grow with the file; this bounds the time, about 5 s a GB)
inline constexpr std::uintmax_t kMaxCsvBytes = 8ull << 30;
// operations.json, read as a stream (`lathectl report` keeps the first rows and the aggregates,
// not the log: memory does not grow with it); this bounds the time, as for channels.csv
inline constexpr std::uintmax_t kMaxOperationLogBytes = 8ull << 30;

// Throws InputError "PATH: ..." unless `path` names a regular file of at most `max_bytes`.
// `what` names the kind of file in the message ("a scenario file (.toml)").
void check_input_file(const std::filesystem::path& path, const std::string& what,
                      std::uintmax_t max_bytes);

// check_input_file, then the whole file; a read error or a file that grew past `max_bytes` while
// it was read is an InputError too.
[[nodiscard]] std::string read_input_file(const std::filesystem::path& path,
                                          const std::string& what, std::uintmax_t max_bytes);

// The same checks, the file then read a chunk at a time (a reader whose memory must not grow with
// the file): opened without waiting (a FIFO swapped in after the check is refused); a read error
// or a file that grows past `max_bytes` while it is read is an InputError.
class InputStream {
 public:
  InputStream(const std::filesystem::path& path, std::string what, std::uintmax_t max_bytes);
  ~InputStream();
  InputStream(const InputStream&) = delete;
  InputStream& operator=(const InputStream&) = delete;
  // Up to `n` bytes into `buf`; 0 at the end of the file.
  std::size_t read(char* buf, std::size_t n);
  [[nodiscard]] std::uintmax_t size_at_open() const noexcept { return size_; }

 private:
  std::filesystem::path path_;
  std::string what_;
  std::uintmax_t max_bytes_ = 0, size_ = 0, read_ = 0;
  int fd_ = -1;
};

}  // namespace lathectl::io
