#include "lathectl/io/channel_stream.hpp"

#include <fcntl.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <system_error>

#include "lathectl/io/output.hpp"
#include "lathectl/io/scenario.hpp"
#include "lathectl/sim/config_error.hpp"

namespace lathectl::io {

namespace fs = std::filesystem;

namespace {
constexpr std::size_t kBlock = std::size_t{1} << 20;  // bytes written at a time
thread_local OutputStage* g_stage = nullptr;
std::atomic<int> g_keep_values{0};

void header(std::string& s, const std::vector<sim::Channel>& ch) {
  for (std::size_t i = 0; i < ch.size(); ++i) s += (i ? "," : "") + ch[i].name;
  s += '\n';
}
}  // namespace

ChannelStream::ChannelStream(const std::vector<sim::Channel>& channels) {
  header(buf_, channels);
  keep_values_ = g_keep_values.load() > 0;
  if (keep_values_)
    for (const auto& c : channels) values_.names.push_back(c.name);
}

ChannelStream::KeepValues::KeepValues() { ++g_keep_values; }
ChannelStream::KeepValues::~KeepValues() { --g_keep_values; }

ChannelStream::ChannelStream(const std::vector<sim::Channel>& channels, const fs::path& file)
    : path_(file) {
  fd_ = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0)
    throw fs::filesystem_error("cannot write", file, std::error_code(errno, std::generic_category()));
  buf_.reserve(kBlock + 4096);
  header(buf_, channels);
}

ChannelStream::~ChannelStream() {
  if (fd_ >= 0) ::close(fd_);
}

void ChannelStream::row(std::span<const double> values) noexcept {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i) buf_ += ',';
    append_general(buf_, values[i], 9);
  }
  buf_ += '\n';
  if (keep_values_) values_.rows.insert(values_.rows.end(), values.begin(), values.end());
  if (fd_ >= 0 && buf_.size() >= kBlock) flush();
}

void ChannelStream::flush() noexcept {
  std::size_t done = 0;
  while (done < buf_.size() && failed_errno_ == 0) {
    const ssize_t n = ::write(fd_, buf_.data() + done, buf_.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      failed_errno_ = n < 0 ? errno : EIO;
      break;
    }
    done += static_cast<std::size_t>(n);
  }
  buf_.clear();  // capacity kept: no allocation in the steady state
}

void ChannelStream::finish() {
  if (fd_ < 0 && failed_errno_ == 0) return;  // in memory
  if (fd_ >= 0) {
    flush();
    if (::close(fd_) != 0 && failed_errno_ == 0) failed_errno_ = errno;
    fd_ = -1;
  }
  if (failed_errno_ != 0)
    throw fs::filesystem_error("write failed", path_,
                               std::error_code(failed_errno_, std::generic_category()));
}

StreamScope::StreamScope(OutputStage& stage) { g_stage = &stage; }
StreamScope::~StreamScope() { g_stage = nullptr; }
OutputStage* StreamScope::current() { return g_stage; }

namespace {
// Promises `max_rows` rows of `per_row` bytes in the stage, if its file system has room for them
// beside what was promised before (statvfs); else sim::ConfigError at `key`, its message ending
// with `advice`.
void reserve_rows(OutputStage& stage, const std::string& name, double max_rows, double per_row,
                  const char* key, const char* advice) {
  static std::mutex mutex;  // the stage's running sum of promised bytes
  std::lock_guard lock(mutex);
  const double need = (std::max(max_rows, 0.0) + 1.0) * per_row;
  struct statvfs vfs{};
  // Test-only: LATHECTL_TEST_FREE_BYTES=<n> stands for the file system's free space.
  const char* fake = std::getenv("LATHECTL_TEST_FREE_BYTES");
  if (fake || ::statvfs(stage.path().c_str(), &vfs) == 0) {
    const double free_bytes =
        fake ? std::strtod(fake, nullptr)
             : static_cast<double>(vfs.f_bavail) * static_cast<double>(vfs.f_frsize);
    if (stage.reserved_bytes() + need > free_bytes) {
      char msg[480];
      std::snprintf(msg, sizeof msg,
                    "%s of up to %.0f rows would need up to %.3g GB (%.0f B a row), more than the "
                    "%.3g GB free on the output's file system (%.3g GB already promised to the "
                    "other recorded files): %s or choose another --out",
                    name.c_str(), std::ceil(max_rows), need * 1e-9, per_row, free_bytes * 1e-9,
                    stage.reserved_bytes() * 1e-9, advice);
      throw sim::ConfigError(key, msg);
    }
  }
  stage.reserved_bytes() += need;
}
}  // namespace

