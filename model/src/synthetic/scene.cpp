// Random forward-facing scenes (see synthetic/scene.h); the objects style and what both styles
// share. The world style: scene_world.cpp.
#include "simpli/model/synthetic/scene.h"

#include "simpli/error.h"
#include "simpli/model/synthetic/camera_path.h"
#include "simpli/model/synthetic/photos.h"

#include "synthetic/scene_internal.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace simpli::synthetic {

namespace detail {

Eigen::Matrix3d rotation(double yaw, double pitch, double roll) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()))
      .toRotationMatrix();
}

CameraPathParams pathParams(const SyntheticSceneParams& p) {
  CameraPathParams c;
  c.views = p.views;
  c.width = p.width;
  c.height = p.height;
  c.fx = p.fx();
  c.fy = p.fy();
  c.maxOffset = p.translation * p.nearDepth;
  c.maxRotationDegrees = p.rotationDegrees;
  return c;
}

double logUniform(Random& rng, double lo, double hi) {
  return hi > lo ? lo * std::pow(hi / lo, rng.uniform()) : lo;
}

void maybePhotoTexture(const SyntheticSceneParams& p, uint64_t index, double unitsPerPixel,
                       bool upright, Shape& shape) {
  if (!p.usesPhotos())
    return;
  Random rng(deriveSeed(deriveSeed(p.seed, kPhotoTextures), index));
  if (!rng.chance(p.photoProbability))
    return;
  shape.texture = randomPhotoTexture(rng, allPhotos(p), unitsPerPixel, upright);
}

std::vector<std::shared_ptr<const Photo>> allPhotos(const SyntheticSceneParams& p) {
  std::vector<std::shared_ptr<const Photo>> photos;
  for (size_t i = 0; i < p.photos->size(); ++i)
    photos.push_back(p.photos->photo(i));
  return photos;
}

Eigen::Vector3d randomLightDirection(uint64_t seed) {
  Random lightRng(deriveSeed(seed, kLight));
  // From above (-y) and from the cameras' side (-z), as if lit over the photographer's shoulder.
  return Eigen::Vector3d(lightRng.uniform(-0.6, 0.6), lightRng.uniform(-1.0, -0.3), -1.0)
      .normalized();
}

Shape makeObjectShape(ShapeRole role, double scale, double pixel, Random& rng) {
  Shape s;
  s.role = role;
  switch (role) {
  case ShapeRole::FrontoPlane:
    s.kind = ShapeKind::Rectangle;
    s.size = Eigen::Vector3d(scale * rng.uniform(0.6, 1.4), scale * rng.uniform(0.6, 1.4), 0);
    break;
  case ShapeRole::SlantedPlane:
    s.kind = ShapeKind::Rectangle;
    s.axes = rotation(rng.sign() * rng.uniform(25, 60) * kDeg, rng.uniform(-30, 30) * kDeg,
                      rng.uniform(-20, 20) * kDeg);
    s.size = Eigen::Vector3d(scale * rng.uniform(0.6, 1.4), scale * rng.uniform(0.6, 1.4), 0);
    break;
  case ShapeRole::Box:
    s.kind = ShapeKind::Box;
    s.axes = rotation(rng.uniform(-45, 45) * kDeg, rng.uniform(-25, 25) * kDeg,
                      rng.uniform(-15, 15) * kDeg);
    s.size = scale *
             Eigen::Vector3d(rng.uniform(0.4, 1.0), rng.uniform(0.4, 1.0), rng.uniform(0.3, 1.0));
    break;
  case ShapeRole::Sphere:
    s.kind = ShapeKind::Sphere;
    // Polar axis up (-y), longitude seam away from the cameras (+z).
    s.axes = frameFromAxis(-Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ());
    s.size = Eigen::Vector3d::Constant(scale * rng.uniform(0.5, 1.0));
    break;
  case ShapeRole::Pole: {
    // Nearly vertical, 2 .. 6 pixels thick, often reaching beyond the image.
    const Eigen::Vector3d axis(rng.uniform(-0.1, 0.1), 1.0, rng.uniform(-0.2, 0.2));
    s.kind = ShapeKind::Cylinder;
    s.axes = frameFromAxis(axis, Eigen::Vector3d::UnitZ());
    s.size = Eigen::Vector3d(pixel * rng.uniform(1.0, 3.0), 0, scale * rng.uniform(2.0, 5.0));
    break;
  }
  case ShapeRole::Wire: {
    // Roughly horizontal, 1.4 .. 4 pixels thick, long.
    const Eigen::Vector3d axis(1.0, rng.uniform(-0.4, 0.4), rng.uniform(-0.3, 0.3));
    s.kind = ShapeKind::Cylinder;
    s.axes = frameFromAxis(axis, Eigen::Vector3d::UnitZ());
    s.size = Eigen::Vector3d(pixel * rng.uniform(0.7, 2.0), 0, scale * rng.uniform(2.0, 5.0));
    break;
  }
  case ShapeRole::Background:
  case ShapeRole::Distant:
  case ShapeRole::Post:
  case ShapeRole::Branch:
  case ShapeRole::Leaf:
    fail("makeObjectShape: role '", toString(role), "' is not made here");
  }
  return s;
}

} // namespace detail

