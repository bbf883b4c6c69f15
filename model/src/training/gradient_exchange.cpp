// One buffer of gradients and scalars per data-parallel step (training/gradient_exchange.h).
#include "simpli/model/training/gradient_exchange.h"

#include "simpli/error.h"

#include <algorithm>

namespace simpli::training {

GradientExchange::GradientExchange(const std::vector<ocl::Tensor>& parameters, std::size_t scalars)
    : scalarCount_(scalars) {
  if (parameters.empty())
    fail("GradientExchange: no parameters");
  f64_ = parameters[0].dtype() == ocl::Dtype::F64;
  for (const ocl::Tensor& p : parameters) {
    if ((p.dtype() == ocl::Dtype::F64) != f64_)
      fail("GradientExchange: parameters of mixed dtypes (", parameters[0].describe(), " and ",
           p.describe(), ")");
    offsets_.push_back(gradients_);
    gradients_ += std::size_t(p.numel());
  }
  total_ = gradients_ + parameters.size() + scalarCount_;
}

template <typename T>
void GradientExchange::addTo(std::vector<T>& sum, const std::vector<ocl::Tensor>& params,
                             const std::vector<double>& scalars) {
  if (params.size() != offsets_.size() || scalars.size() != scalarCount_)
    fail("GradientExchange::add: ", params.size(), " parameters and ", scalars.size(),
         " scalars, expected ", offsets_.size(), " and ", scalarCount_);
  if (!started_)
    sum.assign(total_, T(0));
  started_ = true;
  T* counts = sum.data() + gradients_;
  for (std::size_t p = 0; p < params.size(); ++p) {
    const ocl::Tensor grad = params[p].grad();
    if (!grad.defined())
      continue;
    counts[p] += T(1);
    const std::vector<double> g = grad.toVector();
    T* out = sum.data() + offsets_[p];
    for (std::size_t i = 0; i < g.size(); ++i)
      out[i] += T(g[i]); // g holds exact copies of the gradient's T values
  }
  T* extra = counts + params.size();
  for (std::size_t i = 0; i < scalarCount_; ++i)
    extra[i] += T(scalars[i]);
}

void GradientExchange::add(const std::vector<ocl::Tensor>& parameters,
                           const std::vector<double>& scalars) {
  if (f64_)
    addTo(f64Sum_, parameters, scalars);
  else
    addTo(f32Sum_, parameters, scalars);
}

void GradientExchange::reduce(parallel::Communicator& comm) {
  if (!started_)
    fail("GradientExchange::reduce: no sample was added in this step");
  if (f64_)
    comm.allreduceSum(f64Sum_);
  else
    comm.allreduceSum(f32Sum_);
}

template <typename T>
void GradientExchange::applyFrom(const std::vector<T>& sum, const std::vector<ocl::Tensor>& params,
                                 int samples) {
  const T* counts = sum.data() + gradients_;
  std::vector<double> mean;
  for (std::size_t p = 0; p < params.size(); ++p) {
    if (counts[p] == T(0))
      continue; // no sample had a gradient: none on any rank
    const std::size_t n = std::size_t(params[p].numel());
    mean.resize(n);
    const T* s = sum.data() + offsets_[p];
    for (std::size_t i = 0; i < n; ++i)
      mean[i] = double(s[i] / T(samples)); // rounded to T as the device would hold it
    ocl::Tensor grad = params[p].grad();
    if (grad.defined()) {
      grad.copyFromHost(mean);
    } else {
      ocl::Tensor target = params[p];
      target.setGrad(ocl::Tensor::fromHost(mean, params[p].shape(), params[p].dtype()));
    }
  }
}

void GradientExchange::applyMean(const std::vector<ocl::Tensor>& parameters, int samples) {
  if (!started_)
    fail("GradientExchange::applyMean: no sample was added in this step");
  if (samples < 1)
    fail("GradientExchange::applyMean: ", samples, " samples");
  if (f64_)
    applyFrom(f64Sum_, parameters, samples);
  else
    applyFrom(f32Sum_, parameters, samples);
  started_ = false;
}

std::vector<double> GradientExchange::scalars() const {
  std::vector<double> out(scalarCount_);
  const std::size_t at = gradients_ + offsets_.size();
  for (std::size_t i = 0; i < scalarCount_; ++i)
    out[i] = f64_ ? f64Sum_.at(at + i) : double(f32Sum_.at(at + i));
  return out;
}

} // namespace simpli::training
