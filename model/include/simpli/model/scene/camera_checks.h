#pragma once
// What a camera read from a file must satisfy (validateCamera: invalid cameras are errors), and
// what makes a valid camera give a poor result (cameraConcerns: readers warn about them). One
// place for the rules of every reader: the scene formats (scene/readers.h) and the MLI's
// meta.json (mli/files.h).
#include "simpli/model/scene/camera.h"

#include <string>
#include <vector>

namespace simpli::scene {

/// Relative focal lengths (fx = focal / W, fy = focal / H) a camera may have at all. Outside,
/// a pinhole camera means nothing: 1e-3 is a field of view of 179.9 degrees, 1e3 one of 0.06
/// degrees, and beyond them the float32 kernels see every pixel at the principal point (an MLI
/// with fx = 1e-30 renders black) or every world point at infinity.
inline constexpr double kMinRelativeFocal = 1e-3;
inline constexpr double kMaxRelativeFocal = 1e3;

/// Relative focal lengths for which the network gives good results: fields of view from 157
/// degrees (0.1) down to 2.9 degrees (20), beyond every lens of the training data. Outside
/// (but valid), cameraConcerns names the value; focal lengths in pixels written where fractions
/// of the image size belong are the usual cause.
inline constexpr double kGoodRelativeFocalMin = 0.1;
inline constexpr double kGoodRelativeFocalMax = 20;

/// Throws simpli::Error "<context>: ..." naming the field and the value unless R and t are
/// finite, R is a rotation (max |R^T R - I| <= rotationTolerance, det R > 0), the intrinsics
/// are finite and fx, fy lie in [kMinRelativeFocal, kMaxRelativeFocal].
void validateCamera(const Camera& camera, const std::string& context, double rotationTolerance);

/// Why a valid camera will give a poor result.
struct CameraConcern {
  std::string field; ///< "fx", "fy", "cx", "cy"
  double value = 0;
  std::string why; ///< one sentence, no trailing period
};

/// The concerns about a camera that validateCamera accepts: a focal length outside
/// [kGoodRelativeFocalMin, kGoodRelativeFocalMax], a principal point outside the image
/// ([0, 1] relative). Empty when there are none.
std::vector<CameraConcern> cameraConcerns(const Camera& camera);

} // namespace simpli::scene
