#include "lathectl/io/output.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <span>
#include <system_error>

#include "lathectl/io/channel_stream.hpp"
#include "lathectl/io/errors.hpp"

namespace lathectl::io {

namespace fs = std::filesystem;

namespace {

// Test-only fault point: LATHECTL_TEST_KILL_AT=<point> kills the process there with SIGKILL, as a
// kill -9 or a power cut would, so the tests can check what a kill leaves behind.
void fault_point(const std::string& point) {
  const char* at = std::getenv("LATHECTL_TEST_KILL_AT");
  if (at && point == at) ::raise(SIGKILL);
}

// The pid a temporary's name ends with ("x.tmp.123", "out.tmp-123", "out.old-123"), or 0.
long temporary_pid(const std::string& name, bool& is_staging) {
  for (const char* tag : {".tmp.", ".tmp-", ".old-", ".lathectl-probe-"}) {
    const auto at = name.rfind(tag);
    if (at == std::string::npos) continue;
    const std::string digits = name.substr(at + std::strlen(tag));
    if (digits.empty() || digits.size() > 9 ||
        digits.find_first_not_of("0123456789") != std::string::npos)
      continue;
    is_staging = std::strcmp(tag, ".tmp.") != 0;
    return std::strtol(digits.c_str(), nullptr, 10);
  }
  return 0;
}

bool process_alive(long pid) {
  if (pid == static_cast<long>(::getpid())) return true;
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

// Result files written by lathectl before sets carried the marker.
bool legacy_result_name(const std::string& n) {
  return n == "summary.json" || n == "channels.csv" || n == "channels_compare.csv" ||
         n == "report.html" || n == "lobes.csv" || n == "lobes.html" || n == "lobes.json";
}

// `dir` may be replaced as a whole: it carries the marker, is empty, or holds only result files
// (and temporaries) of an older lathectl.
bool replaceable_output_set(const fs::path& dir) {
  std::error_code ec;
  if (fs::exists(dir / kOutputMarker, ec)) return true;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string n = e.path().filename().string();
    bool staging = false;
    std::error_code ec2;
    if (!e.is_regular_file(ec2)) return false;
    if (!legacy_result_name(n) && temporary_pid(n, staging) == 0) return false;
  }
  return !ec;
}

fs::path normalized(const fs::path& dir) {
  fs::path d = dir.lexically_normal();
  if (d.has_filename()) return d;
  return d.parent_path();  // "out/" → "out"
}

fs::path parent_of(const fs::path& dir) {
  return dir.has_parent_path() ? dir.parent_path() : fs::path(".");
}

// The system's reason a write failed, for a message ("No space left on device").
[[noreturn]] void write_failed(const fs::path& path, int err) {
  throw InputError(path.string() + ": cannot write (" + std::strerror(err) + ")");
}

// `content` into a new file `path` by write(2), so that a full disk or a quota is reported as
// itself (an ofstream only says that something failed). Returns 0, or the errno of the failure
// (the partial file removed).
int write_plain_errno(const fs::path& path, const std::string& content) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return errno;
  const char* p = content.data();
  std::size_t left = content.size();
  int err = 0;
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      err = n < 0 ? errno : ENOSPC;
      break;
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0 && err == 0) err = errno;
  if (err != 0) {
    std::error_code ec;
    fs::remove(path, ec);
  }
  return err;
}

void write_plain(const fs::path& path, const std::string& content) {
  if (const int err = write_plain_errno(path, content)) write_failed(path, err);
}

// The first bytes of a file (at most n).
std::string head_of(const fs::path& path, std::size_t n) {
  std::string s(n, '\0');
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) return {};
  const ssize_t got = ::read(fd, s.data(), n);
  ::close(fd);
  s.resize(got > 0 ? static_cast<std::size_t>(got) : 0);
  return s;
}

}  // namespace

void remove_dead_temporaries(const fs::path& dir) {
  std::error_code ec;
  std::vector<fs::path> dead;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    bool staging = false;
    const long pid = temporary_pid(e.path().filename().string(), staging);
    if (pid <= 0 || process_alive(pid)) continue;
    std::error_code ec2;
    if (e.is_directory(ec2)) {
      // Only our own staging directories: marked, or empty (killed before the marker).
      if (!staging) continue;
      if (!fs::exists(e.path() / kOutputMarker, ec2) && !fs::is_empty(e.path(), ec2)) continue;
    } else if (!e.is_regular_file(ec2)) {
      continue;
    }
    dead.push_back(e.path());
  }
  for (const auto& p : dead) fs::remove_all(p, ec);
}

