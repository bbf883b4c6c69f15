// Portable random distributions over std::mt19937_64 (see synthetic/random.h for why).
#include "simpli/model/synthetic/random.h"

#include "simpli/error.h"

#include <cmath>
#include <utility>

namespace simpli::synthetic {

uint64_t mix64(uint64_t x) {
  // SplitMix64 (Steele, Lea, Flood 2014): add the golden-ratio increment, then two
  // xor-shift-multiply rounds.
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

uint64_t deriveSeed(uint64_t seed, uint64_t index) {
  // Two rounds so that neighbouring seeds and neighbouring indices both decorrelate.
  return mix64(mix64(seed) ^ mix64(index + 0x632BE59BD9B4E019ull));
}

double unitFromBits(uint64_t bits) {
  return double(bits >> 11) * 0x1.0p-53;
}

int Random::uniformInt(int lo, int hi) {
  if (hi < lo)
    fail("Random::uniformInt: empty range [", lo, ", ", hi, "]");
  const uint64_t range = uint64_t(int64_t(hi) - int64_t(lo)) + 1;
  // Reject the 2^64 mod range smallest values so that the rest is a whole number of blocks of
  // `range` values and every result is equally likely.
  const uint64_t threshold = (uint64_t(0) - range) % range;
  uint64_t x = engine_();
  while (x < threshold)
    x = engine_();
  return int(int64_t(lo) + int64_t(x % range));
}

double Random::normal() {
  // Box-Muller with u1 in (0, 1] so that the logarithm is finite.
  const double u1 = 1.0 - uniform();
  const double u2 = uniform();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

std::vector<int> Random::permutation(int n) {
  std::vector<int> p(size_t(n > 0 ? n : 0));
  for (int i = 0; i < n; ++i)
    p[size_t(i)] = i;
  for (int i = n - 1; i > 0; --i)
    std::swap(p[size_t(i)], p[size_t(uniformInt(0, i))]);
  return p;
}

} // namespace simpli::synthetic
