// The world style of the synthetic scenes (see synthetic/scene.h, docs/training_data.md):
// FlyingThings-like layouts under handheld forward-facing camera statistics.
#include "simpli/error.h"
#include "simpli/model/synthetic/photos.h"
#include "simpli/model/synthetic/scene.h"

#include "synthetic/scene_internal.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace simpli::synthetic::detail {

namespace {

// Point on the ray through relative image coordinates (u, v) of the mean camera at depth z.
Eigen::Vector3d atImage(const SyntheticSceneParams& p, double u, double v, double z) {
  return Eigen::Vector3d((u - 0.5) / p.fx() * z, (v - 0.5) / p.fy() * z, z);
}

// Scene units per image pixel at depth z.
double pixelAt(const SyntheticSceneParams& p, double z) {
  return z / (p.fx() * p.width);
}

// Axes of a wall facing the cameras: local z towards them (-z), local y down, turned by yaw.
Eigen::Matrix3d wallAxes(double yaw) {
  return rotation(yaw, 0, 0) * frameFromAxis(-Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY());
}

// The far plane of a scene without sky: nearly fronto-parallel or slanted up to
// kWorldMaxSlantDegrees, at depth `far` on the optical axis.
Shape farPlane(const SyntheticSceneParams& p, double far, Random& rng) {
  Shape bg;
  bg.kind = ShapeKind::Plane;
  bg.role = ShapeRole::Background;
  const double slant =
      kDeg * (rng.chance(0.4) ? rng.uniform(0.0, 3.0) : rng.uniform(5.0, kWorldMaxSlantDegrees));
  const double azimuth = rng.uniform(0.0, 2.0 * M_PI);
  const Eigen::Vector3d normal(std::sin(slant) * std::cos(azimuth),
                               std::sin(slant) * std::sin(azimuth), -std::cos(slant));
  bg.centre = Eigen::Vector3d(0, 0, far);
  bg.axes = frameFromAxis(normal, Eigen::Vector3d::UnitY());
  bg.size = Eigen::Vector3d::Zero();
  bg.texture = randomTexture(rng, pixelAt(p, far), 6, 30);
  return bg;
}

// A wall of the skyline at depth z: from well below the images up to image row vTop, centred
// on image column u with half width hu (relative image units).
Shape skylineWall(const SyntheticSceneParams& p, ShapeRole role, double z, double u, double hu,
                  double vTop, double yaw, Random& rng) {
  Shape s;
  s.kind = ShapeKind::Rectangle;
  s.role = role;
  const double vBottom = 2.0;
  s.axes = wallAxes(yaw);
  s.centre = atImage(p, u, 0.5 * (vTop + vBottom), z);
  s.size = Eigen::Vector3d(hu * z / p.fx(), 0.5 * (vBottom - vTop) * z / p.fy(), 0);
  s.texture = randomTexture(rng, pixelAt(p, z), 6, 30);
  return s;
}

// Distance of x from the far layer on the cameras' side (the layer's local z points to them).
double cameraSideDistance(const Shape& bg, const Eigen::Vector3d& x) {
  return bg.axes.col(2).dot(x - bg.centre);
}

struct Placement {
  const SyntheticSceneParams& p;
  const Shape& far;
  bool sky;
  double farDepth;