void write_file_atomic(const std::filesystem::path& path, const std::string& content) {
  remove_dead_temporaries(parent_of(path));
  const fs::path tmp = path.string() + ".tmp." + std::to_string(::getpid());
  if (const int err = write_plain_errno(tmp, content)) write_failed(path, err);
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw InputError(path.string() + ": cannot write (" + ec.message() + ")");
  }
}

void check_output_file(const fs::path& path, const std::string& flag,
                       const std::vector<fs::path>& inputs) {
  const std::string label = flag + " " + path.string();
  std::error_code ec;
  const auto st = fs::status(path, ec);
  if (fs::exists(st)) {
    if (!fs::is_regular_file(st))
      throw InputError(label + ": exists and is not a regular file (" +
                       (fs::is_directory(st) ? "a directory" : "a device, FIFO or socket") +
                       "); not replacing it: name a file");
    for (const auto& in : inputs)
      if (fs::equivalent(path, in, ec))
        throw InputError(label + ": is the input " + in.string() +
                         "; writing there would destroy it: name another file");
    // A page of this lathectl, or of an older one (whose pages began exactly so).
    const std::string head = head_of(path, 4096);
    const bool ours =
        head.find(kGeneratorMeta) != std::string::npos ||
        head.rfind("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
                   "<meta name=\"viewport\"",
                   0) == 0;
    if (!ours)
      throw InputError(label + ": exists and is not a page lathectl wrote; not replacing it: "
                               "name a new file or remove it");
  }
  const fs::path parent = parent_of(path);
  if (!fs::is_directory(parent, ec))
    throw InputError(label + ": " + parent.string() + " is not a directory");
  if (::access(parent.c_str(), W_OK | X_OK) != 0)
    throw InputError(label + ": cannot write in " + parent.string() + " (" +
                     std::strerror(errno) + ")");
}

void write_output_file(const fs::path& path, const std::string& content, const std::string& flag,
                       const std::vector<fs::path>& inputs) {
  check_output_file(path, flag, inputs);
  try {
    write_file_atomic(path, content);
  } catch (const InputError& e) {
    throw InputError(flag + " " + e.what());
  }
}

void check_not_above(const fs::path& dir, const std::string& flag,
                     const std::vector<fs::path>& inputs) {
  std::error_code ec;
  const fs::path out = fs::weakly_canonical(fs::absolute(dir, ec), ec);
  if (ec) return;  // prepare_output_dir reports what is wrong with it
  for (const auto& input : inputs) {
    std::error_code ec_in;
    const fs::path in = fs::weakly_canonical(fs::absolute(input, ec_in), ec_in);
    if (ec_in || input.empty()) continue;
    const auto [o, i] = std::mismatch(out.begin(), out.end(), in.begin(), in.end());
    if (o != out.end() && !o->empty()) continue;  // out is not a prefix of in
    throw InputError(flag + " " + dir.string() + ": " +
                     (i == in.end() ? "is the input " : "holds the input ") + input.string() +
                     ", which the results would replace; choose a directory outside the inputs");
  }
}

void prepare_output_dir(const fs::path& dir_in, const std::string& flag, bool whole_set,
                        const std::vector<fs::path>& inputs) {
  if (dir_in.empty()) throw InputError(flag + ": empty; name a directory for the results");
  check_not_above(dir_in, flag, inputs);
  const fs::path dir = normalized(dir_in);
  const std::string label = flag + " " + dir_in.string();
  std::error_code ec;
  const auto st = fs::status(dir, ec);
  if (fs::exists(st)) {
    if (!fs::is_directory(st)) throw InputError(label + ": not a directory");
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
      throw InputError(label + ": not writable (" + std::strerror(errno) + ")");
    remove_dead_temporaries(dir);
    if (whole_set && !replaceable_output_set(dir))
      throw InputError(label + ": exists and holds files that are not lathectl results (no " +
                       kOutputMarker + "); choose a new or empty directory");
  }
  // The set is staged beside `dir` and renamed into place: the parent (or, where it does not
  // exist yet, its nearest existing ancestor) must take a new directory. Try one.
  fs::path anc = parent_of(dir);
  while (!fs::exists(anc, ec) && anc.has_parent_path() && anc != anc.parent_path())
    anc = anc.parent_path();
  if (fs::exists(anc, ec) && !fs::is_directory(anc, ec))
    throw InputError(label + ": " + anc.string() + " is not a directory");
  if (fs::is_directory(anc, ec)) remove_dead_temporaries(anc);
  const fs::path probe = anc / (".lathectl-probe-" + std::to_string(::getpid()));
  if (::mkdir(probe.c_str(), 0700) != 0)
    throw InputError(label + ": cannot create a directory in " + anc.string() + " (" +
                     std::strerror(errno) + ")");
  ::rmdir(probe.c_str());
}

