#pragma once
// The perceptual loss of the reference (spec §8.1): torchvision's VGG-19
// `features` without batch norm, every max-pool replaced by a 2x2 average pool, input mapped
// from [-1, 1] with mean 2 mu - 1 and std 2 sigma (mu, sigma = ImageNet statistics), features
// taken after relu1_2, relu2_2, relu3_4, relu4_4, relu5_4 (the outputs of features[:k] for
// k = 4, 9, 18, 27, 36), and per level the masked L1 of ops_loss.h with the mask (the rendered
// opacity) bilinearly resized to the level, weighted 1, 1, 2, 3, 40 and summed.
//
// Weights: a safetensors file with torchvision's key names features.N.weight / features.N.bias
// for the 16 convolutions (N = 0, 2, 5, 7, 10, 12, 14, 16, 19, 21, 23, 25, 28, 30, 32, 34),
// F32 or F64; other keys (e.g. the classifier) are ignored. Channel widths are read from the
// file (3 -> 64 -> ... -> 512 for the real network; smaller widths are accepted, for tests), but
// they must chain: every conv is 3x3 and takes the previous conv's output channels.
#include "simpli/ocl/tensor.h"

#include <array>
#include <string>
#include <vector>

namespace simpli::training {

class Vgg19Features {
public:
  /// Feature indices and level weights of the reference.
  static constexpr std::array<int, 5> kFeatureIndices{4, 9, 18, 27, 36};
  static constexpr std::array<double, 5> kLevelWeights{1, 1, 2, 3, 40};
  /// The torchvision indices of the 16 convolutions of VGG-19's features.
  static const std::array<int, 16>& convIndices();

  Vgg19Features() = default;
  /// Loads the convolutions from `path` in `dtype`. Throws simpli::Error naming the file and
  /// the keys for missing keys (all of them are listed), a wrong rank/kernel/channel count, or
  /// an unsupported dtype.
  Vgg19Features(const std::string& path, ocl::Dtype dtype);
  /// The same checks from the file's header alone, without loading anything.
  static void check(const std::string& path);

  bool loaded() const { return !weights_.empty(); }
  const std::string& path() const { return path_; }
  /// Output channels of conv i (0..15).
  int64_t channels(int conv) const { return weights_.at(size_t(conv)).size(0); }

  /// The normalised input: (x - (2 mu - 1)) / (2 sigma) per channel; x [N, 3, H, W].
  ocl::Tensor normalise(const ocl::Tensor& x) const;
  /// The five feature maps for x [N, 3, H, W] in [-1, 1] (H, W divisible by 16).
  std::vector<ocl::Tensor> features(const ocl::Tensor& x) const;

private:
  std::string path_;
  std::vector<ocl::Tensor> weights_, biases_;
};

/// sum_l w_l * maskedL1(F_l(pred), F_l(target), resize_bilinear(mask, H_l, W_l)).
/// pred, target [N, 3, H, W] in [-1, 1], mask [N, 1, H, W]. The target's features carry no
/// gradient; pred and mask do.
ocl::Tensor perceptualLoss(const Vgg19Features& vgg, const ocl::Tensor& pred,
                           const ocl::Tensor& target, const ocl::Tensor& mask);

} // namespace simpli::training