  // Whether the shape lies clearly in front of the far layer (and, with sky, in front of
  // every skyline wall, which all lie beyond 0.6 x farDepth).
  bool clear(const Shape& s) const {
    const double front = s.centre.z() - s.extent(-Eigen::Vector3d::UnitZ());
    if (sky)
      return s.centre.z() + s.extent(Eigen::Vector3d::UnitZ()) < 0.5 * farDepth;
    return cameraSideDistance(far, s.centre) - s.extent(-far.axes.col(2)) > 0.05 * front;
  }
  bool clear(const std::vector<Shape>& parts) const {
    return std::all_of(parts.begin(), parts.end(), [this](const Shape& s) { return clear(s); });
  }
  // Disparity-uniform depth in [near, 0.45 x farDepth].
  double depth(Random& rng) const {
    const double zMax = 0.45 * farDepth;
    return 1.0 / rng.uniform(1.0 / zMax, 1.0 / p.nearDepth);
  }
};

// Moves the parts together onto the ray through image point (u, v) of the mean camera so that
// their nearest point lies at depth z.
void moveOntoRay(const SyntheticSceneParams& p, double u, double v, double z,
                 std::vector<Shape>& parts) {
  double front = std::numeric_limits<double>::infinity();
  for (const Shape& part : parts)
    front = std::min(front, part.centre.z() - part.extent(-Eigen::Vector3d::UnitZ()));
  const Eigen::Vector3d shift = atImage(p, u, v, z) - Eigen::Vector3d(0, 0, front);
  for (Shape& part : parts)
    part.centre += shift;
}

ShapeRole occluderRole(Random& rng) {
  const double r = rng.uniform();
  return r < 0.3    ? ShapeRole::FrontoPlane
         : r < 0.6  ? ShapeRole::SlantedPlane
         : r < 0.85 ? ShapeRole::Box
                    : ShapeRole::Sphere;
}

// Occluder i: object 0 is the nearest (front at 1 .. 1.1 x nearDepth, near the image centre),
// the others at disparity-uniform depths, often overlapping an earlier one; apparent sizes
// log-uniform in world.objectSize (default 8 .. 60 % of the image width).
Shape placeOccluder(const Placement& where, const std::vector<Shape>& placed, int index,
                    Random& rng) {
  const SyntheticSceneParams& p = where.p;
  const ShapeRole role = occluderRole(rng);
  for (int attempt = 0; attempt < 200; ++attempt) {
    double zFront, u, v, apparent;
    if (index == 0) {
      zFront = p.nearDepth * rng.uniform(1.0, 1.1);
      u = rng.uniform(0.3, 0.7);
      v = rng.uniform(0.3, 0.7);
      apparent = rng.uniform(0.2, 0.5);
    } else {
      zFront = where.depth(rng);
      u = rng.uniform(-0.05, 1.05);
      v = rng.uniform(-0.05, 1.05);
      if (!placed.empty() && rng.chance(0.5)) {
        const Shape& other = placed[size_t(rng.uniformInt(0, int(placed.size()) - 1))];
        u = 0.5 + p.fx() * other.centre.x() / other.centre.z() + rng.uniform(-0.15, 0.15);
        v = 0.5 + p.fy() * other.centre.y() / other.centre.z() + rng.uniform(-0.15, 0.15);
      }
      apparent = logUniform(rng, p.world.objectSizeMin, p.world.objectSizeMax);
    }
    const double scale = 0.5 * apparent * zFront / p.fx();
    const double pixel = pixelAt(p, zFront);
    Shape s = makeObjectShape(role, scale, pixel, rng);
    s.texture = randomTexture(rng, pixel, 3, 20);
    const Eigen::Vector3d ray((u - 0.5) / p.fx(), (v - 0.5) / p.fy(), 1.0);
    s.centre = (zFront + s.extent(-Eigen::Vector3d::UnitZ())) * ray;
    if (where.clear(s))
      return s;
  }
  fail("synthetic world scene (seed ", p.seed, "): cannot place occluder ", index,
       " in front of the far layer");
}

// Thin structure j: a pole (thin cylinder) or post (thin box), both nearly vertical and
// spanning most of the image height; a wire (thin, roughly horizontal cylinder); or a branch:
// a thin box limb at any angle with 1 .. 3 thinner twigs. 1 .. 5 pixels thick where they
// stand.
std::vector<Shape> placeThin(const Placement& where, int index, Random& rng) {
  const SyntheticSceneParams& p = where.p;
  const int kind = rng.uniformInt(0, 3);
  for (int attempt = 0; attempt < 200; ++attempt) {
    const double z = where.depth(rng);
    const double pixel = pixelAt(p, z);
    const double u = rng.uniform(0.05, 0.95), v = rng.uniform(0.05, 0.95);
    std::vector<Shape> parts;
    Shape s;
    switch (kind) {
    case 0: { // pole
      s.role = ShapeRole::Pole;
      s.kind = ShapeKind::Cylinder;
      const Eigen::Vector3d axis(rng.uniform(-0.12, 0.12), 1.0, rng.uniform(-0.2, 0.2));
      s.axes = frameFromAxis(axis, Eigen::Vector3d::UnitZ());
      s.size =
          Eigen::Vector3d(pixel * rng.uniform(0.6, 2.5), 0, z / p.fy() * rng.uniform(0.4, 1.0));
      parts.push_back(s);
      break;
    }
    case 1: { // post
      s.role = ShapeRole::Post;
      s.kind = ShapeKind::Box;
      s.axes = rotation(rng.uniform(-30, 30) * kDeg, 0, rng.uniform(-8, 8) * kDeg);
      s.size = Eigen::Vector3d(pixel * rng.uniform(0.6, 2.5), z / p.fy() * rng.uniform(0.4, 1.0),
                               pixel * rng.uniform(0.6, 2.5));
      parts.push_back(s);
      break;
    }
    case 2: { // wire
      s.role = ShapeRole::Wire;
      s.kind = ShapeKind::Cylinder;
      const Eigen::Vector3d axis(1.0, rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3));
      s.axes = frameFromAxis(axis, Eigen::Vector3d::UnitZ());
      s.size =
          Eigen::Vector3d(pixel * rng.uniform(0.5, 1.5), 0, z / p.fx() * rng.uniform(0.4, 1.2));
      parts.push_back(s);
      break;
    }
    default: { // branch: limb along its local x, twigs from points along it
      const double angle = rng.uniform(-70, 70) * kDeg + (rng.chance(0.5) ? M_PI : 0.0);
      const double yaw = rng.uniform(-35, 35) * kDeg;
      const double half = z / p.fx() * rng.uniform(0.2, 0.5);
      const double thick = pixel * rng.uniform(0.75, 2.5); // half thickness
      s.role = ShapeRole::Branch;
      s.kind = ShapeKind::Box;
      s.axes = rotation(yaw, 0, angle);
      s.size = Eigen::Vector3d(half, thick, thick);
      parts.push_back(s);
      const int twigs = rng.uniformInt(1, 3);
      for (int k = 0; k < twigs; ++k) {
        const Eigen::Vector3d start = s.axes.col(0) * (half * rng.uniform(-0.6, 0.9));
        const double twigAngle = angle + rng.sign() * rng.uniform(25, 60) * kDeg;
        const double twigHalf = half * rng.uniform(0.3, 0.6);
        Shape t = s;
        t.axes = rotation(yaw + rng.uniform(-10, 10) * kDeg, 0, twigAngle);
        t.size = Eigen::Vector3d(twigHalf, 0.6 * thick, 0.6 * thick);
        t.centre = start + t.axes.col(0) * twigHalf;
        parts.push_back(t);
      }
      break;
    }
    }
    moveOntoRay(p, u, v, z, parts);
    for (Shape& part : parts)
      part.texture = randomTexture(rng, pixel, 2, 12);
    if (where.clear(parts))
      return parts;
  }
  fail("synthetic world scene (seed ", p.seed, "): cannot place thin structure ", index,
       " in front of the far layer");
}

