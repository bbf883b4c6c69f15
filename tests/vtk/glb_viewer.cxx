// The GLB export seen by an independent viewer: VTK's glTF importer (vtkGLTFImporter, its own
// parser, textures and camera) renders the exported file headless, and the picture must match
// the OpenCL rasterizer's render of the MLI at the reference camera.
//
// usage: glb_viewer OUT_DIR   (needs an X server: run under xvfb-run)
//
// What is VTK's and what is ours: the importer reads the file, builds one actor per layer with
// the layer's texture and takes the file's camera (node "reference camera"). Two of its
// defaults are replaced, because they are not what glTF asks for here and not what any
// MLI viewer should do: its PBR shading of a material marked KHR_materials_unlit (shown white)
// becomes flat unlit shading of the same texture, and VTK 9.2's order-independent translucency
// becomes blending in an order, farthest actor first (SIMPLILayerActors.h explains both), as
// glTF viewers sort blended objects by distance.
//
// Checked for the per-texel and the adaptive mesh: PSNR >= 30 dB over the pixels both cover,
// coverage >= 70 %. Writes the images (VTK | rasterizer) as PNGs into OUT_DIR.
#include "SIMPLILayerActors.h"

#include <vtkActor.h>
#include <vtkActorCollection.h>
#include <vtkCamera.h>
#include <vtkGLTFImporter.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTexture.h>
#include <vtkUnsignedCharArray.h>

#include "simpli/model/mli/glb.h"
#include "simpli/model/raster/render_mli.h"

#include <Eigen/Geometry>
#include <X11/Xlib.h>

#include <algorithm>
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

constexpr int kW = 48, kH = 36;             // MLI grid
constexpr int kImageW = 192, kImageH = 144; // render size

// Three layers: a far opaque slanted plane with a gradient, a wavy middle layer with smooth
// alpha, a near plane transparent in a band. The reference camera is rotated and moved (the
// file's root matrix must undo that) with a centred principal point (glTF has none).
mli::MLI viewerMLI() {
  scene::Camera ref;
  ref.R = Eigen::AngleAxisd(0.08, Eigen::Vector3d(0.2, 1.0, 0.1).normalized()).toRotationMatrix();
  ref.t = Eigen::Vector3d(0.3, -0.2, 0.5);
  ref.fx = 0.9;
  ref.fy = 0.9 * kW / kH;
  ref.cx = ref.cy = 0.5;
  ref.width = kW;
  ref.height = kH;
  mli::MLI m = mli::MLI::allocate(ref, 3);
  for (int i = 0; i < kH; ++i)
    for (int j = 0; j < kW; ++j) {
      const std::size_t p = std::size_t(i) * kW + j;
      const double u = j / (kW - 1.0), v = i / (kH - 1.0);
      float* c = &m.layers[0].rgba[4 * p];
      m.layers[0].depth[p] = float(8.0 + 3.0 * u - 1.0 * v);
      c[0] = float(0.2 + 0.6 * u);
      c[1] = float(0.3 + 0.5 * v);
      c[2] = float(0.5 + 0.4 * std::sin(3.0 * u + 2.0 * v));
      c[3] = 1.0f;
      c = &m.layers[1].rgba[4 * p];
      m.layers[1].depth[p] = float(4.5 + 0.5 * std::sin(6.0 * u) * v);
      c[0] = float(0.9 - 0.5 * v);
      c[1] = float(0.2 + 0.3 * u);
      c[2] = 0.1f;
      c[3] = float(0.2 + 0.6 * u * (1 - v));
      c = &m.layers[2].rgba[4 * p];
      m.layers[2].depth[p] = 2.6f;
      c[0] = 0.1f;
      c[1] = float(0.8 - 0.4 * u);
      c[2] = float(0.3 + 0.6 * v);
      c[3] = float(std::abs(v - 0.5) < 0.15 ? 0.0 : 0.5);
    }
  return m;
}

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

// The file rendered by VTK's importer as described above; RGB in [0, 1], row 0 at the top.
std::vector<float> renderWithImporter(const std::string& file, const double background[3]) {
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->SetSize(kImageW, kImageH);
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(background[0], background[1], background[2]);
  window->AddRenderer(renderer);
  vtkNew<vtkGLTFImporter> importer;
  importer->SetFileName(file.c_str());
  importer->SetRenderWindow(window);
  importer->SetCamera(0);
  importer->Update();
  vtkActorCollection* actors = renderer->GetActors();
  std::vector<vtkSmartPointer<vtkActor>> inOrder;
  actors->InitTraversal();
  while (vtkActor* a = actors->GetNextActor())
    inOrder.emplace_back(a);
  if (inOrder.empty())
    throw std::runtime_error("the importer made no actors of " + file);
  for (const auto& a : inOrder) {
    renderer->RemoveActor(a);
    vtkProperty* p = a->GetProperty();
    vtkTexture* albedo = p->GetTexture("albedoTex");
    if (!albedo)
      throw std::runtime_error("a layer actor has no base colour texture");
    albedo->SetUseSRGBColorSpace(false); // the PNG holds the texel values themselves
    a->SetTexture(albedo);
    p->RemoveAllTextures();
    p->SetInterpolationToFlat();
    p->LightingOff();
    p->SetAmbient(1.0);
    p->SetDiffuse(0.0);
    a->ForceTranslucentOn();
  }
  // glTF leaves the draw order of blended primitives to the viewer; like three.js and most
  // others, draw them farthest first by the distance of their bounding-box centre from the
  // camera (the importer's own actor list is in no such order).
  double eye[3];
  renderer->GetActiveCamera()->GetPosition(eye);
  auto distance = [&](vtkActor* a) {
    const double* b = a->GetBounds();
    const double c[3] = {0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5])};
    return std::hypot(c[0] - eye[0], c[1] - eye[1], c[2] - eye[2]);
  };
  std::sort(inOrder.begin(), inOrder.end(),
            [&](const auto& a, const auto& b) { return distance(a) > distance(b); });
  for (const auto& a : inOrder)
    renderer->AddActor(a);
  vtkrender::useLayerOrderBlending(renderer);
  window->Render();
  return vtkrender::grabRGB(window);
}

