#pragma once
// Procedural surface textures for the synthetic scenes, evaluated at a hit point's surface
// coordinates (scene units along the surface). Every pattern carries fractal detail noise, so
// that no surface is texture-less (a matching-based method needs something to match) and the
// views show the parallax of the texture, not only of the silhouettes.
#include "simpli/model/synthetic/random.h"

#include <Eigen/Core>

#include <cstdint>

namespace simpli::synthetic {

enum class Pattern {
  Noise,    ///< fractal value noise between two colours
  Stripes,  ///< soft-edged parallel stripes
  Checker,  ///< hard-edged checkerboard (anti-aliased by the renderer's samples)
  Gradient, ///< slow triangle-wave ramp between two colours
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

  /// RGB in [0, 1] at surface coordinates st.
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

/// HSV (hue in [0, 1), saturation, value in [0, 1]) to RGB.
Eigen::Vector3d hsvToRgb(double hue, double saturation, double value);

} // namespace simpli::synthetic
