#pragma once
// channels.csv written as a run records it (issue 19: a run's memory must not grow with its
// duration). A ChannelStream is a sim::RowSink: attached to a streamed Recorder it formats each
// row as it comes (io::append_general, the bytes channels_csv() writes) and writes it out in
// 1 MiB blocks, into the staging directory of the run's output set (OutputStage), so the set
// still appears as a whole. Without a stage (tests, library callers) it collects the text in
// memory, as channels_csv() does.

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "lathectl/sim/recorder.hpp"

namespace lathectl::io {

class OutputStage;

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
  [[nodiscard]] bool to_file() const noexcept { return fd_ >= 0 || failed_errno_ != 0; }
  // The text (in memory only; empty for a file).
  [[nodiscard]] const std::string& text() const noexcept { return buf_; }
  [[nodiscard]] std::string take_text() noexcept { return std::move(buf_); }

  // Upper bound of one row's bytes: each value as %.9g is at most 16 characters
  // ("-1.23456789e-100"), plus its separator.
  static constexpr std::size_t kMaxBytesPerValue = 17;

 private:
  void flush() noexcept;
  std::string buf_;
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

}  // namespace lathectl::io
