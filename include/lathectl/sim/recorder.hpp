#pragma once
// Recorder of a rig's channels: names and units declared up front, one row per record interval.
// Two storages:
//  - columns (the constructor with a capacity): every row kept, capacity reserved for the whole
//    run, push_row() never allocates; column() gives a channel's whole record. For the systems
//    whose runs are short by construction (A's regulator studies, tests); every
//    system's `lathectl run` streams.
//  - streamed (Recorder::streamed): no row kept. Each row goes to the attached sinks as it is
//    pushed (channels.csv written to disk, a metric's accumulator) and into a bounded min/max
//    pyramid per channel for the plots (PlotPyramid, kPlotValuesPerLevel per level): memory does
//    not grow with the run's duration (30 simulated minutes held as columns, CSV text and plot
//    copies took ~0.8 GB).

#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "lathectl/sim/plot_pyramid.hpp"

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

class Recorder {
 public:
  Recorder() = default;
  // Columns storage, capacity_rows rows.
  Recorder(std::vector<Channel> channels, std::size_t capacity_rows);
  // Streamed storage: rows go to `sinks` (not owned; they must outlive the recording) and into a
  // PlotPyramid per channel against channel 0 (the time), at most values_per_level values per
  // level (2^14: A with its comparison run held 116 MB at 2^16 for 1800 s; a recording up to
  // 16 384 rows keeps its samples, so its charts zoom to them). values_per_level 0: no plots
  // (a run that is only measured, such as B's sweep runs; plot_points gives nothing).
  static constexpr std::size_t kPlotValuesPerLevel = std::size_t{1} << 14;
  static Recorder streamed(std::vector<Channel> channels, std::vector<RowSink*> sinks = {},
                           std::size_t values_per_level = kPlotValuesPerLevel);
  // Adds a sink (not owned; it must outlive the recording): it receives each row pushed from now.
  void attach(RowSink* sink) { sinks_.push_back(sink); }
  // Appends one row (values in channel order) and hands it to the sinks. Columns: rows beyond
  // capacity are dropped (and counted).
  void push_row(std::span<const double> values) noexcept;
  [[nodiscard]] std::size_t rows() const noexcept { return rows_; }
  [[nodiscard]] std::size_t dropped() const noexcept { return dropped_; }
  [[nodiscard]] const std::vector<Channel>& channels() const noexcept { return channels_; }
  [[nodiscard]] std::size_t index(const std::string& name) const;  // throws std::out_of_range
  // Column view of one channel (length rows()). Columns storage only (streamed: empty).
  [[nodiscard]] std::span<const double> column(const std::string& name) const;
  [[nodiscard]] std::span<const double> column(std::size_t i) const noexcept;
  // Hands every row kept to `sink`, in order (columns storage; streamed: none are kept).
  void replay(RowSink& sink) const;
  // Channel `name` against channel 0 for a plot: every row (columns) or at most 4096 points from
  // its pyramid (streamed).
  void plot_points(const std::string& name, std::vector<double>& x, std::vector<double>& y) const;
  // Streamed: the channel's finished pyramid, for the interactive plot (io::Series::pyramid);
  // columns: none (the report builds it from every row).
  [[nodiscard]] std::shared_ptr<const PlotPyramid> plot_pyramid(const std::string& name) const;

 private:
  std::vector<Channel> channels_;
  std::vector<std::vector<double>> data_;
  std::vector<RowSink*> sinks_;
  std::vector<PlotPyramid> plots_;
  bool streamed_ = false;
  std::size_t capacity_ = 0;
  std::size_t rows_ = 0;
  std::size_t dropped_ = 0;
};

}  // namespace lathectl::sim
