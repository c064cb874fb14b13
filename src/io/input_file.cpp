#include "lathectl/io/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <utility>

#include "lathectl/io/errors.hpp"

namespace lathectl::io {

namespace {

std::string mib(std::uintmax_t bytes) {
  const double m = static_cast<double>(bytes) / (1024.0 * 1024.0);
  char buf[32];
  std::snprintf(buf, sizeof buf, bytes % (1024u * 1024u) == 0 ? "%.0f MiB" : "%.1f MiB", m);
  return buf;
}

// What a non-regular file is, for the message.
const char* kind_of(mode_t m) {
  if (S_ISDIR(m)) return "a directory";
  if (S_ISCHR(m)) return "a character device";
  if (S_ISBLK(m)) return "a block device";
  if (S_ISFIFO(m)) return "a FIFO (named pipe)";
  if (S_ISSOCK(m)) return "a socket";
  return "not a regular file";
}

// stat() of the file itself (a symbolic link is followed: a link to a regular file is fine).
struct stat stat_input(const std::filesystem::path& path, const std::string& what,
                       std::uintmax_t max_bytes) {
  struct stat st{};
  if (::stat(path.c_str(), &st) != 0)
    throw InputError(path.string() + ": " + (errno == ENOENT ? "no such file" : std::strerror(errno)) +
                     " (expected " + what + ")");
  if (!S_ISREG(st.st_mode))
    throw InputError(path.string() + ": is " + kind_of(st.st_mode) + ", expected " + what);
  if (static_cast<std::uintmax_t>(st.st_size) > max_bytes)
    throw InputError(path.string() + ": " + mib(static_cast<std::uintmax_t>(st.st_size)) +
                     ", more than the " + mib(max_bytes) + " " + what + " may have");
  return st;
}

}  // namespace

void check_input_file(const std::filesystem::path& path, const std::string& what,
                      std::uintmax_t max_bytes) {
  (void)stat_input(path, what, max_bytes);
}

InputStream::InputStream(const std::filesystem::path& path, std::string what,
                         std::uintmax_t max_bytes)
    : path_(path), what_(std::move(what)), max_bytes_(max_bytes) {
  const struct stat st = stat_input(path_, what_, max_bytes_);
  size_ = static_cast<std::uintmax_t>(st.st_size);
  // O_NONBLOCK: had the path been swapped for a FIFO since stat(), open() must not wait for a
  // writer; fstat() below refuses it.
  fd_ = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd_ < 0) throw InputError(path_.string() + ": cannot open (" + std::strerror(errno) + ")");
  struct stat now{};
  if (::fstat(fd_, &now) != 0 || !S_ISREG(now.st_mode)) {
    ::close(fd_);
    throw InputError(path_.string() + ": is " + kind_of(now.st_mode) + ", expected " + what_);
  }
}

InputStream::~InputStream() {
  ::close(fd_);
}

std::size_t InputStream::read(char* buf, std::size_t n) {
  for (;;) {
    const ssize_t got = ::read(fd_, buf, n);
    if (got < 0) {
      if (errno == EINTR) continue;
      throw InputError(path_.string() + ": read error (" + std::strerror(errno) + ")");
    }
    read_ += static_cast<std::uintmax_t>(got);
    if (read_ > max_bytes_)
      throw InputError(path_.string() + ": grew past " + mib(max_bytes_) + " while being read (" +
                       what_ + ")");
    return static_cast<std::size_t>(got);
  }
}

std::string read_input_file(const std::filesystem::path& path, const std::string& what,
                            std::uintmax_t max_bytes) {
  InputStream in(path, what, max_bytes);
  std::string text;
  text.reserve(static_cast<std::size_t>(in.size_at_open()));
  char buf[1 << 16];
  while (const std::size_t n = in.read(buf, sizeof buf)) text.append(buf, n);
  return text;
}

}  // namespace lathectl::io
