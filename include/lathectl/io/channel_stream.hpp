#pragma once
// channels.csv written as a run records it (a run's memory must not grow with its
// duration). A ChannelStream is a sim::RowSink: attached to a streamed Recorder it formats each
// row as it comes (io::append_general, the bytes channels_csv() writes) and writes it out in
// 1 MiB blocks, into the staging directory of the run's output set (OutputStage), so the set
// still appears as a whole. Without a stage (tests, library callers) it collects the text in
// memory, as channels_csv() does.

#include <cstddef>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "lathectl/sim/recorder.hpp"

namespace lathectl::io {

class OutputStage;

// The recorded columns at full precision (the CSV rounds them to 9 significant digits): kept by
// the in-memory streams while a ChannelStream::KeepValues lives (the Python module's runs,
// `lathectl.run`'s Run.channels); empty otherwise.
struct ChannelValues {
  std::vector<std::string> names;
  std::vector<double> rows;  // row-major, names.size() values a row
};

class ChannelStream final : public sim::RowSink {
 public:
  // To a file (created, truncated).
  ChannelStream(const std::vector<sim::Channel>& channels, const std::filesystem::path& file);
  // Into memory (text()).
  explicit ChannelStream(const std::vector<sim::Channel>& channels);
  ~ChannelStream() override;
  ChannelStream(const ChannelStream&) = delete;
  ChannelStream& operator=(const ChannelStream&) = delete;

  void row(std::span<const double> values) noexcept override;
  // Writes what is buffered and closes the file; throws std::filesystem::filesystem_error if
  // any write failed (a full disk). In memory: nothing.
  void finish();
  // The text (in memory only; empty for a file).
  [[nodiscard]] const std::string& text() const noexcept { return buf_; }
  [[nodiscard]] std::string take_text() noexcept { return std::move(buf_); }
  // The values at full precision (in memory, while a KeepValues lived when it was made).
  [[nodiscard]] ChannelValues take_values() noexcept { return std::move(values_); }
  // While one lives (any thread), the in-memory streams made also keep their values (a process
  // flag: a study makes its streams on other threads than its caller's).
  class KeepValues {
   public:
    KeepValues();
    ~KeepValues();
    KeepValues(const KeepValues&) = delete;
    KeepValues& operator=(const KeepValues&) = delete;
  };

  // Upper bound of one row's bytes: each value as %.9g is at most 16 characters
  // ("-1.23456789e-100"), plus its separator.
  static constexpr std::size_t kMaxBytesPerValue = 17;

 private:
  void flush() noexcept;
  std::string buf_;
  ChannelValues values_;
  bool keep_values_ = false;
  std::filesystem::path path_;
  int fd_ = -1;
  int failed_errno_ = 0;
};

// The output set the runs of this thread stream into while the scope lives (`lathectl run`,
// `lathectl demo`): open_channel_stream() writes into its staging directory.
class StreamScope {
 public:
  explicit StreamScope(OutputStage& stage);
  ~StreamScope();
  StreamScope(const StreamScope&) = delete;
  StreamScope& operator=(const StreamScope&) = delete;
  [[nodiscard]] static OutputStage* current();
};

// A stream for the result file `name` (e.g. "channels.csv") of at most `max_rows` rows: into
// `stage` (StreamScope::current() of the thread that runs the study: take it there, before
// handing runs to other threads), or into memory when it is null. Thread-safe. Before the run writes anything it
// checks that the stage's file system has room for max_rows rows at their largest (statvfs; the
// files already opened in the stage counted): if not, throws sim::ConfigError naming
// `key` (the caller turns it into the scenario's error, exit 2), its message ending with
// `advice` (what makes the file smaller) — this replaces the former limit of 5e7 recorded rows.
std::unique_ptr<ChannelStream> open_channel_stream(
    OutputStage* stage, const std::string& name, const std::vector<sim::Channel>& channels,
    double max_rows, const char* key = "run.duration_s",
    const char* advice = "shorten run.duration_s, raise run.record_interval_s");

// The same for a run of `sc`: the disk-space refusal becomes the scenario's error at `key`
// (throw_at_key: its file and line, exit 2).
struct Scenario;
std::unique_ptr<ChannelStream> open_channel_stream(
    const Scenario& sc, OutputStage* stage, const std::string& name,
    const std::vector<sim::Channel>& channels, double max_rows, const char* key,
    const char* advice);

// Rows of `width` doubles kept bit for bit for a second pass once the run has ended, for a
// measure over a window that only the run's end places (system B: the last 30 % of the cut, its
// start known when the cut ends). With a stage: one block in memory, the rest in an unnamed file
// in the stage's directory (O_TMPFILE; gone when the spill is), so memory does not grow with the
// duration; the same disk-space check as open_channel_stream (8 B a value, `what` names it in
// the message). Without a stage (tests, library callers): in memory.
class RowSpill {
 public:
  static constexpr std::size_t kBlockRows = 16384;
  RowSpill(OutputStage* stage, const std::string& what, std::size_t width, double max_rows,
           std::size_t block_rows = kBlockRows);
  ~RowSpill();
  RowSpill(const RowSpill&) = delete;
  RowSpill& operator=(const RowSpill&) = delete;

  void push(std::span<const double> row) noexcept;  // `width` values (missing ones 0)
  [[nodiscard]] std::size_t rows() const noexcept { return file_rows_ + buf_.size() / width_; }
  [[nodiscard]] std::size_t width() const noexcept { return width_; }
  [[nodiscard]] bool on_disk() const noexcept { return fd_ >= 0; }
  // Rows from `from` on into `out` (out.size() / width() of them at most, fewer at the end);
  // returns how many. Throws std::filesystem::filesystem_error if a write or a read failed.
  std::size_t read(std::size_t from, std::span<double> out) const;

 private:
  void flush() noexcept;
  std::filesystem::path dir_;
  std::size_t width_, block_;
  std::vector<double> buf_;
  std::size_t file_rows_ = 0;
  int fd_ = -1;
  int failed_errno_ = 0;
};

}  // namespace lathectl::io