// With probability world.bushSharedTexture (and photoProbability), every leaf of a bush gets
// the same photo with the same colour jitter, each its own crop and turn: foliage whose leaves
// differ little in colour, so that only parallax tells their edges apart (LLFF flower's green
// leaves against green leaves), where leaves textured one by one contrast at every edge. The
// texture loop of generateWorldScene then leaves them alone. Draws come after the placement,
// from the bush's own stream: the placement is the same either way.
void maybeSharedLeafTexture(const SyntheticSceneParams& p, double unitsPerPixel, Random& rng,
                            std::vector<Shape>& leaves) {
  if (!p.usesPhotos() || !(p.world.bushSharedTexture > 0))
    return;
  Random draw(rng.bits());
  if (!draw.chance(p.world.bushSharedTexture) || !draw.chance(p.photoProbability))
    return;
  const Texture shared = randomPhotoTexture(draw, allPhotos(p), unitsPerPixel, false);
  for (Shape& leaf : leaves) {
    leaf.texture = shared;
    leaf.texture.mapping.offset = Eigen::Vector2d(draw.uniform(0.0, double(shared.photo->width)),
                                                  draw.uniform(0.0, double(shared.photo->height)));
    leaf.texture.angle = draw.uniform(0.0, 2.0 * M_PI);
  }
}

