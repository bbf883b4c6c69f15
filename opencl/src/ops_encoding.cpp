#include "simpli/ocl/ops_encoding.h"

#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/launch.h"

#include <cmath>

namespace simpli::ocl {

Tensor positionalEncoding(const Tensor& positions, int dims) {
  if (!positions.defined())
    fail("positionalEncoding: undefined positions");
  if (dims < 1)
    fail("positionalEncoding: dimension ", dims, " for positions ", positions.describe(),
         " must be positive");
  if (positions.dim() >= kMaxDims)
    fail("positionalEncoding: positions ", positions.describe(), " have more than ", kMaxDims - 1,
         " dimensions");
  if (positions.numel() == 0)
    fail("positionalEncoding: positions ", positions.describe(), " are empty");
  Shape outShape = positions.shape();
  outShape.push_back(dims);
  checkedInt(numelOf(outShape), "positionalEncoding");
  const int n = static_cast<int>(positions.numel());
  std::vector<double> frequencies(static_cast<std::size_t>(dims));
  for (int c = 0; c < dims; ++c)
    frequencies[c] = std::pow(10000.0, -2.0 * (c / 2) / dims);
  Tensor freq = Tensor::fromHost(frequencies, {dims}, positions.dtype());
  Tensor out = Tensor::empty(outShape, positions.dtype());
  Launch("encoding", "positional_encoding_forward", positions.dtype())
      .arg(n)
      .arg(dims)
      .arg(freq)
      .arg(positions)
      .arg(out)
      .run2(dims, n);
  if (!needsGrad({positions}))
    return out;
  return record("positionalEncoding", out, {positions},
                [pd = positions.detach(), freq, n, dims](const Tensor& g) {
                  Tensor gp = Tensor::empty(pd.shape(), g.dtype());
                  Launch("encoding", "positional_encoding_backward", g.dtype())
                      .arg(n)
                      .arg(dims)
                      .arg(freq)
                      .arg(pd)
                      .arg(g)
                      .arg(gp)
                      .run(n);
                  return std::vector<Tensor>{gp};
                });
}

Tensor positionalEncoding(const std::vector<double>& positions, int dims, Dtype dtype) {
  if (positions.empty())
    fail("positionalEncoding: no positions (dimension ", dims, ")");
  return positionalEncoding(
      Tensor::fromHost(positions, {static_cast<int64_t>(positions.size())}, dtype), dims);
}

} // namespace simpli::ocl
