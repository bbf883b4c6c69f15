#pragma once
// Comparison of two MLIs for the tests of the lossless form and its VTK round trips.
#include "simpli/model/mli/mli.h"

namespace simpli::test {

/// Expects the same camera, size and layer count, and bit-identical depth and RGBA in every
/// layer (memcmp, so -0 and NaN payloads count).
void expectSameMLI(const mli::MLI& a, const mli::MLI& b);

} // namespace simpli::test
