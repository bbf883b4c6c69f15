#pragma once
// The sinusoidal positional code PE_D: for a position n and channel c in [0, D),
// theta = n * 10000^(-2 floor(c / 2) / D); the code is sin(theta) for even c and cos(theta)
// for odd c. Positions are token indices (or any real positions); SIMPLI adds the code to
// token features.
#include "simpli/ocl/tensor.h"

#include <vector>

namespace simpli::ocl {

/// positions of any shape S (rank <= 5) -> S + [D]. Differentiable with respect to the
/// positions.
Tensor positionalEncoding(const Tensor& positions, int dims);
/// The code of host positions: [positions.size(), D] in `dtype`.
Tensor positionalEncoding(const std::vector<double>& positions, int dims, Dtype dtype = Dtype::F32);

} // namespace simpli::ocl