using namespace detail;

namespace {

template <typename T> void checkRange(const char* field, T value, T lo, T hi) {
  if (!(value >= lo && value <= hi))
    fail("synthetic scene: '", field, "' is ", value, ", expected ", lo, " .. ", hi);
}

Shape makeBackground(const SyntheticSceneParams& p, Random& rng) {
  Shape bg;
  bg.kind = ShapeKind::Plane;
  bg.role = ShapeRole::Background;
  const double depth = rng.uniform(p.backgroundDepthMin, p.backgroundDepthMax);
  // Nearly fronto-parallel in about a third of the scenes, clearly slanted otherwise.
  const double slant = p.maxBackgroundSlantDegrees * kDeg *
                       (rng.chance(0.3) ? rng.uniform(0.0, 0.12) : rng.uniform(0.3, 1.0));
  const double azimuth = rng.uniform(0.0, 2.0 * M_PI);
  // Normal towards the cameras (-z), tilted by `slant`.
  const Eigen::Vector3d normal(std::sin(slant) * std::cos(azimuth),
                               std::sin(slant) * std::sin(azimuth), -std::cos(slant));
  bg.centre = Eigen::Vector3d(0, 0, depth);
  bg.axes = frameFromAxis(normal, Eigen::Vector3d::UnitY());
  bg.size = Eigen::Vector3d::Zero();
  bg.texture = randomTexture(rng, depth / (p.fx() * p.width), 6, 30);
  return bg;
}

// Signed distance of a point from the background plane, positive on the cameras' side.
double cameraSideDistance(const Shape& bg, const Eigen::Vector3d& x) {
  return bg.axes.col(2).dot(x - bg.centre);
}

constexpr ShapeRole kObjectRoles[] = {ShapeRole::FrontoPlane, ShapeRole::SlantedPlane,
                                      ShapeRole::Box,         ShapeRole::Sphere,
                                      ShapeRole::Pole,        ShapeRole::Wire};
constexpr int kRoleCount = 6;

Shape placeObject(const SyntheticSceneParams& p, const Shape& bg, ShapeRole role,
                  const std::vector<Shape>& placed, int index, Random& rng) {
  const double fx = p.fx(), fy = p.fy();
  // Far limit for the objects' fronts: well in front of the background's nearest visible part.
  const double zFar = std::max(p.nearDepth * 1.2, 0.6 * p.backgroundDepthMin);
  for (int attempt = 0; attempt < 200; ++attempt) {
    // Disparity-uniform front depth: as many objects per unit of parallax near as far.
    const double zFront = 1.0 / rng.uniform(1.0 / zFar, 1.0 / p.nearDepth);
    double u = rng.uniform(0.1, 0.9), v = rng.uniform(0.1, 0.9);
    if (!placed.empty() && rng.chance(0.5)) {
      // Next to an earlier object, so that the two overlap in the image (occlusion).
      const Shape& other = placed[size_t(rng.uniformInt(0, int(placed.size()) - 1))];
      u = 0.5 + fx * other.centre.x() / other.centre.z() + rng.uniform(-0.12, 0.12);
      v = 0.5 + fy * other.centre.y() / other.centre.z() + rng.uniform(-0.12, 0.12);
      u = std::min(0.95, std::max(0.05, u));
      v = std::min(0.95, std::max(0.05, v));
    }
    const double scale = 0.5 * rng.uniform(0.12, 0.35) * zFront / fx;
    const double pixel = zFront / (fx * p.width);
    Shape s = makeObjectShape(role, scale, pixel, rng);
    s.texture = randomTexture(rng, pixel, 3, 20);
    // Centre on the ray through (u, v) at the depth where the shape's front is at zFront.
    const Eigen::Vector3d ray((u - 0.5) / fx, (v - 0.5) / fy, 1.0);
    s.centre = (zFront + s.extent(-Eigen::Vector3d::UnitZ())) * ray;
    const double clearance = cameraSideDistance(bg, s.centre) - s.extent(-bg.axes.col(2));
    if (clearance > 0.05 * zFront)
      return s;
  }
  fail("synthetic scene (seed ", p.seed, "): cannot place object ", index, " (", toString(role),
       ") in front of the background");
}

} // namespace

