#pragma once
// The synthetic MLI of `simpli bench render --synthetic`, the standard display measurement.
#include "simpli/model/mli/mli.h"

namespace simpli::app {

/// A forward-facing scene as SIMPLI's layers look, W x H texels, 4 layers (layer 0 farthest):
/// an opaque background receding towards the top (a slanted surface with fine texture),
/// rolling hills over part of the image, three spheres with soft edges, and sparse foliage near
/// the camera. Depths are ordered per texel; the camera has square pixels (fy = fx W / H).
mli::MLI syntheticMLI(int W, int H);

} // namespace simpli::app
