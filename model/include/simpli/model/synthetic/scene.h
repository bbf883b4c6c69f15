#pragma once
// Random forward-facing scenes with exact geometry, in one of two styles:
//  * "objects" (the default, SceneStyle::Objects): a textured background plane (fronto-
//    parallel or slanted) and textured objects in front of it — fronto-parallel and slanted
//    rectangles, boxes, spheres, and thin poles and wires (thin cylinders) — at random depths,
//    overlapping so that nearer objects occlude farther ones;
//  * "world" (SceneStyle::World, FlyingThings-like, docs/training_data.md): per scene a
//    horizontal field of view in [fovDegreesMin, fovDegreesMax], a far layer at 10 .. 100 x
//    the nearest depth (a full background plane, or a skyline of distant walls under a sky at
//    infinity), large occluding planes and objects at disparity-uniform depths with the nearest
//    one at the near depth, and thin structures (poles, posts, wires, branches of thin boxes);
//    the camera baseline is a few percent of the nearest depth.
// plus a handheld-like path of cameras looking along +z (camera_path.h). Surfaces carry
// procedural textures (texture.h) or, with TextureSet::Photo, photographs (photos.h) on a
// fraction photoProbability of them. Everything follows from the seed (random.h explains why
// the distributions are our own).
//
// Units and frames: world = the OpenCV frame of the mean camera (x right, y down, z forward),
// scene units with the nearest object at depth >= nearDepth. Cameras: simpli::Camera
// (world->camera R, t; relative intrinsics; square pixels; principal point at the centre).
#include "simpli/model/scene/camera.h"
#include "simpli/model/synthetic/shapes.h"

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace simpli::synthetic {

class PhotoLibrary;

enum class SceneStyle { Objects, World };
enum class TextureSet { Procedural, Photo };

const char* toString(SceneStyle style);
const char* toString(TextureSet textures);
/// "objects" / "world"; throws simpli::Error "<what> '<text>': expected ..." otherwise.
SceneStyle parseSceneStyle(const std::string& text, const std::string& what);
/// "procedural" / "photo"; throws simpli::Error "<what> '<text>': expected ..." otherwise.
TextureSet parseTextureSet(const std::string& text, const std::string& what);

/// Ranges of the world style, drawn once per scene (SyntheticScene::world records the draw).
struct WorldStyleParams {
  double fovDegreesMin = 50.0, fovDegreesMax = 70.0; ///< horizontal field of view, uniform
  /// Depth of the far layer / nearDepth, log-uniform: near/far ratios of 1:10 .. 1:100.
  double farRatioMin = 10.0, farRatioMax = 100.0;
  double skyProbability = 0.6; ///< scenes with a sky at infinity above a skyline
  /// Largest distance of a camera centre from the mean centre / nearDepth, log-uniform. Real
  /// handheld captures reach far more than a few %: LLFF flower's centres lie up to 0.55 x its
  /// near bound apart (`simpli info`), about 0.28 from their mean.
  double translationMin = 0.01, translationMax = 0.3;
  /// What validate() accepts for the translation range (training configs check the same).
  static constexpr double kTranslationLow = 1e-4, kTranslationHigh = 0.5;
  double rotationDegreesMax = 2.0; ///< bound on yaw, pitch, roll: 0.25 .. 1 x this per scene
  /// Apparent width of the occluders after the first / image width, log-uniform. Dense small
  /// clutter (foliage: LLFF flower's leaves are ~5-20 % of the image) needs a lower range and
  /// more `objects` than the default's few large shapes.
  double objectSizeMin = 0.08, objectSizeMax = 0.6;
  /// What validate() accepts for the object size range (training configs check the same).
  static constexpr double kObjectSizeLow = 0.005, kObjectSizeHigh = 1.0;
  int thinStructuresMin = 1, thinStructuresMax = 4; ///< poles, posts, wires, branches
  /// Bushes per scene, uniform: clusters of 20 .. 60 small pointed leaves (Leaf shapes, 3 .. 10 %
  /// of the image width long, turned up to 60 degrees about both image axes) around a point at a
  /// disparity-uniform depth. Foliage as in LLFF flower: many small surfaces at many depths and
  /// slants, whose edges cross each other (the default scenes' few large occluders do not).
  int bushesMin = 0, bushesMax = 0;
  static constexpr int kBushesHigh = 50; ///< what validate() accepts
  /// Each bush's size (its leaves and the ball they fill) x a factor drawn log-uniform in [min,
  /// max] per bush. LLFF flower's leaves are 10 .. 35 % of the image long: 3 draws leaves of 9 ..
  /// 30 % in a ball of 24 .. 75 %. Equal bounds draw nothing, so the default's scenes keep their
  /// draws.
  double bushScaleMin = 1, bushScaleMax = 1;
  /// What validate() accepts for the bush scale range (training configs check the same).
  static constexpr double kBushScaleLow = 0.25, kBushScaleHigh = 4;
  /// Probability that a bush's leaves share one photo (same colour jitter, own crops and turns)
  /// instead of a texture each: foliage of one colour whose leaves only parallax separates.
  /// Needs photo textures; 0 draws nothing, so the default's scenes keep their draws.
  double bushSharedTexture = 0;
};

struct SyntheticSceneParams {
  uint64_t seed = 0;
  int views = 12;
  int width = 192, height = 128;           ///< pixels (the network needs multiples of 16)
  int objects = 8;                         ///< objects in front of the background
  double fovDegrees = 60.0;                ///< horizontal field of view
  double nearDepth = 2.0;                  ///< objects are placed at depths >= this (scene units)
  double backgroundDepthMin = 10.0;        ///< background depth on the optical axis: uniform in
  double backgroundDepthMax = 16.0;        ///< [min, max] (scene units)
  double maxBackgroundSlantDegrees = 25.0; ///< tilt of the background plane's normal from -z
  /// Camera centres lie within translation * nearDepth of their mean (exactly that far for the
  /// farthest one); the motion is mostly in the image plane.
  double translation = 0.04;
  double rotationDegrees = 1.5; ///< bound on each camera's yaw, pitch and roll
  int antialias = 4;            ///< antialias^2 jittered samples per pixel (1 = centre only)
  SceneStyle style = SceneStyle::Objects;
  /// Photo: each surface gets a photo texture with probability photoProbability (else a
  /// procedural one) when `photos` holds photographs; without photos the scene falls back to
  /// procedural textures (and records TextureSet::Procedural).
  TextureSet textures = TextureSet::Procedural;
  double photoProbability = 0.85;
  std::shared_ptr<const PhotoLibrary> photos;
  /// The world style's ranges; with it, fovDegrees, translation, rotationDegrees and the
  /// background depths above are not used (each scene draws its own from these).
  WorldStyleParams world;

  /// Throws simpli::Error naming the field and value when a parameter is out of range.
  void validate() const;
  /// Whether surfaces get photo textures (textures == Photo and photos holds photographs).
  bool usesPhotos() const;
  /// Relative focal lengths for square pixels: fx = 0.5 / tan(fov / 2), fy = fx * width / height.
  double fx() const;
  double fy() const;
};

/// What a world-style scene drew from its WorldStyleParams ranges.
struct WorldLayout {
  double fovDegrees = 0;      ///< horizontal field of view
  double farDepth = 0;        ///< depth of the far layer on the optical axis (scene units)
  double translation = 0;     ///< largest camera offset from the mean centre / nearDepth
  double rotationDegrees = 0; ///< bound on the cameras' yaw, pitch, roll
  bool sky = false;           ///< a sky at infinity above a skyline of distant walls
};

struct SyntheticScene {
  SyntheticSceneParams params; ///< as given (validated); textures as used
  /// ShapeKind::Plane (objects style, and world style without sky), else (world style with
  /// sky) the farthest wall of the skyline, a Rectangle reaching from below the images to a
  /// top edge inside them.
  Shape background;
  std::vector<Shape> objects;
  bool hasSky = false; ///< rays that hit nothing see `sky` (depth 0 = infinity), else grey
  Texture sky;         ///< Pattern::Sky or Pattern::Photo, evaluated at (azimuth, elevation)
  WorldLayout world;   ///< world style: the per-scene draw
  Eigen::Vector3d lightDirection = Eigen::Vector3d(0, 0, -1); ///< unit, towards the light
  std::vector<scene::Camera> cameras;

  /// Background first (index 0), then the objects (index i + 1) — the indices SurfaceHit uses.
  const Shape& shape(int index) const {
    return index == 0 ? background : objects[size_t(index) - 1];
  }
  int shapeCount() const { return int(objects.size()) + 1; }
};

/// Generates the scene for params.seed (validating the parameters first). Objects, cameras and
/// textures come from separate streams derived from the seed, so changing --views keeps the
/// geometry and changing --objects keeps the cameras and the first objects.
SyntheticScene generateSyntheticScene(const SyntheticSceneParams& params);

/// A scene with the given background and objects and the params' camera path; for tests and
/// hand-built scenes (no randomness except the cameras, which come from params.seed).
SyntheticScene makeSyntheticScene(const SyntheticSceneParams& params, const Shape& background,
                                  const std::vector<Shape>& objects);

} // namespace simpli::synthetic
