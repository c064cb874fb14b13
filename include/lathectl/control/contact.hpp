#pragma once
// Contact: is the tool in the material? The load above air_threshold·limit means contact at
// once; below it for air_time_s means the tool has left the cut (a short dip — an interrupted
// cut, the noise of a light cut — is not an exit). The adaptive controller's regulator state and
// the machine side's operation log, overload levels and teach-in all decide contact with this.
// Real-time: no allocation, no exceptions.

namespace lathectl::control {

class ContactDetector {
 public:
  // One sample of the load against `threshold` (same unit); `active`: the detector runs (a feed
  // move with a valid reading) — when not, contact ends at once. Returns true in the sample the
  // tool enters the cut.
  bool update(double load, double threshold, double air_time_s, double dt_s,
              bool active) noexcept {
    if (!active) {
      reset();
      return false;
    }
    if (load > threshold) {
      below_s_ = 0.0;
      const bool entered = !in_;
      in_ = true;
      return entered;
    }
    if (in_) {
      below_s_ += dt_s;
      if (below_s_ >= air_time_s) in_ = false;
    }
    return false;
  }
  void reset() noexcept {
    in_ = false;
    below_s_ = 0.0;
  }
  [[nodiscard]] bool in_cut() const noexcept { return in_; }

 private:
  bool in_ = false;
  double below_s_ = 0.0;
};

}  // namespace lathectl::control
