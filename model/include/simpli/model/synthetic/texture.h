#pragma once
// Procedural surface textures for the synthetic scenes, evaluated at a hit point's surface
// coordinates (scene units along the surface). Every pattern carries fractal detail noise, so
// that no surface is texture-less (a matching-based method needs something to match) and the
// views show the parallax of the texture, not only of the silhouettes. Photo textures
// (Pattern::Photo) map a photograph (photos.h) onto the surface instead, with a random crop,
// scale, rotation, mirror and colour jitter; the sky (Pattern::Sky) is a smooth gradient with
// faint clouds, evaluated on ray directions rather than surface points.
#include "simpli/model/synthetic/random.h"

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <vector>

namespace simpli::synthetic {

enum class Pattern {
  Noise,    ///< fractal value noise between two colours
  Stripes,  ///< soft-edged parallel stripes
  Checker,  ///< hard-edged checkerboard (anti-aliased by the renderer's samples)
  Gradient, ///< slow triangle-wave ramp between two colours
  Photo,    ///< a photograph (Texture::photo), see PhotoMapping
  Sky,      ///< st = (azimuth, elevation) in radians: colourB at the horizon -> colourA above
};

struct Photo;

/// How a photo texture maps surface coordinates to photo pixels and adjusts the colours:
/// p = offset + scale * Rot(angle) * (mirror ? (-s, t) : (s, t)), sampled bilinearly with
/// mirrored repetition (Photo::sample); then per channel v = luma + saturation * (v - luma)
/// (luma of the photo pixel), v = 0.5 + contrast * (v - 0.5), v = v * gain + brightness,
/// clamped to [0, 1].
struct PhotoMapping {
  double scale = 1.0; ///< photo pixels per scene unit along the surface
  Eigen::Vector2d offset = Eigen::Vector2d::Zero(); ///< photo pixel at st = (0, 0)
  bool mirror = false;
  Eigen::Vector3d gain = Eigen::Vector3d::Ones();
  double saturation = 1.0, contrast = 1.0, brightness = 0.0;
};

const char* toString(Pattern pattern);

struct Texture {
  Pattern pattern = Pattern::Noise;
  Eigen::Vector3d colourA{0.2, 0.2, 0.2}; ///< RGB in [0, 1]
  Eigen::Vector3d colourB{0.8, 0.8, 0.8};
  double frequency = 1.0; ///< pattern cycles per scene unit along the surface
  double angle = 0.0;     ///< orientation (radians) of stripes, checker and gradient
  double detail = 0.25;   ///< relative amplitude of the detail noise (0 = none)
  uint64_t seed = 0;      ///< noise lattice seed
  std::shared_ptr<const Photo> photo; ///< Pattern::Photo: the photograph (shared, read-only)
  PhotoMapping mapping;               ///< Pattern::Photo (angle above is its rotation)

  /// RGB in [0, 1] at surface coordinates st. Throws simpli::Error for Pattern::Photo
  /// without a photo.
  Eigen::Vector3d evaluate(const Eigen::Vector2d& st) const;
};

/// Value noise in [0, 1] on the integer lattice (hashed corner values, quintic blending).
double valueNoise(double x, double y, uint64_t seed);

/// Fractal sum of `octaves` value-noise octaves (frequency x2, amplitude x0.5 each), in [0, 1].
double fractalNoise(double x, double y, uint64_t seed, int octaves);

/// A random texture whose pattern features are about `minPixels` .. `maxPixels` wide for a
/// surface where one pixel covers `unitsPerPixel` scene units.
Texture randomTexture(Random& rng, double unitsPerPixel, double minPixels = 8,
                      double maxPixels = 40);

/// A photo texture of a photo drawn from `photos` (non-empty): a random crop (offset), a
/// log-uniform zoom of `minZoom` .. `maxZoom` photo pixels per image pixel for a surface where
/// one pixel covers `unitsPerPixel` scene units, a rotation (`upright`: within +-12 degrees of
/// the photo's own orientation, else any), a mirror with probability 1/2 and colour jitter.
Texture randomPhotoTexture(Random& rng, const std::vector<std::shared_ptr<const Photo>>& photos,
                           double unitsPerPixel, bool upright, double minZoom = 0.5,
                           double maxZoom = 2.5);

/// A random sky: clear (blue), overcast (grey-white) or dusk (warm horizon), with clouds of
/// random amount.
Texture randomSkyTexture(Random& rng);

/// HSV (hue in [0, 1), saturation, value in [0, 1]) to RGB.
Eigen::Vector3d hsvToRgb(double hue, double saturation, double value);

} // namespace simpli::synthetic