// Bush j: 20 .. 60 pointed leaves (3 .. 10 % of the image width long, a quarter to half as wide)
// scattered through a flattened ball 8 .. 25 % of the width across, each turned up to 60 degrees
// about both image axes and any angle in its plane; the nearest leaf at a disparity-uniform depth.
// Leaves and ball x a factor drawn in world.bushScale (log-uniform).
std::vector<Shape> placeBush(const Placement& where, int index, Random& rng) {
  const SyntheticSceneParams& p = where.p;
  const int leaves = rng.uniformInt(20, 60);
  const double scale =
      logUniform(rng, p.world.bushScaleMin, p.world.bushScaleMax); // equal: no draw
  for (int attempt = 0; attempt < 200; ++attempt) {
    const double z = where.depth(rng);
    const double unitsPerWidth = scale * z / p.fx(); // scene units across the image at z, x scale
    const double radius = 0.5 * unitsPerWidth * rng.uniform(0.08, 0.25);
    const double u = rng.uniform(0.0, 1.0), v = rng.uniform(0.0, 1.0);
    std::vector<Shape> parts;
    for (int k = 0; k < leaves; ++k) {
      Shape leaf;
      leaf.kind = ShapeKind::Leaf;
      leaf.role = ShapeRole::Leaf;
      leaf.axes = rotation(rng.uniform(-60, 60) * kDeg, rng.uniform(-60, 60) * kDeg,
                           rng.uniform(-180, 180) * kDeg);
      const double half = 0.5 * unitsPerWidth * rng.uniform(0.03, 0.10);
      leaf.size = Eigen::Vector3d(half, half * rng.uniform(0.25, 0.5), 0);
      Eigen::Vector3d offset;
      do
        offset = Eigen::Vector3d(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
      while (offset.squaredNorm() > 1);
      leaf.centre = radius * Eigen::Vector3d(offset.x(), offset.y(), 0.5 * offset.z());
      parts.push_back(leaf);
    }
    moveOntoRay(p, u, v, z, parts);
    for (Shape& part : parts)
      part.texture = randomTexture(rng, pixelAt(p, part.centre.z()), 2, 12);
    if (where.clear(parts)) {
      maybeSharedLeafTexture(p, pixelAt(p, z), rng, parts);
      return parts;
    }
  }
  fail("synthetic world scene (seed ", p.seed, "): cannot place bush ", index,
       " in front of the far layer");
}

// Appends low .. high groups of shapes (thin structures, bushes): the count drawn from `stream`,
// group j placed with its own stream (j + 1 of it), so each kind leaves the others' draws alone.
using PlaceGroup = std::vector<Shape> (*)(const Placement&, int, Random&);
void addGroups(uint64_t seed, Stream stream, int low, int high, const Placement& where,
               PlaceGroup place, std::vector<Shape>& objects) {
  Random count(deriveSeed(seed, stream));
  const int groups = count.uniformInt(low, high);
  for (int j = 0; j < groups; ++j) {
    Random rng(deriveSeed(deriveSeed(seed, stream), uint64_t(j) + 1));
    for (Shape& part : place(where, j, rng))
      objects.push_back(std::move(part));
  }
}

} // namespace

