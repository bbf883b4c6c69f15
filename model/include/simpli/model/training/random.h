#pragma once
// The training sampler's random numbers: xoshiro256** (Blackman & Vigna) with distributions
// spelled out, so that a run is the same on every platform and its whole state (four 64-bit
// words) can be written into a checkpoint and restored: a resumed run draws exactly the
// samples the uninterrupted run would have drawn.
#include <array>
#include <cstdint>
#include <string>

namespace simpli::training {

class TrainRandom {
public:
  using State = std::array<uint64_t, 4>;

  /// The state is filled from `seed` with SplitMix64 (never all zero).
  explicit TrainRandom(uint64_t seed = 0);

  uint64_t bits();
  /// Uniform in [0, 1) from the top 53 bits.
  double uniform();
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [lo, hi] (inclusive), unbiased (rejection). Throws when hi < lo.
  int64_t uniformInt(int64_t lo, int64_t hi);
  bool chance(double p) { return uniform() < p; }
  /// Standard normal (Box-Muller from two uniforms, spelled out so that runs agree across
  /// platforms, unlike std::normal_distribution).
  double normal();

  /// Advances the state by 2^128 draws (the generator's published jump polynomial): streams
  /// made by jumping one seed's state 0, 1, 2, ... times never overlap (sample streams of
  /// data-parallel training, trainer.h).
  void jump();

  const State& state() const { return s_; }
  /// Throws simpli::Error for the all-zero state (xoshiro's one fixed point).
  void setState(const State& state);

  /// "xxxxxxxxxxxxxxxx:xxxxxxxxxxxxxxxx:..." (hex words) and back; parse errors name `what`.
  std::string stateString() const;
  static State parseState(const std::string& text, const std::string& what);

private:
  State s_{};
};

} // namespace simpli::training
