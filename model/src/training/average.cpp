// Exponential moving average of the parameters (training/average.h).
#include "simpli/model/training/average.h"

#include "simpli/error.h"

namespace simpli::training {

ParameterAverage::ParameterAverage(const network::ParameterStore& store, double decay)
    : decay_(decay), names_(store.names()) {
  if (!(decay > 0 && decay < 1))
    fail("ParameterAverage: decay ", decay, " must be in (0, 1)");
  for (const std::string& name : names_)
    averages_.push_back(store.get(name).detach().to(ocl::Dtype::F64).clone());
}

void ParameterAverage::update(const network::ParameterStore& store) {
  if (store.names() != names_)
    fail("ParameterAverage: the parameter store changed since the average started");
  for (size_t i = 0; i < names_.size(); ++i) {
    ocl::Tensor weighted = store.get(names_[i]).detach().to(ocl::Dtype::F64).clone();
    weighted.mulInPlace(1.0 - decay_);
    averages_[i].mulInPlace(decay_);
    averages_[i].addInPlace(weighted);
  }
}

void ParameterAverage::copyTo(network::ParameterStore& store) const {
  if (store.names() != names_)
    fail("ParameterAverage: the parameter store does not match the averaged one");
  for (size_t i = 0; i < names_.size(); ++i) {
    ocl::Tensor parameter = store.get(names_[i]); // a handle: writes reach the store's buffer
    parameter.copyFromHost(averages_[i].toVector());
  }
}

std::map<std::string, io::HostTensor<double>> ParameterAverage::values() const {
  std::map<std::string, io::HostTensor<double>> out;
  for (size_t i = 0; i < names_.size(); ++i) {
    io::HostTensor<double>& t = out[names_[i]];
    t.shape = averages_[i].shape();
    t.data = averages_[i].toVector();
  }
  return out;
}

void ParameterAverage::setValues(const std::map<std::string, io::HostTensor<double>>& values,
                                 const std::string& source) {
  for (size_t i = 0; i < names_.size(); ++i) {
    auto it = values.find(names_[i]);
    if (it == values.end())
      fail(source, ": no average for parameter '", names_[i], "'");
    if (it->second.shape != averages_[i].shape())
      fail(source, ": parameter '", names_[i], "' has shape ", ocl::toString(it->second.shape),
           ", expected ", ocl::toString(averages_[i].shape()));
    averages_[i].copyFromHost(it->second.data);
  }
}

} // namespace simpli::training
