// The data-parallel step's one buffer: two samples' gradients and scalars summed and averaged as
// the all-reduce over two ranks would, parameters without a gradient, f64, bad layouts.
#include "support/expect_error.h"

#include "simpli/model/parallel/communicator.h"
#include "simpli/model/training/gradient_exchange.h"

#include <gtest/gtest.h>

namespace simpli::training {
namespace {

ocl::Tensor parameter(const ocl::Shape& shape, ocl::Dtype dtype) {
  ocl::Tensor p = ocl::Tensor::zeros(shape, dtype);
  p.setRequiresGrad(true);
  return p;
}

void setGrad(ocl::Tensor p, const std::vector<double>& g) {
  p.setGrad(ocl::Tensor::fromHost(g, p.shape(), p.dtype()));
}

TEST(TrainGradientExchange, MeanOfTwoSamplesAndTheirScalars) {
  const ocl::Dtype f32 = ocl::Dtype::F32;
  std::vector<ocl::Tensor> params{parameter({3}, f32), parameter({2, 2}, f32), parameter({2}, f32),
                                  parameter({1}, f32)};
  GradientExchange ex(params, 2);
  EXPECT_EQ(ex.size(), 3u + 4u + 2u + 1u + 4u + 2u); // gradients, one count each, scalars
  EXPECT_EQ(ex.bytes(), ex.size() * 4);
  // Sample A: gradients for parameters 0 and 1; parameter 2 only in sample B, 3 in neither.
  setGrad(params[0], {1.0, 2.0, 0.1});
  setGrad(params[1], {-1.0, 0.5, 3.0, 1e-8});
  ex.add(params, {0.25, 1.0});
  setGrad(params[0], {3.0, -2.0, 0.2});
  setGrad(params[1], {1.0, 0.5, -3.0, 3e-8});
  setGrad(params[2], {4.0, 6.0});
  ex.add(params, {0.75, 0.0});
  params[2].setGrad({}); // on this "rank" the parameter has none again: the count decides
  ex.reduce(parallel::world());
  EXPECT_EQ(ex.scalars(), (std::vector<double>{1.0, 1.0}));
  ex.applyMean(params, 2);
  auto f = [](double v) { return double(float(v)); };
  EXPECT_EQ(params[0].grad().toVector(), (std::vector<double>{2.0, 0.0, f((0.1f + 0.2f) / 2.0f)}));
  EXPECT_EQ(params[1].grad().toVector(),
            (std::vector<double>{0.0, 0.5, 0.0, f((1e-8f + 3e-8f) / 2.0f)}));
  ASSERT_TRUE(params[2].grad().defined());
  EXPECT_EQ(params[2].grad().toVector(), (std::vector<double>{2.0, 3.0}));
  EXPECT_FALSE(params[3].grad().defined()) << "no sample had a gradient: none is made";
  // The next step starts from zero.
  ex.add(params, {5.0, 0.0});
  ex.reduce(parallel::world());
  EXPECT_EQ(ex.scalars(), (std::vector<double>{5.0, 0.0}));
  ex.applyMean(params, 1);
  EXPECT_EQ(params[2].grad().toVector(), (std::vector<double>{2.0, 3.0}));
}

TEST(TrainGradientExchange, DoublesForF64Runs) {
  std::vector<ocl::Tensor> params{parameter({2}, ocl::Dtype::F64)};
  GradientExchange ex(params, 1);
  EXPECT_EQ(ex.bytes(), ex.size() * 8);
  setGrad(params[0], {0.1, 0.5});
  ex.add(params, {0.1});
  setGrad(params[0], {0.2, 1.5});
  ex.add(params, {0.2});
  ex.reduce(parallel::world());
  EXPECT_EQ(ex.scalars(), std::vector<double>{0.1 + 0.2}); // double sums, not float ones
  ex.applyMean(params, 2);
  EXPECT_EQ(params[0].grad().toVector(), (std::vector<double>{(0.1 + 0.2) / 2, 1.0}));
}

TEST(TrainGradientExchange, BadLayoutsAreNamed) {
  std::vector<ocl::Tensor> mixed{parameter({2}, ocl::Dtype::F32), parameter({2}, ocl::Dtype::F64)};
  test::expectError([&] { GradientExchange ex(mixed, 0); }, {"mixed dtypes", "f64[2]"});
  test::expectError([] { GradientExchange ex({}, 0); }, {"no parameters"});
  std::vector<ocl::Tensor> params{parameter({2}, ocl::Dtype::F32)};
  GradientExchange ex(params, 1);
  test::expectError([&] { ex.add(params, {}); }, {"0 scalars", "expected 1 and 1"});
  test::expectError([&] { ex.reduce(parallel::world()); }, {"no sample was added"});
  test::expectError([&] { ex.applyMean(params, 1); }, {"no sample was added"});
  ex.add(params, {1.0});
  test::expectError([&] { ex.applyMean(params, 0); }, {"0 samples"});
}

} // namespace
} // namespace simpli::training
