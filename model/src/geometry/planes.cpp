#include "simpli/model/geometry/planes.h"

#include "simpli/error.h"

#include <cmath>

namespace simpli::geometry {

std::vector<double> planeDepths(int count, double near, double far) {
  if (count < 1)
    fail("planeDepths: plane count ", count, " must be at least 1");
  if (!std::isfinite(near) || !std::isfinite(far) || !(near > 0) || !(far >= near))
    fail("planeDepths: depth range near = ", near, ", far = ", far,
         " must satisfy 0 < near <= far (finite)");
  // linspace(1/far, 1/near, count) evaluated like PyTorch's: the first half from the start,
  // the second half from the end, so both ends are exact.
  const double start = 1.0 / far, end = 1.0 / near;
  std::vector<double> depths(static_cast<std::size_t>(count));
  if (count == 1) {
    depths[0] = far;
    return depths;
  }
  const double step = (end - start) / (count - 1);
  for (int i = 0; i < count; ++i) {
    const double disparity = i < count / 2 ? start + i * step : end - (count - 1 - i) * step;
    depths[static_cast<std::size_t>(i)] = 1.0 / disparity;
  }
  return depths;
}

} // namespace simpli::geometry
