#pragma once
// Result files. Every write is atomic: a single file goes to a temporary file in the same
// directory, which is then renamed over the target, so an interrupted run leaves no half file.
// A run's set of files (summary.json, channels.csv, report.html, ...) appears as a whole: it is
// written into a fresh staging directory beside the output directory, which then takes the
// output directory's place in one rename, so a reader never sees new files beside old ones.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "lathectl/sim/recorder.hpp"

namespace lathectl::io {

// Writes `content` to a temporary file beside `path`, then renames it over `path`. A failed
// write (a full disk, a quota) removes the temporary and throws InputError naming `path` and the
// system's reason.
void write_file_atomic(const std::filesystem::path& path, const std::string& content);

// Every HTML page lathectl writes carries this line in its head: what a single-file output may
// replace (write_output_file).
inline constexpr const char* kGeneratorMeta = "<meta name=\"generator\" content=\"lathectl\">";

// A single result file a user names with `flag` (lathectl report --out): written atomically, and
// only where nothing but an earlier lathectl page is. Throws InputError "FLAG PATH: ..." (before
// anything is written) when `path` exists and is not a regular file (a device such as /dev/null,
// a directory, a FIFO), is one of `inputs` (the same file under any name), or is a file lathectl
// did not write (no kGeneratorMeta in its head, nor the head of an older lathectl page).
void write_output_file(const std::filesystem::path& path, const std::string& content,
                       const std::string& flag, const std::vector<std::filesystem::path>& inputs);
// The same checks alone, for a command to make before its work.
void check_output_file(const std::filesystem::path& path, const std::string& flag,
                       const std::vector<std::filesystem::path>& inputs);
std::string channels_csv(const sim::Recorder& rec);

// Appends v as printf's "%.<digits>g" would write it in the "C" locale, byte for byte (inf,
// -inf, nan, -nan included), by std::to_chars: about 10× faster than snprintf, which made
// writing channels.csv most of a long run's CPU. digits: 1..17.
void append_general(std::string& out, double v, int digits);

// Marks a directory as a lathectl output set (written first into every set): only a directory
// that has it, is empty, or holds nothing but result files of an older lathectl is replaced.
inline constexpr const char* kOutputMarker = ".lathectl-output";

// Checks, before anything runs, that `dir` can receive results: it is a directory or can be
// created, and is writable; with `whole_set` (a run's set, replaced as a whole) an existing `dir`
// must also be empty or a lathectl output set. Removes temporaries that dead runs left beside it
// and in it. Throws InputError "FLAG DIR: ..." (one line). `inputs` are the files and
// directories the command reads: `dir` may be none of them nor hold one (check_not_above).
void prepare_output_dir(const std::filesystem::path& dir, const std::string& flag,
                        bool whole_set = true,
                        const std::vector<std::filesystem::path>& inputs = {});
// Throws InputError "FLAG DIR: ..." when `dir` is one of `inputs` or an ancestor of one (the
// same file or directory under any name, symbolic links resolved): an output set replaces `dir`
// as a whole, so `lathectl compare P/x P/y --out P` would remove the runs it compares. Every
// command's --out goes through it (prepare_output_dir), before anything is written.
void check_not_above(const std::filesystem::path& dir, const std::string& flag,
                     const std::vector<std::filesystem::path>& inputs);

// Writes `files` (name, content) as one set replacing `dir` as a whole: staged in
// DIR.tmp-<pid>/ beside it, then swapped into place (renameat2 RENAME_EXCHANGE, or two renames
// where the file system lacks it) and the old set removed. A kill leaves either the old set or the
// new one at `dir` (with the two-rename fallback, at worst no set), never a mix; its staging
// directory is removed by the next prepare_output_dir / write_output_set beside it.
void write_output_set(const std::filesystem::path& dir,
                      const std::vector<std::pair<std::string, std::string>>& files);

// The staging directory of one output set, made before a run so that large files can be
// streamed into it as they are produced (channels.csv, ChannelStream) instead of being held in
// memory: DIR.tmp-<pid>/ beside `dir`, marked first. commit() writes the remaining files and
// swaps the set into place as write_output_set does; a stage not committed (an error, an
// exception) is removed by the destructor, and one a kill leaves by the next run beside it.
class OutputStage {
 public:
  explicit OutputStage(const std::filesystem::path& dir);
  ~OutputStage();
  OutputStage(const OutputStage&) = delete;
  OutputStage& operator=(const OutputStage&) = delete;
  [[nodiscard]] const std::filesystem::path& path() const noexcept { return stage_; }
  // `name` has been written into path() (complete): it is part of the set.
  void add_streamed(const std::string& name) { streamed_.push_back(name); }
  [[nodiscard]] bool streamed(const std::string& name) const;
  // Bytes promised to files being streamed into the stage (the disk-space check's running sum).
  double& reserved_bytes() noexcept { return reserved_; }
  void commit(const std::vector<std::pair<std::string, std::string>>& files);

 private:
  std::filesystem::path dir_, stage_;
  std::vector<std::string> streamed_;
  double reserved_ = 0.0;
  bool done_ = false;
};

// Removes, in `dir`, what runs that are no longer alive left behind: NAME.tmp.<pid> files
// (write_file_atomic) and NAME.tmp-<pid> / NAME.old-<pid> staging directories (only ones that are
// empty or carry the output marker). A live process's temporaries are left alone.
void remove_dead_temporaries(const std::filesystem::path& dir);

// A LinuxCNC runner's output (scripts/linuxcnc-sim-*: its directory, or its summary.json) without
// an operation log, holding summary.json and every one of `files`: the session `lathectl report`
// reads for that runner's system.
bool is_runner_output(const std::filesystem::path& path, const std::vector<const char*>& files);

}  // namespace lathectl::io