OutputStage::OutputStage(const fs::path& dir_in) : dir_(normalized(dir_in)) {
  const fs::path parent = parent_of(dir_);
  fs::create_directories(parent);
  remove_dead_temporaries(parent);
  stage_ = parent / (dir_.filename().string() + ".tmp-" + std::to_string(::getpid()));
  fs::remove_all(stage_);
  fs::create_directory(stage_);
  try {
    write_plain(stage_ / kOutputMarker, "lathectl output set\n");
  } catch (...) {
    std::error_code ec;
    fs::remove_all(stage_, ec);
    throw;
  }
}

OutputStage::~OutputStage() {
  if (done_) return;
  std::error_code ec;
  fs::remove_all(stage_, ec);
}

bool OutputStage::streamed(const std::string& name) const {
  return std::find(streamed_.begin(), streamed_.end(), name) != streamed_.end();
}

void OutputStage::commit(const std::vector<std::pair<std::string, std::string>>& files) {
  const fs::path& dir = dir_;
  const fs::path parent = parent_of(dir);
  std::error_code ec;
  const bool replace = fs::exists(dir, ec);
  if (replace && (!fs::is_directory(dir, ec) || !replaceable_output_set(dir)))
    throw InputError(dir.string() + ": exists and is not a lathectl output directory; not "
                                    "replacing it");
  const std::string pid = std::to_string(::getpid());
  for (const auto& name : streamed_) fault_point(name);
  for (const auto& [name, content] : files) {
    write_plain(stage_ / name, content);
    fault_point(name);
  }
  if (!replace) {
    fs::rename(stage_, dir);
    done_ = true;
    fault_point("swapped");
    return;
  }
  if (::renameat2(AT_FDCWD, stage_.c_str(), AT_FDCWD, dir.c_str(), RENAME_EXCHANGE) == 0) {
    fault_point("swapped");
    fs::remove_all(stage_);  // now the old set
    done_ = true;
    return;
  }
  if (errno != EINVAL && errno != ENOSYS)
    throw InputError(dir.string() + ": cannot replace it (" + std::strerror(errno) + ")");
  // No atomic exchange on this file system: move the old set aside, then the new one in.
  const fs::path old = parent / (dir.filename().string() + ".old-" + pid);
  fs::rename(dir, old);
  fs::rename(stage_, dir);
  done_ = true;
  fault_point("swapped");
  fs::remove_all(old);
}

void write_output_set(const fs::path& dir_in,
                      const std::vector<std::pair<std::string, std::string>>& files) {
  OutputStage stage(dir_in);
  stage.commit(files);
}

void append_general(std::string& out, double v, int digits) {
  char buf[40];
  // std::to_chars with a precision formats as printf's %.*g in the "C" locale ([charconv.to.chars]).
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, digits);
  out.append(buf, r.ptr);
}

std::string channels_csv(const sim::Recorder& rec) {
  ChannelStream out(rec.channels());
  rec.replay(out);
  return out.take_text();
}

bool is_runner_output(const std::filesystem::path& path, const std::vector<const char*>& files) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const bool dir_given = fs::is_directory(path, ec);
  if (!dir_given && path.filename() != "summary.json") return false;
  const fs::path dir = dir_given ? path : path.parent_path();
  if (fs::exists(dir / "operations.json", ec) || !fs::exists(dir / "summary.json", ec))
    return false;
  return std::all_of(files.begin(), files.end(),
                     [&](const char* f) { return fs::exists(dir / f, ec); });
}

}  // namespace lathectl::io
