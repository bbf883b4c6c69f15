#pragma once
// Exact CPU ray casting of a synthetic scene.
//
// Pixel (x, y) covers relative image coordinates [x/W, (x+1)/W] x [y/H, (y+1)/H]; its centre
// is ((x + 0.5)/W, (y + 0.5)/H) (the reference's centre grid, spec §1.3).
//  * Depth: camera-space z of the nearest surface on the ray through the pixel centre — exact
//    up to double rounding (stored as float); 0 where the ray hits nothing.
//  * Colour: mean of antialias x antialias stratified samples with deterministic jitter
//    (hashed from the scene seed, view and pixel), each the procedural texture at the hit's
//    surface coordinates times a view-independent Lambert factor; rays that hit nothing see
//    the scene's sky (at infinity: its colour depends on the ray direction only) or, without
//    sky, mid-grey (the reference's "no geometry" value 0 in [-1, 1]). Quantised to 8 bits,
//    as an image file would hold it.
#include "simpli/model/io/image.h"
#include "simpli/model/synthetic/scene.h"

#include <cstdint>
#include <vector>

namespace simpli::synthetic {

struct RenderedView {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb; ///< height x width x 3 (R, G, B), row-major
  std::vector<float> depth; ///< height x width camera-space z (scene units); 0 = no surface

  float depthAt(int x, int y) const { return depth[size_t(y) * size_t(width) + size_t(x)]; }
  /// RGB in [-1, 1] (CHW), value for value what readImage returns for the PNG of `rgb`.
  io::Image image() const;
};

/// Ray through relative image coordinates (u, v): origin at the camera centre, direction with
/// camera-space z = 1, so that a hit's ray parameter is its depth.
Ray cameraRay(const scene::Camera& camera, double u, double v);

/// Nearest hit along a ray over all shapes of the scene (hit.shape: 0 = background,
/// i + 1 = objects[i]); no hit: hit.hit() is false.
SurfaceHit castRay(const SyntheticScene& scene, const Ray& ray);

/// castRay over the shapes in `shapes` only (ascending indices, e.g. shapesThroughWindow's).
SurfaceHit castRay(const SyntheticScene& scene, const Ray& ray, const std::vector<int>& shapes);

/// The shapes (ascending indices) that a ray of `camera` through the relative image window
/// [u0, u1] x [v0, v1] can hit. A shape is left out only when it lies entirely outside one of
/// the four planes through the camera centre that bound the window's rays (the support
/// function test with Shape::extent, with a small margin), so castRay among them gives
/// castRay's hit for every ray through the window. Infinite planes are always kept.
std::vector<int> shapesThroughWindow(const SyntheticScene& scene, const scene::Camera& camera,
                                     double u0, double u1, double v0, double v1);

/// RGB in [0, 1] of a hit: its shape's texture times 0.55 + 0.45 * max(0, n . light) (planes
/// and rectangles are two-sided: |n . light|).
Eigen::Vector3d shadeHit(const SyntheticScene& scene, const SurfaceHit& hit);

/// RGB in [0, 1] of a ray that hits nothing: the sky at (azimuth, elevation) of its world
/// direction (atan2(x, z), atan2(-y, hypot(x, z))), or mid-grey without sky.
Eigen::Vector3d missColour(const SyntheticScene& scene, const Ray& ray);

/// Renders one camera; `jitterSeed` fixes the anti-aliasing sample positions.
RenderedView renderView(const SyntheticScene& scene, const scene::Camera& camera,
                        uint64_t jitterSeed);

/// Renders view `index` of scene.cameras with the scene's own jitter seed for that view.
RenderedView renderView(const SyntheticScene& scene, int index);

/// All views of the scene.
std::vector<RenderedView> renderViews(const SyntheticScene& scene);

/// The depth of view `index` alone (rgb left empty): exactly renderView(scene, index).depth
/// (one ray through each pixel centre) at a fifth of the rays of a 2x2-antialiased render and
/// no shading. Training needs every view's depth (the scene's bounds) but colour only of the
/// views a sample uses.
RenderedView renderDepth(const SyntheticScene& scene, int index);

/// Near and far bounds of one view for poses_bounds.npy. The depth maps are exact, so there
/// are no outliers to reject (LLFF takes percentiles of noisy SfM points instead): near =
/// 0.9 x the smallest depth and far = 1.1 x the largest, so that every surface lies strictly
/// inside. Throws when the view has no surface at all.
struct DepthBounds {
  double near = 0, far = 0;
};
DepthBounds depthBounds(const RenderedView& view);

} // namespace simpli::synthetic
