#pragma once
// The fronto-parallel planes of SIMPLI's MPIs (spec §3 step 2, §6.2).
#include <vector>

namespace simpli::geometry {

/// `count` plane depths uniform in disparity between 1/far and 1/near, as the reference's
/// 1 / linspace(1/far, 1/near, count): index 0 is the farthest plane (depth `far`), index
/// count - 1 the nearest (`near`). Depths are reference-camera z (not distances).
/// count == 1 gives {far} (linspace's single sample is its start). Throws simpli::Error unless
/// count >= 1 and 0 < near <= far are finite.
std::vector<double> planeDepths(int count = 41, double near = 1.0, double far = 100.0);

} // namespace simpli::geometry
