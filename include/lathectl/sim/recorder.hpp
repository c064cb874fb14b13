#pragma once
// Recorder of a rig's channels: names and units declared up front, one row per record interval.
// Two storages:
//  - columns (the constructor with a capacity): every row kept, capacity reserved for the whole
//    run, push_row() never allocates; column() gives a channel's whole record. For the systems
//    whose runs are short by construction (B, C, D: a fixed cut; A's regulator studies).
//  - streamed (Recorder::streamed): no row kept. Each row goes to the attached sinks as it is
//    pushed (channels.csv written to disk, a metric's accumulator) and into a bounded min/max
//    decimation per channel for the plots (PlotDecimator): memory does not grow with the run's
//    duration (issue 19: 30 simulated minutes held ~0.8 GB as columns, CSV text and plot copies).

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace lathectl::sim {

struct Channel {
  std::string name;  // snake_case with unit suffix, e.g. "force_N"
  std::string unit;
};

// Receives every row a streamed Recorder records, in channel order, as it is recorded.
class RowSink {
 public:
  virtual ~RowSink() = default;
  virtual void row(std::span<const double> values) noexcept = 0;
};

// A plot series of any length held in bounded memory: the points are grouped into at most
// max_buckets buckets of equal row counts, each keeping its smallest and its largest y (with
// their x), in the order they came; when the buckets are full, neighbours merge pairwise and a
// bucket takes twice the rows. Peaks survive (a bucket's extremes are the extremes of its rows),
// as in the report's per-pixel decimation; up to max_buckets points are kept exactly.
class PlotDecimator {
 public:
  explicit PlotDecimator(std::size_t max_buckets = 2048);
  void push(double x, double y) noexcept;  // never allocates (storage reserved up front)
  // The points in arrival order: ≤ 2·max_buckets of them (all of them up to max_buckets).
  void points(std::vector<double>& x, std::vector<double>& y) const;
  [[nodiscard]] std::size_t pushed() const noexcept { return pushed_; }

 private:
  struct Point {
    std::size_t i;  // arrival index
    double x, y;
  };
  struct Bucket {
    Point lo, hi;  // smallest and largest y (NaN only while the bucket has no number)
    std::size_t n = 0;
  };
  static void absorb(Bucket& b, const Point& p) noexcept;
  std::vector<Bucket> b_;
  std::size_t max_ = 2;
  std::size_t per_bucket_ = 1;
  std::size_t pushed_ = 0;
};

class Recorder {
 public:
  Recorder() = default;
  // Columns storage, capacity_rows rows.
  Recorder(std::vector<Channel> channels, std::size_t capacity_rows);
  // Streamed storage: rows go to `sinks` (not owned; they must outlive the recording) and into a
  // PlotDecimator per channel against channel 0 (the time).
  static Recorder streamed(std::vector<Channel> channels, std::vector<RowSink*> sinks = {},
                           std::size_t plot_buckets = 2048);
  // Adds a sink (not owned; it must outlive the recording): it receives each row pushed from now.
  void attach(RowSink* sink) { sinks_.push_back(sink); }
  // Appends one row (values in channel order) and hands it to the sinks. Columns: rows beyond
  // capacity are dropped (and counted).
  void push_row(std::span<const double> values) noexcept;
  [[nodiscard]] std::size_t rows() const noexcept { return rows_; }
  [[nodiscard]] std::size_t dropped() const noexcept { return dropped_; }
  [[nodiscard]] bool is_streamed() const noexcept { return streamed_; }
  [[nodiscard]] const std::vector<Channel>& channels() const noexcept { return channels_; }
  [[nodiscard]] std::size_t index(const std::string& name) const;  // throws std::out_of_range
  // Column view of one channel (length rows()). Columns storage only (streamed: empty).
  [[nodiscard]] std::span<const double> column(const std::string& name) const;
  [[nodiscard]] std::span<const double> column(std::size_t i) const noexcept;
  // Hands every row kept to `sink`, in order (columns storage; streamed: none are kept).
  void replay(RowSink& sink) const;
  // Channel `name` against channel 0 for a plot: every row (columns) or the bounded decimation
  // (streamed).
  void plot_points(const std::string& name, std::vector<double>& x, std::vector<double>& y) const;

 private:
  std::vector<Channel> channels_;
  std::vector<std::vector<double>> data_;
  std::vector<RowSink*> sinks_;
  std::vector<PlotDecimator> plots_;
  bool streamed_ = false;
  std::size_t capacity_ = 0;
  std::size_t rows_ = 0;
  std::size_t dropped_ = 0;
};

}  // namespace lathectl::sim
