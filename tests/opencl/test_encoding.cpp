// The sinusoidal positional code through the harness (odd and size-1 shapes, odd D), its
// host-vector form at SIMPLI's settings, and bad use.
#include "op_harness.h"
#include "test_support.h"

#include "simpli/error.h"
#include "simpli/ocl/ops_encoding.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace simpli;
using namespace simpli::test;
using ocl::Dtype;

namespace {

double code(double n, int c, int d) {
  const double theta = n * std::pow(10000.0, -2.0 * std::floor(c / 2.0) / d);
  return c % 2 == 0 ? std::sin(theta) : std::cos(theta);
}

std::vector<double> codeRef(const std::vector<double>& pos, int d) {
  std::vector<double> out;
  for (double n : pos)
    for (int c = 0; c < d; ++c)
      out.push_back(code(n, c, d));
  return out;
}

} // namespace

TEST(Encoding, PositionalEncodingAgainstReference) {
  struct Case {
    Shape shape;
    int d;
  };
  const Case cases[] = {{{7}, 12}, {{3, 5}, 16}, {{1}, 1}, {{4, 1}, 3}, {{2, 1, 3}, 5}};
  for (const auto& k : cases) {
    OpCase c;
    c.name = "positionalEncoding " + ocl::toString(k.shape) + " D=" + std::to_string(k.d);
    c.inputShapes = {k.shape};
    c.low = 0.0; // SIMPLI's positions: plane indices 0..40
    c.high = 40.0;
    c.device = [k](const std::vector<ocl::Tensor>& in) {
      ocl::Tensor out = ocl::positionalEncoding(in[0], k.d);
      Shape expected = k.shape;
      expected.push_back(k.d);
      EXPECT_EQ(out.shape(), expected);
      return out;
    };
    c.reference = [k](const HostInputs& in) { return codeRef(in[0], k.d); };
    checkOp(c);
  }
}

TEST(Encoding, HostPositionsAtSimpliSettings) {
  for (int d : {12, 16}) {
    std::vector<double> pos(41);
    for (int p = 0; p <= 40; ++p)
      pos[p] = p;
    const auto ref = codeRef(pos, d);
    for (Dtype dtype : {Dtype::F32, Dtype::F64}) {
      ocl::Tensor t = ocl::positionalEncoding(pos, d, dtype);
      EXPECT_EQ(t.shape(), (Shape{41, d}));
      EXPECT_EQ(t.dtype(), dtype);
      EXPECT_LE(relativeError(t.toVector(), ref), dtype == Dtype::F32 ? 1e-5 : 1e-13) << d;
    }
    // Channel 0 at position 1 is sin(1); channel 1 at position 0 is cos(0) = 1.
    const auto v = ocl::positionalEncoding(pos, d, Dtype::F64).toVector();
    EXPECT_NEAR(v[d], std::sin(1.0), 1e-15);
    EXPECT_EQ(v[1], 1.0);
  }
}

TEST(Encoding, BadUseThrowsNamingOpAndShapes) {
  expectError([] { ocl::positionalEncoding(ocl::Tensor::zeros({3}), 0); },
              {"positionalEncoding", "0", "[3]"});
  expectError([] { ocl::positionalEncoding(ocl::Tensor::zeros({0}), 4); },
              {"positionalEncoding", "[0]"});
  expectError(
      [] {
        ocl::positionalEncoding(ocl::Tensor::zeros({1, 1, 1, 1, 1, 1}), 4);
      },
      {"positionalEncoding", "[1, 1, 1, 1, 1, 1]"});
  expectError([] { ocl::positionalEncoding(std::vector<double>{}, 4); }, {"positionalEncoding"});
  expectError([] { ocl::positionalEncoding(ocl::Tensor(), 4); }, {"positionalEncoding"});
}
