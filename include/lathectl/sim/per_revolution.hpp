#pragma once
// The per-revolution mean of a recorded signal: at each sample, the mean over the trailing
// window of one spindle revolution at that sample's speed, w = round(60 / max(n, 1 rpm) / Δt)
// samples (at least 1; fewer at the start of the record). A feed drive cannot act within a
// revolution, so this is the force a feed controller answers for. One function for every claim,
// metric and plot that shows it, so that what is plotted is what is claimed.

#include <span>
#include <vector>

namespace lathectl::sim {

// `x` and `rpm` sampled together every `dt_s` seconds (same length).
std::vector<double> per_revolution_mean(std::span<const double> x, std::span<const double> rpm,
                                        double dt_s);

}  // namespace lathectl::sim
