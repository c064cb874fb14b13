#pragma once
// Asynchronous quenching, the principle behind seed 001's modulated feed: a van der Pol
// oscillator (a self-excited vibration with limit-cycle amplitude a0) forced at a frequency far
// from its own,
//   ẍ − ε·(1 − x²)·ẋ + x = E·cos(Ω·t),      a0 = 2 for small ε,
// loses its self-excited component when the forced amplitude B = E/|1 − Ω²| is large enough.
// First-order averaging (x ≈ a·cos(t + φ) + B·cos Ωt): ȧ = (ε/2)·a·(1 − B²/2 − a²/4), so the free
// oscillation dies for B > √2 = a0/√2. The seed asks for 1.41·a0 (twice that).

namespace lathectl::dynamics {

struct QuenchResult {
  double self_amplitude_mid = 0.0;  // self-excited amplitude over the run's second quarter
  double self_amplitude = 0.0;      // ... over its last quarter
  double forced_amplitude = 0.0;    // measured amplitude at Ω (last quarter)
};

// Simulates (RK4, 200 steps per shortest period) from the forced response plus a self-excited
// seed of amplitude `seed_amplitude`, and separates the response at Ω (least-squares fit of
// cos/sin) from the rest (the self-excited part) over two windows.
QuenchResult van_der_pol_forced(double eps, double omega_forcing, double forcing,
                                double duration = 400.0, double seed_amplitude = 0.5);

// The forced amplitude B (measured) at which a small self-excited oscillation neither grows nor
// decays: bisection on the forcing with a 0.05 seed, growth judged between the two windows.
// (Judging by "amplitude below x % at the end" overestimates it: near the threshold the decay
// rate (ε/2)(1 − B²/2) vanishes.)
double quenching_threshold(double eps, double omega_forcing);

}  // namespace lathectl::dynamics
