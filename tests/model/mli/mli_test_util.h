#pragma once
// Synthetic MLIs for the MLI tests (temporary folders, errors: tests/support).
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "simpli/model/mli/mli.h"
#include "support/expect_error.h"
#include "support/temp_dir.h"

namespace simpli::test {

namespace fs = std::filesystem;

/// A rotated, translated camera with an off-centre principal point (fx != fy).
scene::Camera generalCamera(int W, int H);

/// Uniform random depth in [dmin, dmax] and RGBA in [0, 1], with a general camera.
mli::MLI randomMLI(int L, int H, int W, unsigned seed, float dmin = 1.0f, float dmax = 50.0f);

/// Smooth colour, alpha and depth (low-frequency sines), what JPEG handles well.
mli::MLI smoothMLI(int L, int H, int W);

} // namespace simpli::test