SyntheticScene generateWorldScene(const SyntheticSceneParams& params) {
  const WorldStyleParams& w = params.world;
  // The per-scene draw: field of view, far depth, baseline, rotations, sky.
  Random layout(deriveSeed(params.seed, kWorldLayout));
  WorldLayout drawn;
  drawn.fovDegrees = layout.uniform(w.fovDegreesMin, w.fovDegreesMax);
  drawn.farDepth = params.nearDepth * logUniform(layout, w.farRatioMin, w.farRatioMax);
  drawn.translation = logUniform(layout, w.translationMin, w.translationMax);
  drawn.rotationDegrees = w.rotationDegreesMax * layout.uniform(0.25, 1.0);
  drawn.sky = layout.chance(w.skyProbability);
  // The params this scene is built with (the camera path and the placement use them).
  SyntheticSceneParams p = params;
  p.fovDegrees = drawn.fovDegrees;
  p.translation = drawn.translation;
  p.rotationDegrees = drawn.rotationDegrees;
  p.backgroundDepthMin = p.backgroundDepthMax = drawn.farDepth;
  const double far = drawn.farDepth;

  Random bgRng(deriveSeed(params.seed, kBackground));
  std::vector<Shape> objects;
  Shape background;
  if (drawn.sky) {
    // The farthest wall spans the images below a top edge at 25 .. 60 % of the height; up to
    // three nearer, narrower and lower walls in front of it.
    const double vTop = bgRng.uniform(0.25, 0.6);
    background = skylineWall(p, ShapeRole::Background, far, 0.5, 1.5, vTop, 0.0, bgRng);
    const int walls = bgRng.uniformInt(0, 3);
    for (int k = 0; k < walls; ++k) {
      const double z = far * bgRng.uniform(0.6, 0.95);
      const double u = bgRng.uniform(0.0, 1.0), hu = bgRng.uniform(0.08, 0.4);
      const double top = bgRng.uniform(vTop + 0.05, 0.9);
      objects.push_back(
          skylineWall(p, ShapeRole::Distant, z, u, hu, top, bgRng.uniform(-8, 8) * kDeg, bgRng));
    }
  } else {
    background = farPlane(p, far, bgRng);
  }

  const Placement where{p, background, drawn.sky, far};
  std::vector<Shape> occluders;
  for (int i = 0; i < p.objects; ++i) {
    Random rng(deriveSeed(deriveSeed(p.seed, kObjects), uint64_t(i)));
    occluders.push_back(placeOccluder(where, occluders, i, rng));
  }
  objects.insert(objects.end(), occluders.begin(), occluders.end());
  addGroups(p.seed, kThin, w.thinStructuresMin, w.thinStructuresMax, where, placeThin, objects);
  addGroups(p.seed, kBushes, w.bushesMin, w.bushesMax, where, placeBush, objects);

  // Photo textures, upright on the walls and fronto-parallel planes.
  maybePhotoTexture(p, 0, pixelAt(p, background.centre.z()), true, background);
  for (size_t i = 0; i < objects.size(); ++i) {
    Shape& o = objects[i];
    if (o.role == ShapeRole::Leaf && o.texture.pattern == Pattern::Photo)
      continue; // a bush's shared photo (maybeSharedLeafTexture)
    const bool upright = o.role == ShapeRole::Distant || o.role == ShapeRole::FrontoPlane;
    maybePhotoTexture(p, uint64_t(i) + 1, pixelAt(p, std::max(o.centre.z(), p.nearDepth)), upright,
                      o);
  }

  SyntheticScene scene;
  scene.params = params;
  scene.background = background;
  scene.objects = std::move(objects);
  scene.world = drawn;
  if (drawn.sky) {
    Random skyRng(deriveSeed(p.seed, kSky));
    scene.hasSky = true;
    scene.sky = randomSkyTexture(skyRng);
  }
  Random camRng(deriveSeed(p.seed, kCameras));
  scene.cameras = makeCameraPath(pathParams(p), camRng);
  scene.lightDirection = randomLightDirection(p.seed);
  return scene;
}

} // namespace simpli::synthetic::detail
