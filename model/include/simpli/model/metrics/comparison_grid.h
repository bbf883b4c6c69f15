#pragma once
// Pictures for quality reports: a row of equally sized images side by side, and an error map
// that shows where a render differs from the ground truth.
#include "simpli/model/io/image.h"

#include <vector>

namespace simpli::metrics {

/// Images are io::Image ([-1, 1], as the network sees them). Per pixel, the mean absolute
/// difference over the colour channels on the [0, 1] scale, times `gain`, clamped to [0, 1]
/// and shown with a black -> red -> yellow -> white ramp (returned in [-1, 1] like any
/// io::Image). gain 4 makes an error of 0.25 (about 12 dB locally) white. Throws when the sizes
/// differ.
io::Image errorMap(const io::Image& render, const io::Image& truth, double gain = 4.0);

/// The images left to right with `gap` white pixels between them; all must have the
/// same size.
io::Image sideBySide(const std::vector<const io::Image*>& images, int gap = 4);

} // namespace simpli::metrics
