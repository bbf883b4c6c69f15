#pragma once
// Deterministic random numbers for the synthetic scenes.
//
// Why our own distributions: the output sequence of std::mt19937_64 is fixed by the C++
// standard, but std::uniform_real_distribution, std::normal_distribution, std::shuffle etc. are
// not (libstdc++, libc++ and MSVC produce different values from the same engine). A scene must
// be the same for a seed on every platform, so only the raw engine output is used and every
// distribution below is spelled out.
#include <cstdint>
#include <random>
#include <vector>

namespace simpli::synthetic {

/// SplitMix64 finaliser: a bijective, well-mixing 64-bit hash.
uint64_t mix64(uint64_t x);

/// Seed of item `index` of a stream seeded with `seed`; different (seed, index) pairs give
/// unrelated streams. Used for per-object, per-view and per-dataset-index seeds.
uint64_t deriveSeed(uint64_t seed, uint64_t index);

/// Uniform double in [0, 1) from the top 53 bits of `bits`.
double unitFromBits(uint64_t bits);

class Random {
public:
  explicit Random(uint64_t seed) : engine_(seed) {}

  uint64_t bits() { return engine_(); }
  /// Uniform in [0, 1).
  double uniform() { return unitFromBits(engine_()); }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [lo, hi] (inclusive), unbiased (rejection sampling).
  int uniformInt(int lo, int hi);
  /// Standard normal (Box-Muller; one value per call, nothing cached).
  double normal();
  bool chance(double p) { return uniform() < p; }
  /// -1 or +1 with equal probability.
  double sign() { return chance(0.5) ? 1.0 : -1.0; }
  /// A uniformly random permutation of 0 .. n-1 (Fisher-Yates).
  std::vector<int> permutation(int n);

private:
  std::mt19937_64 engine_;
};

} // namespace simpli::synthetic
