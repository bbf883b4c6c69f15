// Agreement of the OpenCL rasterizer (perspective-correct interpolation, what `simpli render
// --perspective-correct` draws) with VTK's OpenGL rendering of the same MLI from the same camera,
// for both layer forms vtkMLIReader builds.
//
// usage: render_agreement OUT_DIR   (needs an X server: run under xvfb-run)
//
// VTK side (simpli_vtk_render, SIMPLILayerActors.h): one unlit actor per layer (ambient 1,
// diffuse 0), no multisampling, window size = image size, the camera converted from the simpli
// intrinsics/extrinsics (vtkrender::setCamera; square pixels, fx' W = fy' H). Three VTK renders
// are checked against the rasterizer's render of the per-texel mesh:
//   1. per-texel layers (RGBA point scalars, MapScalars off) with dual depth peeling, no peel
//      limit and occlusion ratio 0 (see renderVTK for why not a finite limit such as 20);
//   2. per-texel layers blended back to front in layer order (no depth peeling);
//   3. adaptive layers (MeshMode Adaptive: the adaptive mesh with a per-layer texture, linear
//      interpolation, straight alpha) blended back to front, on the coarse MLI below and on a
//      finer, textured one (where the adaptive mesh has far fewer triangles than texels).
//
// Comparison: PSNR (peak 1) over the pixels both renderers cover. VTK coverage = pixels that
// come out the same over a black and a white background; rasterizer coverage = opacity > 0.999.
// The far layer covers the view, so the rasterizer's "farthest fragment is opaque" rule (spec
// §6.7) applies to it, as simpli_vtk_render's opaque back layer does, and both renderers
// composite the same fragments (the coarse MLI's far layer has alpha 1, the textured one's 0.6).
// Fails below 35 dB or when fewer than 70 % of the pixels are compared. Writes the images as PNGs
// into OUT_DIR.
#include "SIMPLILayerActors.h"
#include "vtkMLIReader.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPartitionedDataSet.h>
#include <vtkPartitionedDataSetCollection.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>

#include "simpli/model/mli/files.h"
#include "simpli/model/raster/render_mli.h"

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace simpli;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kW = 16, kH = 12; // MLI grid

// Three layers on a coarse 16 x 12 grid (so that triangles span many pixels and a range of
// depths, where screen-linear and perspective-correct interpolation differ): a far opaque layer (z
// ~ 9) with a colour gradient, a middle layer (z ~ 4.5, wavy) with smoothly varying alpha, a near
// layer (z ~ 2.6) that is transparent in a band. Smooth colours: the comparison measures the
// renderers, not aliasing.
mli::MLI agreementMLI() {
  scene::Camera ref;
  ref.R = Eigen::AngleAxisd(0.05, Eigen::Vector3d(0.0, 1.0, 0.2).normalized()).toRotationMatrix();
  ref.t = Eigen::Vector3d(0.1, -0.05, 0.2);
  ref.fx = 0.8;
  ref.fy = 0.8 * kW / kH;
  ref.cx = 0.5;
  ref.cy = 0.5;
  ref.width = kW;
  ref.height = kH;
  mli::MLI mli = mli::MLI::allocate(ref, 3);
  for (int i = 0; i < kH; ++i)
    for (int j = 0; j < kW; ++j) {
      const std::size_t p = static_cast<std::size_t>(i) * kW + j;
      const double u = j / (kW - 1.0), v = i / (kH - 1.0);
      float* far = &mli.layers[0].rgba[4 * p];
      mli.layers[0].depth[p] = static_cast<float>(6.0 + 8.0 * u - 0.8 * v); // strongly slanted
      far[0] = static_cast<float>(0.2 + 0.6 * u);
      far[1] = static_cast<float>(0.3 + 0.5 * v);
      far[2] = static_cast<float>(0.5 + 0.4 * std::sin(3.0 * u + 2.0 * v));
      far[3] = 1.0f;
      float* mid = &mli.layers[1].rgba[4 * p];
      mli.layers[1].depth[p] = static_cast<float>(4.5 + 0.6 * std::sin(2 * kPi * u) * v);
      mid[0] = static_cast<float>(0.9 - 0.5 * v);
      mid[1] = static_cast<float>(0.2 + 0.3 * u);
      mid[2] = 0.1f;
      mid[3] = static_cast<float>(0.2 + 0.6 * u * (1 - v));
      float* near = &mli.layers[2].rgba[4 * p];
      mli.layers[2].depth[p] = static_cast<float>(2.6 + 0.5 * u * v);
      near[0] = 0.1f;
      near[1] = static_cast<float>(0.8 - 0.4 * u);
      near[2] = static_cast<float>(0.3 + 0.6 * v);
      near[3] = static_cast<float>(std::abs(v - 0.5) < 0.15 ? 0.0 : 0.7 * std::abs(v - 0.5) + 0.2);
    }
  return mli;
}