const char* toString(SceneStyle style) {
  return style == SceneStyle::World ? "world" : "objects";
}

const char* toString(TextureSet textures) {
  return textures == TextureSet::Photo ? "photo" : "procedural";
}

SceneStyle parseSceneStyle(const std::string& text, const std::string& what) {
  if (text == "objects")
    return SceneStyle::Objects;
  if (text == "world")
    return SceneStyle::World;
  fail(what, " '", text, "': expected \"objects\" (the default) or \"world\"");
}

TextureSet parseTextureSet(const std::string& text, const std::string& what) {
  if (text == "procedural")
    return TextureSet::Procedural;
  if (text == "photo")
    return TextureSet::Photo;
  fail(what, " '", text, "': expected \"procedural\" (the default) or \"photo\"");
}

bool SyntheticSceneParams::usesPhotos() const {
  return textures == TextureSet::Photo && photos && !photos->empty();
}

double SyntheticSceneParams::fx() const {
  return 0.5 / std::tan(0.5 * fovDegrees * kDeg);
}
double SyntheticSceneParams::fy() const {
  return fx() * double(width) / double(height);
}

void SyntheticSceneParams::validate() const {
  checkRange("views", views, 1, 10000);
  checkRange("width", width, 1, 16384);
  checkRange("height", height, 1, 16384);
  checkRange("objects", objects, 0, 1000);
  checkRange("fovDegrees", fovDegrees, 5.0, 120.0);
  checkRange("nearDepth", nearDepth, 1e-3, 1e6);
  checkRange("backgroundDepthMin", backgroundDepthMin, 2.0 * nearDepth, 1e7);
  checkRange("backgroundDepthMax", backgroundDepthMax, backgroundDepthMin, 1e7);
  checkRange("maxBackgroundSlantDegrees", maxBackgroundSlantDegrees, 0.0, 45.0);
  checkRange("translation", translation, 0.0, 0.5);
  checkRange("rotationDegrees", rotationDegrees, 0.0, 10.0);
  checkRange("antialias", antialias, 1, 16);
  checkRange("photoProbability", photoProbability, 0.0, 1.0);
  if (style == SceneStyle::World) {
    const WorldStyleParams& w = world;
    checkRange("world.fovDegreesMin", w.fovDegreesMin, 20.0, 100.0);
    checkRange("world.fovDegreesMax", w.fovDegreesMax, w.fovDegreesMin, 100.0);
    checkRange("world.farRatioMin", w.farRatioMin, 3.0, 1e5);
    checkRange("world.farRatioMax", w.farRatioMax, w.farRatioMin, 1e5);
    checkRange("world.skyProbability", w.skyProbability, 0.0, 1.0);
    checkRange("world.translationMin", w.translationMin, WorldStyleParams::kTranslationLow,
               WorldStyleParams::kTranslationHigh);
    checkRange("world.translationMax", w.translationMax, w.translationMin,
               WorldStyleParams::kTranslationHigh);
    checkRange("world.rotationDegreesMax", w.rotationDegreesMax, 0.0, 10.0);
    checkRange("world.objectSizeMin", w.objectSizeMin, WorldStyleParams::kObjectSizeLow,
               WorldStyleParams::kObjectSizeHigh);
    checkRange("world.objectSizeMax", w.objectSizeMax, w.objectSizeMin,
               WorldStyleParams::kObjectSizeHigh);
    checkRange("world.thinStructuresMin", w.thinStructuresMin, 0, 100);
    checkRange("world.thinStructuresMax", w.thinStructuresMax, w.thinStructuresMin, 100);
    checkRange("world.bushesMin", w.bushesMin, 0, WorldStyleParams::kBushesHigh);
    checkRange("world.bushesMax", w.bushesMax, w.bushesMin, WorldStyleParams::kBushesHigh);
    checkRange("world.bushScaleMin", w.bushScaleMin, WorldStyleParams::kBushScaleLow,
               WorldStyleParams::kBushScaleHigh);
    checkRange("world.bushScaleMax", w.bushScaleMax, w.bushScaleMin,
               WorldStyleParams::kBushScaleHigh);
    checkRange("world.bushSharedTexture", w.bushSharedTexture, 0.0, 1.0);
    // Without sky the far plane (slanted up to kWorldMaxSlant) must fill every view, as below.
    SyntheticSceneParams widest = *this;
    widest.fovDegrees = w.fovDegreesMax;
    const double corner = std::atan(std::hypot(0.5 / widest.fx(), 0.5 / widest.fy())) / kDeg;
    const double worst = corner + kWorldMaxSlantDegrees + std::sqrt(3.0) * w.rotationDegreesMax;
    if (w.skyProbability < 1 && worst > 80.0)
      fail("synthetic scene: the image corners are ", corner,
           " degrees off-axis ('world.fovDegreesMax' ", w.fovDegreesMax, ", size ", width, "x",
           height, "); with 'world.rotationDegreesMax' ", w.rotationDegreesMax,
           " the far plane could be missed (", worst,
           " > 80 degrees): use a smaller field of view or a less elongated size");
    return;
  }
  // Every camera ray must meet the background in front of the camera: the ray farthest from
  // the optical axis (an image corner, turned further by the largest camera rotation) must
  // stay clear of the tilted plane's horizon, with a margin of 10 degrees.
  const double corner = std::atan(std::hypot(0.5 / fx(), 0.5 / fy())) / kDeg;
  const double worst = corner + maxBackgroundSlantDegrees + std::sqrt(3.0) * rotationDegrees;
  if (worst > 80.0)
    fail("synthetic scene: the image corners are ", corner, " degrees off-axis (fovDegrees ",
         fovDegrees, ", size ", width, "x", height, "); with 'maxBackgroundSlantDegrees' ",
         maxBackgroundSlantDegrees, " and 'rotationDegrees' ", rotationDegrees,
         " the background could be missed (", worst,
         " > 80 degrees): use a smaller field of view or slant, or a less elongated size");
}

