// Procedural textures (see synthetic/texture.h).
#include "simpli/model/synthetic/texture.h"

#include "simpli/error.h"
#include "simpli/model/synthetic/photos.h"

#include <algorithm>
#include <cmath>

namespace simpli::synthetic {

const char* toString(Pattern pattern) {
  switch (pattern) {
  case Pattern::Noise:
    return "noise";
  case Pattern::Stripes:
    return "stripes";
  case Pattern::Checker:
    return "checker";
  case Pattern::Gradient:
    return "gradient";
  case Pattern::Photo:
    return "photo";
  case Pattern::Sky:
    return "sky";
  }
  return "?";
}

namespace {

double latticeValue(int64_t ix, int64_t iy, uint64_t seed) {
  return unitFromBits(mix64(mix64(seed ^ uint64_t(ix)) + uint64_t(iy) * 0xD1B54A32D192ED03ull));
}

double quintic(double t) {
  return t * t * t * (t * (t * 6 - 15) + 10);
}

double clamp01(double v) {
  return std::min(1.0, std::max(0.0, v));
}

} // namespace

double valueNoise(double x, double y, uint64_t seed) {
  const double fx = std::floor(x), fy = std::floor(y);
  const int64_t ix = int64_t(fx), iy = int64_t(fy);
  const double tx = quintic(x - fx), ty = quintic(y - fy);
  const double v00 = latticeValue(ix, iy, seed), v10 = latticeValue(ix + 1, iy, seed);
  const double v01 = latticeValue(ix, iy + 1, seed), v11 = latticeValue(ix + 1, iy + 1, seed);
  const double a = v00 + (v10 - v00) * tx, b = v01 + (v11 - v01) * tx;
  return a + (b - a) * ty;
}

double fractalNoise(double x, double y, uint64_t seed, int octaves) {
  double sum = 0, norm = 0, amplitude = 1, scale = 1;
  for (int o = 0; o < octaves; ++o) {
    // Each octave on its own lattice, rotated by ~37 degrees and shifted, so that lattice
    // axes and corners do not line up across octaves (visible grid artefacts otherwise).
    const double c = 0.8, s = 0.6;
    const double rx = c * x - s * y, ry = s * x + c * y;
    x = rx + 17.31;
    y = ry - 9.73;
    sum += amplitude * valueNoise(x * scale, y * scale, deriveSeed(seed, uint64_t(o)));
    norm += amplitude;
    amplitude *= 0.5;
    scale *= 2.0;
  }
  return norm > 0 ? sum / norm : 0.5;
}

namespace {

Eigen::Vector3d evaluatePhoto(const Texture& t, const Eigen::Vector2d& st) {
  if (!t.photo)
    fail("photo texture without a photo");
  const PhotoMapping& m = t.mapping;
  const double s = m.mirror ? -st.x() : st.x(), u = st.y();
  const double ca = std::cos(t.angle), sa = std::sin(t.angle);
  const double px = m.offset.x() + m.scale * (ca * s - sa * u);
  const double py = m.offset.y() + m.scale * (sa * s + ca * u);
  Eigen::Vector3d rgb = t.photo->sample(px, py);
  const double luma = 0.299 * rgb[0] + 0.587 * rgb[1] + 0.114 * rgb[2];
  for (int c = 0; c < 3; ++c) {
    double v = luma + m.saturation * (rgb[c] - luma);
    v = 0.5 + m.contrast * (v - 0.5);
    rgb[c] = clamp01(v * m.gain[c] + m.brightness);
  }
  return rgb;
}

Eigen::Vector3d evaluateSky(const Texture& t, const Eigen::Vector2d& st) {
  // Elevation (radians, up positive) -> 0 at the horizon .. 1 high up; a little haze below.
  const double e = st.y();
  const double p = e > 0 ? 1.0 - std::exp(-3.0 * e) : 0.0;
  Eigen::Vector3d rgb = t.colourB + (t.colourA - t.colourB) * p;
  if (e < 0)
    rgb *= std::max(0.6, 1.0 + 0.8 * e);
  if (t.detail > 0) {
    // Clouds: fractal noise flattened towards the horizon, soft-thresholded.
    const double flat = 1.0 / std::max(0.15, std::abs(e) + 0.15);
    const double c =
        fractalNoise(t.frequency * st.x(), t.frequency * flat * st.y() * 0.4, t.seed, 5);
    const double mask = clamp01((c - 0.48) / 0.22);
    const Eigen::Vector3d cloud = Eigen::Vector3d::Constant(0.93) * (0.85 + 0.15 * c);
    rgb += (cloud - rgb) * (t.detail * mask);
  }
  for (int c = 0; c < 3; ++c)
    rgb[c] = clamp01(rgb[c]);
  return rgb;
}

} // namespace

Eigen::Vector3d Texture::evaluate(const Eigen::Vector2d& st) const {
  if (pattern == Pattern::Photo)
    return evaluatePhoto(*this, st);
  if (pattern == Pattern::Sky)
    return evaluateSky(*this, st);
  const double ca = std::cos(angle), sa = std::sin(angle);
  const double a = (ca * st.x() + sa * st.y()) * frequency;  // along the pattern direction
  const double b = (-sa * st.x() + ca * st.y()) * frequency; // across it
  double p = 0.5;
  switch (pattern) {
  case Pattern::Noise:
    // Fractal noise concentrates around 0.5; stretch its contrast to use both colours.
    p = clamp01(0.5 + 2.2 * (fractalNoise(a, b, seed, 4) - 0.5));
    break;
  case Pattern::Stripes:
    p = clamp01(0.5 + 0.8 * std::sin(2.0 * M_PI * a));
    break;
  case Pattern::Checker:
    p = double((int64_t(std::floor(a)) + int64_t(std::floor(b))) & 1);
    break;
  case Pattern::Gradient: {
    const double w = 0.25 * a; // a quarter of the frequency: a slow ramp
    p = std::abs(2.0 * (w - std::floor(w)) - 1.0);
    break;
  }
  case Pattern::Photo:
  case Pattern::Sky:
    break; // handled above
  }
  Eigen::Vector3d rgb = colourA + (colourB - colourA) * p;
  if (detail > 0) {
    // Finer than the pattern, on its own lattice.
    const double d =
        fractalNoise(3.1 * st.x() * frequency, 3.1 * st.y() * frequency, deriveSeed(seed, 1000), 3);
    rgb *= 1.0 + detail * (2.0 * d - 1.0);
  }
  for (int c = 0; c < 3; ++c)
    rgb[c] = clamp01(rgb[c]);
  return rgb;
}

Eigen::Vector3d hsvToRgb(double hue, double saturation, double value) {
  const double h = 6.0 * (hue - std::floor(hue));
  const int sector = std::min(5, int(h));
  const double f = h - sector;
  const double p = value * (1 - saturation), q = value * (1 - saturation * f),
               t = value * (1 - saturation * (1 - f));
  switch (sector) {
  case 0:
    return {value, t, p};
  case 1:
    return {q, value, p};
  case 2:
    return {p, value, t};
  case 3:
    return {p, q, value};
  case 4:
    return {t, p, value};
  default:
    return {value, p, q};
  }
}

Texture randomTexture(Random& rng, double unitsPerPixel, double minPixels, double maxPixels) {
  Texture tex;
  tex.pattern = Pattern(rng.uniformInt(0, 3));
  // Two colours of related hue with clearly different brightness, so that the pattern shows
  // in every channel.
  const double hue = rng.uniform();
  const double hueB = hue + rng.uniform(-0.25, 0.25);
  tex.colourA = hsvToRgb(hue, rng.uniform(0.3, 0.9), rng.uniform(0.15, 0.45));
  tex.colourB = hsvToRgb(hueB, rng.uniform(0.2, 0.8), rng.uniform(0.6, 0.95));
  if (rng.chance(0.5))
    std::swap(tex.colourA, tex.colourB);
  // Log-uniform feature size in pixels; one pattern cycle spans two features.
  const double pixels = minPixels * std::pow(maxPixels / minPixels, rng.uniform());
  tex.frequency = 1.0 / (2.0 * pixels * unitsPerPixel);
  tex.angle = rng.uniform(0.0, M_PI);
  tex.detail = rng.uniform(0.15, 0.35);
  tex.seed = rng.bits();
  return tex;
}

Texture randomPhotoTexture(Random& rng, const std::vector<std::shared_ptr<const Photo>>& photos,
                           double unitsPerPixel, bool upright, double minZoom, double maxZoom) {
  if (photos.empty())
    fail("randomPhotoTexture: no photos");
  if (!(unitsPerPixel > 0) || !(minZoom > 0) || !(maxZoom >= minZoom))
    fail("randomPhotoTexture: units per pixel ", unitsPerPixel, ", zoom ", minZoom, " .. ",
         maxZoom);
  Texture tex;
  tex.pattern = Pattern::Photo;
  tex.detail = 0;
  tex.photo = photos[size_t(rng.uniformInt(0, int(photos.size()) - 1))];
  PhotoMapping& m = tex.mapping;
  const double zoom = minZoom * std::pow(maxZoom / minZoom, rng.uniform());
  m.scale = zoom / unitsPerPixel;
  tex.angle = upright ? rng.uniform(-12.0, 12.0) * M_PI / 180.0 : rng.uniform(0.0, 2.0 * M_PI);
  m.offset = Eigen::Vector2d(rng.uniform(0.0, double(tex.photo->width)),
                             rng.uniform(0.0, double(tex.photo->height)));
  m.mirror = rng.chance(0.5);
  for (int c = 0; c < 3; ++c)
    m.gain[c] = std::min(1.25, std::max(0.8, std::exp(0.08 * rng.normal())));
  m.saturation = rng.chance(0.05) ? 0.0 : rng.uniform(0.6, 1.3);
  m.contrast = rng.uniform(0.75, 1.25);
  m.brightness = rng.uniform(-0.08, 0.08);
  tex.seed = rng.bits();
  return tex;
}

Texture randomSkyTexture(Random& rng) {
  Texture tex;
  tex.pattern = Pattern::Sky;
  const double kind = rng.uniform();
  if (kind < 0.5) { // clear: deep blue above, pale blue at the horizon
    const double hue = rng.uniform(0.55, 0.64);
    tex.colourA = hsvToRgb(hue, rng.uniform(0.45, 0.8), rng.uniform(0.55, 0.85));
    tex.colourB =
        hsvToRgb(hue + rng.uniform(-0.03, 0.03), rng.uniform(0.1, 0.35), rng.uniform(0.8, 0.97));
  } else if (kind < 0.8) { // overcast
    const double v = rng.uniform(0.55, 0.9);
    tex.colourA = hsvToRgb(rng.uniform(0.55, 0.65), rng.uniform(0.0, 0.12), v);
    tex.colourB = hsvToRgb(rng.uniform(0.55, 0.65), rng.uniform(0.0, 0.08),
                           std::min(0.98, v + rng.uniform(0.0, 0.12)));
  } else { // dusk: blue-violet above, warm horizon
    tex.colourA = hsvToRgb(rng.uniform(0.6, 0.75), rng.uniform(0.3, 0.6), rng.uniform(0.35, 0.7));
    tex.colourB = hsvToRgb(rng.uniform(0.02, 0.12), rng.uniform(0.3, 0.7), rng.uniform(0.75, 0.98));
  }
  tex.frequency = rng.uniform(1.5, 5.0); // cloud cycles per radian
  tex.detail = rng.chance(0.3) ? 0.0 : rng.uniform(0.1, 0.8);
  tex.seed = rng.bits();
  return tex;
}

} // namespace simpli::synthetic