// Writes colour in [0, 1] (row 0 = top; value(c, p) for channel c of pixel p) as an 8-bit PNG.
template <typename Value>
void writePNG(const scene::Camera& cam, const std::string& png, Value value) {
  const std::size_t n = static_cast<std::size_t>(cam.width) * cam.height;
  vtkNew<vtkImageData> image;
  image->SetDimensions(cam.width, cam.height, 1);
  vtkNew<vtkUnsignedCharArray> rgb;
  rgb->SetNumberOfComponents(3);
  rgb->SetNumberOfTuples(static_cast<vtkIdType>(n));
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const double v = std::round(255.0 * value(c, static_cast<std::size_t>(y) * cam.width + x));
        rgb->SetTypedComponent(static_cast<vtkIdType>(cam.height - 1 - y) * cam.width + x, c,
                               static_cast<unsigned char>(v < 0 ? 0 : (v > 255 ? 255 : v)));
      }
  image->GetPointData()->SetScalars(rgb);
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputData(image);
  writer->SetFileName(png.c_str());
  writer->Write();
}

// Planar [3, H, W] colour (the rasterizer's).
void writeRGB(const std::vector<float>& colour, const scene::Camera& cam, const std::string& png) {
  const std::size_t n = static_cast<std::size_t>(cam.width) * cam.height;
  writePNG(cam, png, [&](int c, std::size_t p) { return colour[c * n + p]; });
}

// Interleaved RGB (VTK's).
void writeRGBInterleaved(const std::vector<float>& rgb, const scene::Camera& cam,
                         const std::string& png) {
  writePNG(cam, png, [&](int c, std::size_t p) { return rgb[3 * p + c]; });
}

// VTK render of the layers over `background`, as RGB rows top to bottom in [0, 1]: one actor per
// layer (simpli_vtk_render), either dual depth peeling with no peel limit and occlusion ratio 0
// (see below why not a finite limit such as 20) or the layers blended back to front in order.
std::vector<double> renderVTK(vtkPartitionedDataSetCollection* layers, const scene::Camera& cam,
                              double background, bool depthPeeling, const std::string& png) {
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(background, background, background);
  if (!depthPeeling)
    vtkrender::useLayerOrderBlending(renderer);
  else {
    renderer->SetUseDepthPeeling(1);
    // 0 = no limit: peel until no pixel changes (occlusion ratio 0). With any finite limit (2,
    // 20, 100, 1000 tried) VTK 9.2's dual depth peeling under Mesa llvmpipe dropped the middle
    // translucent layer wherever a near translucent layer covered it (PSNR 20 dB here).
    renderer->SetMaximumNumberOfPeels(0);
    renderer->SetOcclusionRatio(0.0);
  }
  vtkrender::addLayerActors(renderer, layers);
  vtkrender::setCamera(renderer->GetActiveCamera(), cam, 0.5, 50.0);
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->SetAlphaBitPlanes(1);
  window->SetSize(cam.width, cam.height);
  window->AddRenderer(renderer);
  window->Render();
  const std::vector<float> rgb = vtkrender::grabRGB(window);
  if (rgb.size() != static_cast<std::size_t>(3) * cam.width * cam.height)
    throw std::runtime_error("VTK window is not " + std::to_string(cam.width) + " x " +
                             std::to_string(cam.height));
  writeRGBInterleaved(rgb, cam, png);
  return std::vector<double>(rgb.begin(), rgb.end());
}

struct Agreement {
  double psnr = 0.0, maxError = 0.0;
  std::size_t compared = 0, pixels = 0;
};

