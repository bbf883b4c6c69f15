// xoshiro256** for the training sampler (training/random.h).
#include "simpli/model/training/random.h"

#include "simpli/error.h"

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace simpli::training {

namespace {
uint64_t rotl(uint64_t x, int k) {
  return (x << k) | (x >> (64 - k));
}
uint64_t splitMix(uint64_t& x) {
  uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}
} // namespace

TrainRandom::TrainRandom(uint64_t seed) {
  uint64_t x = seed;
  for (uint64_t& w : s_)
    w = splitMix(x);
  if (s_[0] == 0 && s_[1] == 0 && s_[2] == 0 && s_[3] == 0)
    s_[0] = 1;
}

uint64_t TrainRandom::bits() {
  const uint64_t result = rotl(s_[1] * 5, 7) * 9;
  const uint64_t t = s_[1] << 17;
  s_[2] ^= s_[0];
  s_[3] ^= s_[1];
  s_[1] ^= s_[2];
  s_[0] ^= s_[3];
  s_[2] ^= t;
  s_[3] = rotl(s_[3], 45);
  return result;
}

void TrainRandom::jump() {
  // The jump polynomial of xoshiro256** (Blackman & Vigna, xoshiro256starstar.c): the state
  // after 2^128 calls of bits() as a GF(2) combination of the states along the way.
  static constexpr uint64_t kJump[] = {0x180ec6d33cfd0abaULL, 0xd5a61266f0c9392cULL,
                                       0xa9582618e03fc9aaULL, 0x39abdc4529b1661cULL};
  State next{};
  for (const uint64_t word : kJump)
    for (int b = 0; b < 64; ++b) {
      if (word & (uint64_t(1) << b))
        for (int i = 0; i < 4; ++i)
          next[size_t(i)] ^= s_[size_t(i)];
      bits();
    }
  s_ = next;
}

double TrainRandom::uniform() {
  return double(bits() >> 11) * 0x1.0p-53;
}

double TrainRandom::normal() {
  const double u1 = 1.0 - uniform(), u2 = uniform(); // u1 in (0, 1]: the logarithm is finite
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

int64_t TrainRandom::uniformInt(int64_t lo, int64_t hi) {
  if (hi < lo)
    fail("TrainRandom::uniformInt: empty range [", lo, ", ", hi, "]");
  const uint64_t range = uint64_t(hi) - uint64_t(lo) + 1; // 0 means the full 2^64 range
  if (range == 0)
    return int64_t(bits());
  // Reject the top partial block so every value is equally likely.
  const uint64_t limit = UINT64_MAX - UINT64_MAX % range;
  uint64_t x;
  do
    x = bits();
  while (x >= limit);
  return lo + int64_t(x % range);
}

void TrainRandom::setState(const State& state) {
  if (state[0] == 0 && state[1] == 0 && state[2] == 0 && state[3] == 0)
    fail("TrainRandom: the all-zero state is invalid");
  s_ = state;
}

std::string TrainRandom::stateString() const {
  char buf[4 * 17 + 1];
  std::snprintf(buf, sizeof buf, "%016" PRIx64 ":%016" PRIx64 ":%016" PRIx64 ":%016" PRIx64, s_[0],
                s_[1], s_[2], s_[3]);
  return buf;
}

TrainRandom::State TrainRandom::parseState(const std::string& text, const std::string& what) {
  State s{};
  std::istringstream in(text);
  for (int i = 0; i < 4; ++i) {
    std::string word;
    if (!std::getline(in, word, ':') || word.size() != 16 ||
        word.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos)
      fail(what, ": random state '", text, "': expected four 16-digit hex words joined by ':'");
    s[i] = std::stoull(word, nullptr, 16);
  }
  std::string rest;
  if (std::getline(in, rest))
    fail(what, ": random state '", text, "': trailing text '", rest, "'");
  if (s[0] == 0 && s[1] == 0 && s[2] == 0 && s[3] == 0)
    fail(what, ": random state '", text, "' is all zero");
  return s;
}

} // namespace simpli::training
