#pragma once
// The named parameters of a SIMPLI network. Names are the reference implementation's
// state-dict keys (spec §5), e.g. "features_extractor.conv1a.conv.weight", so a
// converted official checkpoint loads by name. Every parameter is a leaf tensor that requires
// gradients; modules keep handles to these tensors, and loading writes into them in place, so
// the handles stay valid.
#include "simpli/ocl/tensor.h"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace simpli::io {
class SafeTensorsReader;
}

namespace simpli::network {

/// How a parameter is drawn by initialise(): PyTorch's defaults for the reference's layers.
enum class InitKind {
  FanInUniform, ///< U(-1/sqrt(fanIn), 1/sqrt(fanIn)): conv / linear weights (kaiming-uniform
                ///< with a = sqrt(5)) and their biases
  Uniform01,    ///< U[0, 1): LayerNormTotal gamma
  Zeros,        ///< LayerNormTotal beta, LayerNorm bias
  Ones,         ///< LayerNorm weight
  Normal01      ///< N(0, 1): the planes deformer's anchors
};

struct ParamInit {
  InitKind kind = InitKind::Zeros;
  int64_t fanIn = 0; ///< used by FanInUniform (input channels x kernel volume)
};

/// Outcome of ParameterStore::load.
struct LoadReport {
  std::size_t loaded = 0;              ///< parameters written
  std::vector<std::string> unexpected; ///< keys of the file that name no parameter (sorted)
  bool strippedModulePrefix = false;   ///< some keys carried a leading "module."
};

/// The most parameters a network may have: 2^28 (1 GiB in float32), far above the reference's
/// 1,879,343 (4 layers); it keeps a config with huge channel counts from exhausting memory.
inline constexpr int64_t kMaxParameters = int64_t(1) << 28;

class ParameterStore {
public:
  /// Parameters are created in `dtype` (F32 for work, F64 for reference / gradient checks)
  /// and drawn with `seed` as they are added.
  explicit ParameterStore(ocl::Dtype dtype = ocl::Dtype::F32, uint64_t seed = 0);

  ocl::Dtype dtype() const { return dtype_; }

  /// Registers and initialises a parameter. Throws simpli::Error if the name is taken, empty,
  /// the shape has a non-positive dimension, or the store would exceed kMaxParameters (checked
  /// before anything is allocated).
  ocl::Tensor add(const std::string& name, const ocl::Shape& shape, ParamInit init);

  bool contains(const std::string& name) const { return index_.count(name) != 0; }
  /// Throws simpli::Error naming the key when it is unknown.
  const ocl::Tensor& get(const std::string& name) const;
  /// Names in registration order.
  const std::vector<std::string>& names() const { return names_; }
  /// The parameter tensors in registration order (for optimisers).
  std::vector<ocl::Tensor> parameters() const;
  std::map<std::string, ocl::Shape> shapes() const;
  std::size_t size() const { return names_.size(); }
  /// Total number of scalars (sum of numel), as PyTorch's sum(p.numel()).
  int64_t count() const;

  /// Redraws every parameter with PyTorch's default initialisation. Each parameter's stream
  /// depends only on (seed, name), so adding a module does not change the others' values.
  void initialise(uint64_t seed);

  /// Loads every parameter from a safetensors file (F32 or F64 tensors; a leading "module." on
  /// a key is ignored, as the reference loader does). Throws simpli::Error naming the file and
  /// the key for a missing parameter, a shape mismatch (expected vs found) or a key present
  /// both with and without the prefix; keys that name no parameter are reported, not fatal.
  /// Nothing is written unless every parameter is present with the right shape.
  LoadReport load(const std::string& path);
  LoadReport load(const io::SafeTensorsReader& reader);

  /// Writes every parameter (in the store's dtype) atomically, with optional metadata.
  void save(const std::string& path, const std::map<std::string, std::string>& metadata = {}) const;

  /// Zeroes the gradients of every parameter.
  void zeroGrad();

private:
  struct Entry {
    ocl::Tensor tensor;
    ParamInit init;
  };
  void draw(const std::string& name, Entry& entry, uint64_t seed);

  ocl::Dtype dtype_;
  uint64_t seed_;
  std::vector<std::string> names_;
  std::map<std::string, Entry> index_;
};

} // namespace simpli::network