// PSNR of the VTK render (over black; `white` tells coverage) against the rasterizer's.
Agreement compare(const std::vector<double>& black, const std::vector<double>& white,
                  const raster::RenderedLayers& r, const scene::Camera& cam) {
  const std::vector<float> colour = r.colour.toVectorF32(), opacity = r.opacity.toVectorF32();
  Agreement a;
  a.pixels = static_cast<std::size_t>(cam.width) * cam.height;
  double se = 0.0;
  for (std::size_t p = 0; p < a.pixels; ++p) {
    bool vtkCovers = true;
    for (int c = 0; c < 3; ++c)
      vtkCovers = vtkCovers && black[3 * p + c] == white[3 * p + c];
    if (!vtkCovers || !(opacity[p] > 0.999f))
      continue;
    ++a.compared;
    for (int c = 0; c < 3; ++c) {
      const double d = colour[c * a.pixels + p] - black[3 * p + c];
      se += d * d;
      a.maxError = std::max(a.maxError, std::abs(d));
    }
  }
  const double mse = a.compared ? se / (3.0 * a.compared) : 1.0;
  a.psnr = 10.0 * std::log10(1.0 / std::max(mse, 1e-20));
  return a;
}

// Reads `folder` in `meshMode`, renders it with VTK and checks it against `reference`; false
// (with a FAIL line) below 35 dB or 70 % coverage.
bool checkVTK(const std::string& name, const fs::path& folder, int meshMode, double tolerance,
              bool depthPeeling, const raster::RenderedLayers& reference, const scene::Camera& cam,
              const fs::path& out) {
  vtkNew<vtkMLIReader> reader;
  reader->SetFileName(folder.c_str());
  reader->SetMeshMode(meshMode);
  reader->SetMeshTolerance(tolerance);
  reader->Update();
  vtkPartitionedDataSetCollection* layers = reader->GetOutput();
  long long triangles = 0;
  for (unsigned int k = 0; k < layers->GetNumberOfPartitionedDataSets(); ++k)
    triangles += layers->GetPartitionedDataSet(k)->GetPartition(0)->GetNumberOfCells();
  const std::vector<double> black =
      renderVTK(layers, cam, 0.0, depthPeeling, (out / (name + "_black.png")).string());
  const std::vector<double> white =
      renderVTK(layers, cam, 1.0, depthPeeling, (out / (name + "_white.png")).string());
  const Agreement a = compare(black, white, reference, cam);
  std::printf("%-34s %9lld triangles: PSNR %.2f dB over %zu of %zu pixels (%.1f %%), max error "
              "%.4f\n",
              name.c_str(), triangles, a.psnr, a.compared, a.pixels, 100.0 * a.compared / a.pixels,
              a.maxError);
  if (a.compared < 0.7 * a.pixels) {
    std::fprintf(stderr, "FAIL: %s: only %zu of %zu pixels covered by both\n", name.c_str(),
                 a.compared, a.pixels);
    return false;
  }
  if (a.psnr < 35.0) {
    std::fprintf(stderr, "FAIL: %s: PSNR %.2f dB < 35 dB\n", name.c_str(), a.psnr);
    return false;
  }
  return true;
}

