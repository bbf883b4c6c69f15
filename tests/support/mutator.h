#pragma once
// Seeded, deterministic mutants of valid files for the parser mutation tests
// (tests/model/<folder>/test_*_mutants.cpp): every parser must turn each mutant into a valid
// object or a simpli::Error, never a crash, a hang, std::bad_alloc or another exception. The
// same (seed, corpus) gives the same mutants on every machine (own generator, no std::
// distributions), so a failure names a mutant that can be made again.
#include "simpli/error.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace simpli::test {

class Mutator {
public:
  explicit Mutator(uint64_t seed) : state_(seed) {}

  /// Byte-level mutants of any file: truncation, bit flips, byte insertion and deletion, a run
  /// of bytes overwritten with a huge or zero length field (32/64-bit, either byte order), a
  /// random byte run, a duplicated or removed chunk. Never returns `original` unchanged.
  std::string binary(const std::string& original);
  /// Text mutants: the byte-level kinds and, on tokens and lines, a number replaced by a huge,
  /// tiny, negative, NaN, infinite or non-numeric value, a token dropped or repeated, a line
  /// dropped, repeated, swapped or emptied, an extra field.
  std::string text(const std::string& original);
  /// JSON mutants: a value of the parsed document replaced by one of another type (null, bool,
  /// string, huge / negative / fractional number, array, object, 100 levels of nesting), a key
  /// dropped, renamed or added, a large array; or a text mutant of the document.
  std::string json(const std::string& original);

  /// The kind of the last mutant ("truncate at 17", "number -> nan", ...), for failure messages.
  const std::string& lastKind() const { return kind_; }

  uint64_t next();                  ///< splitmix64
  std::size_t below(std::size_t n); ///< uniform in [0, n), n > 0

private:
  std::string mutateBytes(std::string s);
  std::string mutateTokens(const std::string& s);
  std::string mutateJsonValue(const std::string& s);

  uint64_t state_;
  std::string kind_;
};

/// What a mutation run saw.
struct MutationCounts {
  int parsed = 0;   ///< mutants that were parsed to a valid object
  int rejected = 0; ///< mutants rejected with a simpli::Error
};

enum class MutantKind { Binary, Text, Json };

/// Runs `parse` on `count` mutants of the corpus files (in turn) made by Mutator(seed) of
/// `kind`. `parse` returns normally for a valid object (checking its invariants with gtest
/// assertions) or throws simpli::Error. Anything else thrown is a test failure naming the
/// mutant (`what`, index, kind); so is an error message that is empty or not one line.
MutationCounts runMutants(const std::string& what, uint64_t seed, int count, MutantKind kind,
                          const std::vector<std::string>& corpus,
                          const std::function<void(const std::string& mutant)>& parse);

} // namespace simpli::test
