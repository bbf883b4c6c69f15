#pragma once
// An exponential moving average of the network's parameters (spec §8.2: the
// reference trainer keeps an EMA copy of the generator, decay_rate 0.9 per iteration, saved
// beside the plain weights; the released checkpoint is the plain generator). After each
// optimiser step: average = decay * average + (1 - decay) * parameter, in float64 on the device
// whatever the parameters' dtype, starting from the parameters' values when the run starts.
// Checkpoints store it exactly (F64), so a resumed run continues the same average.
#include "simpli/model/io/safetensors.h"
#include "simpli/model/network/parameter_store.h"

#include "simpli/ocl/tensor.h"

#include <map>
#include <string>
#include <vector>

namespace simpli::training {

class ParameterAverage {
public:
  /// Starts at the current values of `store`'s parameters. decay in (0, 1).
  ParameterAverage(const network::ParameterStore& store, double decay);

  double decay() const { return decay_; }
  /// One update from the current parameter values (same store layout as at construction).
  void update(const network::ParameterStore& store);
  /// Writes the averages into `store`'s parameters (same layout as at construction), rounded to
  /// its dtype: a network that computes with the averaged weights.
  void copyTo(network::ParameterStore& store) const;
  /// The averages by parameter name, for writing.
  std::map<std::string, io::HostTensor<double>> values() const;
  /// Replaces the averages (on resume); every parameter must be present with its shape.
  /// `source` names the file in errors.
  void setValues(const std::map<std::string, io::HostTensor<double>>& values,
                 const std::string& source);

private:
  double decay_;
  std::vector<std::string> names_;
  std::vector<ocl::Tensor> averages_; ///< F64, shaped like the parameters
};

} // namespace simpli::training