SyntheticScene makeSyntheticScene(const SyntheticSceneParams& params, const Shape& background,
                                  const std::vector<Shape>& objects) {
  params.validate();
  SyntheticScene scene;
  scene.params = params;
  scene.background = background;
  scene.objects = objects;
  Random camRng(deriveSeed(params.seed, kCameras));
  scene.cameras = makeCameraPath(pathParams(params), camRng);
  return scene;
}

SyntheticScene generateSyntheticScene(const SyntheticSceneParams& input) {
  input.validate();
  SyntheticSceneParams params = input;
  if (params.textures == TextureSet::Photo && !params.usesPhotos())
    params.textures = TextureSet::Procedural; // no photographs: the procedural fallback
  if (params.style == SceneStyle::World)
    return generateWorldScene(params);
  Random bgRng(deriveSeed(params.seed, kBackground));
  Shape background = makeBackground(params, bgRng);
  maybePhotoTexture(params, 0, background.centre.z() / (params.fx() * params.width), true,
                    background);

  // Roles: shuffled blocks of all six, so every scene with >= 6 objects has each kind once.
  Random kindRng(deriveSeed(params.seed, kKinds));
  std::vector<ShapeRole> roles;
  while (int(roles.size()) < params.objects)
    for (int k : kindRng.permutation(kRoleCount))
      roles.push_back(kObjectRoles[k]);

  std::vector<Shape> objects;
  for (int i = 0; i < params.objects; ++i) {
    Random objRng(deriveSeed(deriveSeed(params.seed, kObjects), uint64_t(i)));
    objects.push_back(placeObject(params, background, roles[size_t(i)], objects, i, objRng));
    Shape& o = objects.back();
    maybePhotoTexture(params, uint64_t(i) + 1, o.centre.z() / (params.fx() * params.width),
                      o.role == ShapeRole::FrontoPlane, o);
  }

  SyntheticScene scene = makeSyntheticScene(params, background, objects);
  scene.lightDirection = randomLightDirection(params.seed);
  return scene;
}

} // namespace simpli::synthetic
