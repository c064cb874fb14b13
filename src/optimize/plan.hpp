#pragma once
// The feed of each piece of each move (plan.cpp) and the program written from it (rewrite.cpp).
#include <string>
#include <utility>
#include <vector>

#include "lathectl/cutting/cutting_model.hpp"
#include "lathectl/cutting/force_parameter.hpp"
#include "optimize/optimize.hpp"

namespace lathectl::optimize {

struct FeedLimits {
  double param = 0.0;                                // force parameter (N, or W for a power sensor)
  double power_W = 0.0;                              // cutting power
  double torque_N_m = 0.0;                           // spindle torque
  double feed_min = 0.0, feed_max = 0.0, air = 0.0;  // mm/rev
};
FeedLimits feed_limits(const systems::e_adaptive::Settings& e, const Options& opt);

std::pair<double, std::string> largest_feed(const cutting::CuttingModel& cut,
                                            cutting::ForceParameter which, const FeedLimits& l,
                                            double t, double v, double h, double w, double x);

// [first, last) sample of each move.
std::vector<std::pair<std::size_t, std::size_t>> move_ranges(const Samples& s, std::size_t moves);

// What each move is to the plan, per move (empty: nothing): `kept` why it keeps its programmed
// feed (a keep marker, an unknown tool, after a rapid through material); `finishing` why it is a
// finishing cut whatever its depth (cutter compensation, a G70 cycle, a finish marker): its feed
// is at most the one of the roughness the programmed feed gives, never raised.
// `finishing_pass`: the move belongs to a pass whose cut is mostly within the finish depth: its
// pieces the stock model finds in air (a shoulder or face it does not know is there) are not
// raised either.
struct MoveRoles {
  std::vector<std::string> kept, finishing, finishing_pass;
  std::vector<const ToolSpec*> spec;  // the move's tool in --tool-file (nullptr: not listed)
};

// Pieces and feeds for every move from the prediction at the programmed feeds; kept moves and
// threading keep the programmed feed.
Plan choose_feeds(const io::CanonProgram& prog, const Prediction& before,
                  const systems::e_adaptive::Settings& e, const Options& opt,
                  const MoveRoles& roles);

// The feeds of `plan`'s pieces taken again from `trial`, the prediction of that plan: LinuxCNC's
// blend arcs (blend.hpp) depend on where the program is split, so the path each piece really cuts
// is known only once the pieces are. The pieces' bounds stay.
void refeed(const io::CanonProgram& prog, Plan& plan, const Prediction& trial,
            const systems::e_adaptive::Settings& e, const Options& opt,
            const MoveRoles& roles);

}  // namespace lathectl::optimize