std::unique_ptr<ChannelStream> open_channel_stream(OutputStage* stage, const std::string& name,
                                                   const std::vector<sim::Channel>& channels,
                                                   double max_rows, const char* key,
                                                   const char* advice) {
  if (!stage) return std::make_unique<ChannelStream>(channels);
  reserve_rows(*stage, name, max_rows,
               static_cast<double>(channels.size() * ChannelStream::kMaxBytesPerValue), key,
               advice);
  auto s = std::make_unique<ChannelStream>(channels, stage->path() / name);
  stage->add_streamed(name);
  return s;
}

std::unique_ptr<ChannelStream> open_channel_stream(const Scenario& sc, OutputStage* stage,
                                                   const std::string& name,
                                                   const std::vector<sim::Channel>& channels,
                                                   double max_rows, const char* key,
                                                   const char* advice) {
  try {
    return open_channel_stream(stage, name, channels, max_rows, key, advice);
  } catch (const std::invalid_argument& e) {
    throw_at_key(sc, e);
  }
}

RowSpill::RowSpill(OutputStage* stage, const std::string& what, std::size_t width, double max_rows,
                   std::size_t block_rows)
    : width_(std::max<std::size_t>(width, 1)), block_(std::max<std::size_t>(block_rows, 1)) {
  if (!stage) return;  // in memory
  reserve_rows(*stage, what, max_rows, static_cast<double>(width_ * sizeof(double)),
               "run.duration_s", "shorten run.duration_s, raise run.record_interval_s");
  dir_ = stage->path();
  buf_.reserve(block_ * width_);
}

RowSpill::~RowSpill() {
  if (fd_ >= 0) ::close(fd_);
}

void RowSpill::push(std::span<const double> row) noexcept {
  const std::size_t n = std::min(row.size(), width_);
  buf_.insert(buf_.end(), row.begin(), row.begin() + static_cast<std::ptrdiff_t>(n));
  buf_.resize(buf_.size() + (width_ - n), 0.0);
  if (!dir_.empty() && buf_.size() >= block_ * width_) flush();
}

void RowSpill::flush() noexcept {
  if (failed_errno_ != 0) return;
  if (fd_ < 0) {
    // An unnamed file in the stage (the file system the disk check measured); where O_TMPFILE is
    // not supported, a named one removed at once.
    fd_ = ::open(dir_.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
    if (fd_ < 0) {
      std::string name = (dir_ / ".spill-XXXXXX").string();
      fd_ = ::mkostemp(name.data(), O_CLOEXEC);
      if (fd_ >= 0) ::unlink(name.c_str());
    }
    if (fd_ < 0) {
      failed_errno_ = errno;
      return;
    }
  }
  const auto* p = reinterpret_cast<const char*>(buf_.data());
  const std::size_t bytes = buf_.size() * sizeof(double);
  std::size_t done = 0;
  while (done < bytes) {
    const ssize_t n = ::write(fd_, p + done, bytes - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      failed_errno_ = n < 0 ? errno : EIO;
      return;
    }
    done += static_cast<std::size_t>(n);
  }
  file_rows_ += buf_.size() / width_;
  buf_.clear();  // capacity kept
}

std::size_t RowSpill::read(std::size_t from, std::span<double> out) const {
  if (failed_errno_ != 0)
    throw fs::filesystem_error("cannot keep the rows for the run's window", dir_,
                               std::error_code(failed_errno_, std::generic_category()));
  const std::size_t total = rows();
  if (from >= total) return 0;
  const std::size_t want = std::min(out.size() / width_, total - from);
  std::size_t got = 0;
  while (got < want && from + got < file_rows_) {  // from the file
    const std::size_t n = std::min(want - got, file_rows_ - (from + got));
    const std::size_t bytes = n * width_ * sizeof(double);
    auto* p = reinterpret_cast<char*>(out.data() + got * width_);
    std::size_t done = 0;
    while (done < bytes) {
      const auto off = static_cast<off_t>((from + got) * width_ * sizeof(double) + done);
      const ssize_t r = ::pread(fd_, p + done, bytes - done, off);
      if (r < 0 && errno == EINTR) continue;
      if (r <= 0)
        throw fs::filesystem_error("cannot read back the rows for the run's window", dir_,
                                   std::error_code(r < 0 ? errno : EIO, std::generic_category()));
      done += static_cast<std::size_t>(r);
    }
    got += n;
  }
  if (got < want) {  // from the block in memory
    const std::size_t b = (from + got - file_rows_) * width_;
    std::copy_n(buf_.begin() + static_cast<std::ptrdiff_t>(b), (want - got) * width_,
                out.begin() + static_cast<std::ptrdiff_t>(got * width_));
    got = want;
  }
  return got;
}

}  // namespace lathectl::io