void writePNG(const std::string& path, const std::vector<float>& left,
              const std::vector<float>& right) {
  vtkNew<vtkImageData> image;
  image->SetDimensions(2 * kImageW, kImageH, 1);
  vtkNew<vtkUnsignedCharArray> rgb;
  rgb->SetNumberOfComponents(3);
  rgb->SetNumberOfTuples(2 * kImageW * kImageH);
  for (int y = 0; y < kImageH; ++y)
    for (int x = 0; x < 2 * kImageW; ++x)
      for (int c = 0; c < 3; ++c) {
        const std::vector<float>& src = x < kImageW ? left : right;
        const float v = src[3 * (std::size_t(y) * kImageW + x % kImageW) + c];
        // vtkImageData row 0 is the bottom.
        rgb->SetTypedComponent(
            (kImageH - 1 - y) * 2 * kImageW + x, c,
            static_cast<unsigned char>(std::lround(255 * std::clamp(v, 0.f, 1.f))));
      }
  image->GetPointData()->SetScalars(rgb);
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(image);
  writer->Write();
}

// PSNR (peak 1) of the importer's render against the rasterizer's over the pixels both cover:
// the importer's where its renders over black and white agree, the rasterizer's where its
// opacity is > 0.999.
bool check(const std::string& name, const mli::MLI& m, const mli::GlbOptions& options,
           const fs::path& out) {
  const std::string file = (out / (name + ".glb")).string();
  const mli::GlbSummary summary = mli::writeGlb(m, file, options);
  const double black[3] = {0, 0, 0}, white[3] = {1, 1, 1};
  const std::vector<float> vtkBlack = renderWithImporter(file, black);
  const std::vector<float> vtkWhite = renderWithImporter(file, white);

  scene::Camera target = m.camera;
  target.width = kImageW;
  target.height = kImageH;
  raster::RasterSettings settings;
  settings.interpolation = raster::RasterInterpolation::PerspectiveCorrect; // as OpenGL
  const raster::RenderedLayers r = raster::renderMLI(m, target, settings);
  const std::vector<float> colour = r.colour.toVectorF32(), opacity = r.opacity.toVectorF32();
  const std::size_t n = std::size_t(kImageW) * kImageH;
  std::vector<float> raster(3 * n);
  double se = 0;
  std::size_t compared = 0;
  for (std::size_t p = 0; p < n; ++p) {
    bool covered = opacity[p] > 0.999f;
    for (int c = 0; c < 3; ++c) {
      raster[3 * p + c] = colour[c * n + p];
      covered = covered && std::abs(vtkBlack[3 * p + c] - vtkWhite[3 * p + c]) < 1.5f / 255;
    }
    if (!covered)
      continue;
    ++compared;
    for (int c = 0; c < 3; ++c)
      se += std::pow(double(vtkBlack[3 * p + c]) - raster[3 * p + c], 2);
  }
  writePNG((out / (name + ".png")).string(), vtkBlack, raster);
  const double psnr =
      10 * std::log10(1.0 / std::max(se / std::max<std::size_t>(1, 3 * compared), 1e-20));
  std::printf("%s: %d layers, %zu triangles, %.1f kB; importer vs rasterizer %.2f dB over %zu of "
              "%zu pixels (%.0f %%)\n",
              name.c_str(), summary.layers, summary.triangles, summary.bytes / 1e3, psnr, compared,
              n, 100.0 * compared / n);
  bool ok = true;
  if (psnr < 30.0) {
    std::fprintf(stderr, "FAIL: %s: PSNR %.2f dB < 30 dB\n", name.c_str(), psnr);
    ok = false;
  }
  if (compared < n * 7 / 10) {
    std::fprintf(stderr, "FAIL: %s: only %zu of %zu pixels covered by both\n", name.c_str(),
                 compared, n);
    ok = false;
  }
  return ok;
}

} // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT_DIR\n", argv[0]);
    return 2;
  }
  Display* display = holdXDisplay();
  if (!display) {
    std::fprintf(stderr, "FAIL: no X server (DISPLAY unset or unreachable); run under xvfb-run\n");
    return 1;
  }
  try {
    const fs::path out = argv[1];
    fs::create_directories(out);
    const mli::MLI m = viewerMLI();
    mli::GlbOptions perTexel, adaptive;
    adaptive.layerMesh = mli::adaptiveGlbMesh({});
    bool ok = check("per_texel", m, perTexel, out);
    ok = check("adaptive", m, adaptive, out) && ok;
    XCloseDisplay(display);
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "FAIL: %s\n", e.what());
    return 1;
  }
}
