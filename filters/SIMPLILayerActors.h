// Drawing an MLI layer collection (SIMPLIMLIToVTK.h) with VTK's OpenGL renderer: one actor per
// layer, drawn back to front in dataset order and blended with straight alpha, and the simpli
// camera as a vtkCamera. Not part of the VTK module (whose dependencies stop at data and
// execution): a small library, simpli_vtk_render, for `simpli bench render` and the render
// tests. Private: it mentions Eigen through scene::Camera.
//
// Why back to front without depth peeling: an MLI's layers are ordered by depth along every
// reference ray (layer 0 farthest), so drawing them in index order with over-blending
// (c = a c_layer + (1 - a) c_below; VTK's default blend function on straight alpha) composites
// them as the rasterizer does, in one pass per layer. Depth peeling costs several passes and,
// with a finite peel limit, drops layers under Mesa (tests/vtk/render_agreement.cxx). VTK 9.2's
// renderer without depth peeling does not blend in order either: it uses weighted blended
// order-independent translucency (measured: red then green at alpha 0.5 over black gives
// (96, 96, 0) in either order instead of (64, 128, 0)). useLayerOrderBlending therefore gives
// the renderer a plain vtkRenderStepsPass, whose translucent step draws the translucent actors
// in the order they were added, depth test on (against opaque layers) and depth writes off.
#pragma once

#include <vector>

#include <vtkSmartPointer.h>

#include "simpli/model/scene/camera.h"

class vtkActor;
class vtkCamera;
class vtkPartitionedDataSetCollection;
class vtkRenderWindow;
class vtkRenderer;

namespace simpli::vtkrender {

struct LayerActorOptions {
  /// Draw the first (farthest) layer opaque, its colour without its alpha: the rasterizer's
  /// rule that the farthest fragment of a pixel is opaque (spec §6.7), which is what
  /// `simpli render` shows; off draws every layer with its own alpha.
  bool opaqueBackLayer = true;
};

/// Adds one actor per layer of `layers` to `renderer` in dataset order (back to front) and
/// returns them. Unlit (ambient 1, diffuse 0): the colour is the texel's. Adaptive layers (with
/// a TextureRGBA) are drawn with a vtkTexture of their layerTexture (linear interpolation,
/// clamped at the edges, straight alpha, scalars off); per-texel layers with their RGBA point
/// scalars as colours (direct scalars, ParaView's MapScalars off). Throws simpli::Error naming
/// the layer when a dataset is not a vtkPolyData.
std::vector<vtkSmartPointer<vtkActor>> addLayerActors(vtkRenderer* renderer,
                                                      vtkPartitionedDataSetCollection* layers,
                                                      const LayerActorOptions& options = {});

/// Makes `renderer` blend translucent actors in the order they were added (see above): no depth
/// peeling, a vtkRenderStepsPass instead of the default order-independent translucency.
void useLayerOrderBlending(vtkRenderer* renderer);

/// Sets `vc` to look through simpli camera `c`: position = centre, focal point one unit along
/// +z_cam, view up = -y_cam (OpenCV's y points down), vertical view angle 2 atan(0.5 / fy'),
/// window centre (1 - 2 cx', 2 cy' - 1) for the principal point, clipping range [nearZ, farZ].
/// vtkCamera needs square pixels: throws simpli::Error naming fx' W and fy' H otherwise.
void setCamera(vtkCamera* vc, const scene::Camera& c, double nearZ, double farZ);

/// The window's colour buffer as RGB in [0, 1], interleaved, row 0 = the top image row.
std::vector<float> grabRGB(vtkRenderWindow* window);

/// Connects to $DISPLAY (retrying for up to 30 s) and keeps the connection until the process
/// exits: Xvfb resets when its last client leaves and refuses clients meanwhile, and VTK aborts
/// the process on a refused connection. False when DISPLAY is unset or nothing answers.
bool holdXDisplay();

} // namespace simpli::vtkrender
