// Agreement of the OpenCL rasterizer (perspective-correct interpolation) with VTK's OpenGL
// rendering of the same MLI layer meshes (as vtkMLIReader builds them) from the same camera.
//
// usage: render_agreement OUT_DIR   (needs an X server: run under xvfb-run)
//
// VTK side: one actor per layer, RGBA point scalars used directly (MapScalars off, i.e. direct
// colour mode), unlit (ambient 1, diffuse 0), dual depth peeling with no peel limit and occlusion
// ratio 0 (see renderVTK for why not a finite limit such as 20), no multisampling, window size =
// image size, the camera converted from the simpli intrinsics/extrinsics: position = centre, focal
// point one unit along +z_cam, view up = -y_cam (OpenCV's y points down), view angle = 2 atan(0.5 /
// fy') (vertical), window centre (1 - 2 cx', 2 cy' - 1) for the principal point (vtkCamera puts the
// optical axis at NDC -windowCentre; relative v grows downwards while NDC y grows upwards). Pixels
// are square (fx' W = fy' H), which a vtkCamera requires.
//
// Comparison: PSNR (peak 1) over the pixels both renderers cover. VTK coverage = pixels that
// come out the same over a black and a white background; rasterizer coverage = opacity > 0.999.
// The far layer has alpha 1 everywhere, so the rasterizer's "farthest fragment is opaque" rule
// (spec §6.7) changes nothing where the far layer is hit, and both renderers
// composite the same fragments. Fails below 35 dB or when fewer than 70 % of the pixels are
// compared. Writes both images as PNGs into OUT_DIR.
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
#include <X11/Xlib.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>
#include <thread>
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

void setVTKCamera(vtkCamera* vc, const scene::Camera& c) {
  const Eigen::Vector3d C = c.centre();
  const Eigen::Vector3d forward = c.R.row(2).transpose(), down = c.R.row(1).transpose();
  const Eigen::Vector3d F = C + forward;
  vc->SetPosition(C.x(), C.y(), C.z());
  vc->SetFocalPoint(F.x(), F.y(), F.z());
  vc->SetViewUp(-down.x(), -down.y(), -down.z());
  vc->SetViewAngle(2.0 * std::atan(0.5 / c.fy) * 180.0 / kPi);
  vc->SetWindowCenter(1.0 - 2.0 * c.cx, 2.0 * c.cy - 1.0);
  vc->SetClippingRange(0.5, 50.0);
}

// VTK render of the layers over `background`, as RGB rows top to bottom in [0, 1].
std::vector<double> renderVTK(vtkPartitionedDataSetCollection* layers, const scene::Camera& cam,
                              double background, const std::string& png) {
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(background, background, background);
  renderer->SetUseDepthPeeling(1);
  // 0 = no limit: peel until no pixel changes (occlusion ratio 0). With any finite limit (2, 20,
  // 100, 1000 tried) VTK 9.2's dual depth peeling under Mesa llvmpipe dropped the middle
  // translucent layer wherever a near translucent layer covered it (PSNR 20 dB here).
  renderer->SetMaximumNumberOfPeels(0);
  renderer->SetOcclusionRatio(0.0);
  for (unsigned int k = 0; k < layers->GetNumberOfPartitionedDataSets(); ++k) {
    auto* pd = vtkPolyData::SafeDownCast(layers->GetPartitionedDataSet(k)->GetPartition(0));
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(pd);
    mapper->ScalarVisibilityOn();
    mapper->SetScalarModeToUsePointData();
    mapper->SetColorModeToDirectScalars(); // RGBA as is (ParaView: MapScalars off)
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->SetAmbient(1.0);
    actor->GetProperty()->SetDiffuse(0.0);
    actor->GetProperty()->SetSpecular(0.0);
    actor->GetProperty()->LightingOff();
    renderer->AddActor(actor);
  }
  setVTKCamera(renderer->GetActiveCamera(), cam);
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->SetAlphaBitPlanes(1);
  window->SetSize(cam.width, cam.height);
  window->AddRenderer(renderer);
  window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkImageData* image = grab->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  if (dims[0] != cam.width || dims[1] != cam.height)
    throw std::runtime_error("VTK window is " + std::to_string(dims[0]) + " x " +
                             std::to_string(dims[1]));
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputData(image);
  writer->SetFileName(png.c_str());
  writer->Write();
  vtkDataArray* scalars = image->GetPointData()->GetScalars();
  std::vector<double> rgb(static_cast<std::size_t>(3) * cam.width * cam.height);
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x)
      for (int c = 0; c < 3; ++c)
        rgb[3 * (static_cast<std::size_t>(y) * cam.width + x) + c] =
            scalars->GetComponent(static_cast<vtkIdType>(cam.height - 1 - y) * cam.width + x, c) /
            255.0;
  return rgb;
}

// Writes planar [3, H, W] colour in [0, 1] (row 0 = top) as an 8-bit PNG.
void writeRGB(const std::vector<float>& colour, const scene::Camera& cam, const std::string& png) {
  const std::size_t n = static_cast<std::size_t>(cam.width) * cam.height;
  vtkNew<vtkImageData> image;
  image->SetDimensions(cam.width, cam.height, 1);
  vtkNew<vtkUnsignedCharArray> rgb;
  rgb->SetNumberOfComponents(3);
  rgb->SetNumberOfTuples(static_cast<vtkIdType>(n));
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const double v =
            std::round(255.0 * colour[c * n + static_cast<std::size_t>(y) * cam.width + x]);
        rgb->SetTypedComponent(static_cast<vtkIdType>(cam.height - 1 - y) * cam.width + x, c,
                               static_cast<unsigned char>(v < 0 ? 0 : (v > 255 ? 255 : v)));
      }
  image->GetPointData()->SetScalars(rgb);
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputData(image);
  writer->SetFileName(png.c_str());
  writer->Write();
}