// A finer three-layer MLI with texture detail: a far slanted plane with stripes (alpha 0.6,
// which both renderers draw as opaque: the farthest fragment is opaque, spec §6.7), a
// middle curved layer with a transparent hole, a near planar layer transparent in a band.
mli::MLI texturedMLI() {
  const int W = 96, H = 72;
  mli::MLI mli = agreementMLI();
  scene::Camera ref = mli.camera;
  ref.fy = ref.fx * W / H;
  ref.width = W;
  ref.height = H;
  mli = mli::MLI::allocate(ref, 3);
  for (int i = 0; i < H; ++i)
    for (int j = 0; j < W; ++j) {
      const std::size_t p = static_cast<std::size_t>(i) * W + j;
      const double u = j / (W - 1.0), v = i / (H - 1.0);
      float* far = &mli.layers[0].rgba[4 * p];
      mli.layers[0].depth[p] = static_cast<float>(1.0 / (1.0 / 7.0 + 0.03 * u - 0.01 * v));
      far[0] = static_cast<float>(0.5 + 0.3 * std::sin(0.35 * j));
      far[1] = static_cast<float>(0.3 + 0.5 * v);
      far[2] = static_cast<float>(0.5 + 0.3 * std::cos(0.25 * i + 0.1 * j));
      far[3] = 0.6f; // drawn opaque by both renderers (the farthest fragment is opaque)
      float* mid = &mli.layers[1].rgba[4 * p];
      mli.layers[1].depth[p] = static_cast<float>(4.5 + 0.4 * std::sin(2 * kPi * u) * v);
      mid[0] = static_cast<float>(0.9 - 0.5 * v);
      mid[1] = static_cast<float>(0.5 + 0.4 * std::sin(0.5 * i));
      mid[2] = 0.1f;
      mid[3] = std::hypot(u - 0.4, v - 0.5) < 0.2 ? 0.0f : static_cast<float>(0.3 + 0.5 * u);
      float* near = &mli.layers[2].rgba[4 * p];
      mli.layers[2].depth[p] = 2.6f;
      near[0] = 0.1f;
      near[1] = static_cast<float>(0.8 - 0.4 * u);
      near[2] = static_cast<float>(0.5 + 0.4 * std::sin(0.3 * (i + j)));
      near[3] = static_cast<float>(std::abs(v - 0.5) < 0.15 ? 0.0 : 0.6);
    }
  return mli;
}

// The target: moved and turned a little from the reference, off-centre principal point,
// square pixels, W x H.
scene::Camera targetCamera(const scene::Camera& reference, int W, int H) {
  scene::Camera cam = reference;
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(0.06, Eigen::Vector3d(0.3, -1.0, 0.1).normalized()).toRotationMatrix();
  cam.R = turn * reference.R;
  cam.t =
      cam.R * -(reference.centre() + reference.R.transpose() * Eigen::Vector3d(0.25, -0.15, 0.3));
  cam.width = W;
  cam.height = H;
  cam.fx = 0.9;
  cam.fy = 0.9 * W / H;
  cam.cx = 0.5;
  cam.cy = 0.45;
  return cam;
}

} // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT_DIR\n", argv[0]);
    return 2;
  }
  if (!vtkrender::holdXDisplay()) {
    std::fprintf(stderr,
                 "FAIL: no X server (DISPLAY=%s): rendering needs one; run the tests under "
                 "xvfb-run\n",
                 std::getenv("DISPLAY") ? std::getenv("DISPLAY") : "unset");
    return 1;
  }
  try {
    const fs::path out = argv[1];
    fs::create_directories(out);
    bool ok = true;
    struct Case {
      std::string name;
      mli::MLI mli;
      int W, H;
    };
    for (const Case& c :
         {Case{"agreement", agreementMLI(), 160, 120}, Case{"textured", texturedMLI(), 320, 240}}) {
      const fs::path folder = out / (c.name + "_mli");
      mli::writeMLI(folder.string(), c.mli, mli::MLIFormat::Lossless);
      const scene::Camera cam = targetCamera(c.mli.camera, c.W, c.H);
      raster::RasterSettings perspective;
      perspective.interpolation = raster::RasterInterpolation::PerspectiveCorrect;
      const raster::RenderedLayers reference = raster::renderMLI(c.mli, cam, perspective);
      writeRGB(reference.colour.toVectorF32(), cam,
               (out / (c.name + "_opencl_perspective.png")).string());
      if (c.name == "agreement")
        ok = checkVTK(c.name + " per-texel, depth peeling", folder, vtkMLIReader::MESH_PER_TEXEL,
                      0.0, true, reference, cam, out) &&
             ok;
      ok = checkVTK(c.name + " per-texel, back to front", folder, vtkMLIReader::MESH_PER_TEXEL, 0.0,
                    false, reference, cam, out) &&
           ok;
      ok = checkVTK(c.name + " adaptive, back to front", folder, vtkMLIReader::MESH_ADAPTIVE, 0.25,
                    false, reference, cam, out) &&
           ok;
    }
    if (!ok)
      return 1;
    std::printf("agreement OK\n");
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "FAIL: %s\n", e.what());
    return 1;
  }
}
