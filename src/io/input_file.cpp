#include "lathectl/io/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

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

std::string read_input_file(const std::filesystem::path& path, const std::string& what,
                            std::uintmax_t max_bytes) {
  const struct stat st = stat_input(path, what, max_bytes);
  // O_NONBLOCK: had the path been swapped for a FIFO since stat(), open() must not wait for a
  // writer; fstat() below refuses it.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) throw InputError(path.string() + ": cannot open (" + std::strerror(errno) + ")");
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat now{};
  if (::fstat(fd, &now) != 0 || !S_ISREG(now.st_mode))
    throw InputError(path.string() + ": is " + kind_of(now.st_mode) + ", expected " + what);
  std::string text;
  text.reserve(static_cast<std::size_t>(st.st_size));
  char buf[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw InputError(path.string() + ": read error (" + std::strerror(errno) + ")");
    }
    if (n == 0) break;
    text.append(buf, static_cast<std::size_t>(n));
    if (text.size() > max_bytes)
      throw InputError(path.string() + ": grew past " + mib(max_bytes) + " while being read (" +
                       what + ")");
  }
  return text;
}

}  // namespace lathectl::io