// Connects to $DISPLAY (retrying for up to 30 s) and keeps the connection until exit: Xvfb
// resets when its last client leaves and refuses clients meanwhile, and VTK aborts the process
// on a refused connection (see pv_layer_grid.py). Null when there is no display.
Display* holdXDisplay() {
  if (!std::getenv("DISPLAY"))
    return nullptr;
  for (int attempt = 0; attempt < 600; ++attempt) {
    if (Display* d = XOpenDisplay(nullptr))
      return d;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return nullptr;
}

} // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT_DIR\n", argv[0]);
    return 2;
  }
  Display* display = holdXDisplay();
  if (!display) {
    std::fprintf(stderr,
                 "FAIL: no X server (DISPLAY=%s): rendering needs one; run the tests under "
                 "xvfb-run\n",
                 std::getenv("DISPLAY") ? std::getenv("DISPLAY") : "unset");
    return 1;
  }
  try {
    const fs::path out = argv[1];
    fs::create_directories(out);
    const mli::MLI mli = agreementMLI();
    mli::writeMLI((out / "agreement_mli").string(), mli, mli::MLIFormat::Lossless);
    vtkNew<vtkMLIReader> reader;
    reader->SetFileName((out / "agreement_mli").c_str());
    reader->Update();
    vtkPartitionedDataSetCollection* layers = reader->GetOutput();
    if (layers->GetNumberOfPartitionedDataSets() != 3) {
      std::fprintf(stderr, "FAIL: the MLI reader gave %u layers\n",
                   layers->GetNumberOfPartitionedDataSets());
      return 1;
    }

    // Target: moved and turned a little, off-centre principal point, square pixels.
    scene::Camera cam = mli.camera;
    const Eigen::Matrix3d turn =
        Eigen::AngleAxisd(0.06, Eigen::Vector3d(0.3, -1.0, 0.1).normalized()).toRotationMatrix();
    cam.R = turn * mli.camera.R;
    cam.t = cam.R *
            -(mli.camera.centre() + mli.camera.R.transpose() * Eigen::Vector3d(0.25, -0.15, 0.3));
    cam.width = 160;
    cam.height = 120;
    cam.fx = 0.9;
    cam.fy = 0.9 * 160.0 / 120.0;
    cam.cx = 0.5;
    cam.cy = 0.45;

    const std::vector<double> black = renderVTK(layers, cam, 0.0, (out / "vtk_black.png").string());
    const std::vector<double> white = renderVTK(layers, cam, 1.0, (out / "vtk_white.png").string());

    double best = 0.0;
    for (raster::RasterInterpolation interp : {raster::RasterInterpolation::PerspectiveCorrect,
                                               raster::RasterInterpolation::ScreenLinear}) {
      raster::RasterSettings s;
      s.interpolation = interp;
      const raster::RenderedLayers r = raster::renderMLI(mli, cam, s);
      const std::vector<float> colour = r.colour.toVectorF32(), opacity = r.opacity.toVectorF32();
      const std::size_t n = static_cast<std::size_t>(cam.width) * cam.height;
      writeRGB(colour, cam,
               (out / (interp == raster::RasterInterpolation::PerspectiveCorrect
                           ? "opencl_perspective.png"
                           : "opencl_screen_linear.png"))
                   .string());
      double se = 0.0, maxErr = 0.0;
      std::size_t count = 0;
      for (std::size_t p = 0; p < n; ++p) {
        bool vtkCovers = true;
        for (int c = 0; c < 3; ++c)
          vtkCovers = vtkCovers && black[3 * p + c] == white[3 * p + c];
        if (!vtkCovers || !(opacity[p] > 0.999f))
          continue;
        ++count;
        for (int c = 0; c < 3; ++c) {
          const double d = colour[c * n + p] - black[3 * p + c];
          se += d * d;
          maxErr = std::max(maxErr, std::abs(d));
        }
      }
      const double mse = count ? se / (3.0 * count) : 1.0;
      const double psnr = 10.0 * std::log10(1.0 / std::max(mse, 1e-20));
      const bool perspective = interp == raster::RasterInterpolation::PerspectiveCorrect;
      std::printf("%s vs VTK OpenGL: PSNR %.2f dB over %zu of %zu pixels (%.1f %%), max error "
                  "%.4f\n",
                  perspective ? "perspective-correct" : "screen-linear      ", psnr, count, n,
                  100.0 * count / n, maxErr);
      if (perspective) {
        best = psnr;
        if (count < 0.7 * n) {
          std::fprintf(stderr, "FAIL: only %zu of %zu pixels covered by both\n", count, n);
          return 1;
        }
      }
    }
    if (best < 35.0) {
      std::fprintf(stderr, "FAIL: PSNR %.2f dB < 35 dB\n", best);
      return 1;
    }
    std::printf("agreement OK\n");
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "FAIL: %s\n", e.what());
    return 1;
  }
}
