// simpli::MLI <-> vtkPartitionedDataSetCollection (see SIMPLIMLIToVTK.h for the layout).
#include "SIMPLIMLIToVTK.h"

#include <vtkCellArray.h>
#include <vtkCompositeDataSet.h>
#include <vtkDataArray.h>
#include <vtkDataAssembly.h>
#include <vtkDataSet.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkIntArray.h>
#include <vtkPartitionedDataSet.h>
#include <vtkPartitionedDataSetCollection.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include "simpli/error.h"
#include "simpli/model/mli/adaptive_mesh.h"
#include "simpli/model/mli/mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

namespace simpli::vtkmli {

namespace {

vtkSmartPointer<vtkFloatArray> floatArray(const char* name, int components, vtkIdType tuples,
                                          const float* values) {
  auto a = vtkSmartPointer<vtkFloatArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(tuples);
  std::copy(values, values + tuples * components, a->GetPointer(0));
  return a;
}

// Layer k's corner-grid vertices back-projected in double (mli::mliVertex), point i W + j.
vtkSmartPointer<vtkDoubleArray> doublePoints(const mli::MLI& mli, int k) {
  const int W = mli.width(), H = mli.height();
  const std::vector<float>& depth = mli.layers[static_cast<std::size_t>(k)].depth;
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName("Points");
  array->SetNumberOfComponents(3);
  array->SetNumberOfTuples(static_cast<vtkIdType>(W) * H);
  double* out = array->GetPointer(0);
  for (int i = 0; i < H; ++i)
    for (int j = 0; j < W; ++j) {
      const std::size_t p = static_cast<std::size_t>(i) * W + j;
      const Eigen::Vector3d x = mli::mliVertex(mli.camera, i, j, depth[p]);
      out[3 * p + 0] = x.x();
      out[3 * p + 1] = x.y();
      out[3 * p + 2] = x.z();
    }
  return array;
}

vtkSmartPointer<vtkIntArray> intValue(const char* name, int value) {
  auto a = vtkSmartPointer<vtkIntArray>::New();
  a->SetName(name);
  a->SetNumberOfTuples(1);
  a->SetValue(0, value);
  return a;
}

// The array `name` of `fd` with exactly `components` components and one tuple.
vtkDataArray* requireFieldArray(vtkFieldData* fd, const char* name, int components,
                                const std::string& context) {
  vtkDataArray* a = fd ? fd->GetArray(name) : nullptr;
  if (!a) {
    const bool present = fd && fd->GetAbstractArray(name);
    fail(context, ": field data array \"", name, "\" is ",
         present ? "not a numeric array" : "missing",
         " (the reference camera travels as field data: CameraIntrinsics, CameraExtrinsics, "
         "CameraImageSize)");
  }
  if (a->GetNumberOfComponents() != components || a->GetNumberOfTuples() != 1)
    fail(context, ": field data array \"", name, "\" has ", a->GetNumberOfTuples(), " tuple(s) of ",
         a->GetNumberOfComponents(), " component(s), expected 1 tuple of ", components);
  return a;
}

// Names of the point arrays of `ds`, for messages about a missing one.
std::string pointArrayNames(vtkDataSet* ds) {
  std::ostringstream os;
  vtkPointData* pd = ds->GetPointData();
  for (int i = 0; i < pd->GetNumberOfArrays(); ++i) {
    const char* n = pd->GetArrayName(i);
    os << (i ? ", " : "") << (n ? n : "(unnamed)");
  }
  const std::string s = os.str();
  return s.empty() ? "none" : s;
}

// `a` (named `name`, from `kind` data) as floats: `components` components, `tuples` tuples.
std::vector<float> requireFloats(vtkDataArray* a, const char* kind, const char* name,
                                 int components, vtkIdType tuples, const char* perWhat,
                                 const std::string& where) {
  if (a->GetNumberOfComponents() != components)
    fail(where, ": ", kind, " array \"", name, "\" has ", a->GetNumberOfComponents(),
         " component(s), expected ", components);
  if (a->GetNumberOfTuples() != tuples)
    fail(where, ": ", kind, " array \"", name, "\" has ", a->GetNumberOfTuples(),
         " tuples, expected ", tuples, " (", perWhat, ")");
  std::vector<float> out(static_cast<std::size_t>(tuples) * components);
  if (auto* f = vtkFloatArray::FastDownCast(a)) {
    std::copy(f->GetPointer(0), f->GetPointer(0) + out.size(), out.begin());
  } else {
    for (vtkIdType t = 0; t < tuples; ++t)
      for (int c = 0; c < components; ++c)
        out[static_cast<std::size_t>(t * components + c)] =
            static_cast<float>(a->GetComponent(t, c));
  }
  return out;
}

// Point array `name` of layer `ds`: `components` components, `tuples` tuples, as floats.
std::vector<float> requirePointArray(vtkDataSet* ds, const char* name, int components,
                                     vtkIdType tuples, const std::string& where) {
  vtkDataArray* a = ds->GetPointData()->GetArray(name);
  if (!a)
    fail(where, ": point data array \"", name,
         "\" is missing (arrays present: ", pointArrayNames(ds), ")");
  return requireFloats(a, "point data", name, components, tuples, "one per point", where);
}

// Texture array `name` of an adaptive layer's field data, rows flipped back to MLI order
// (row 0 = top).
std::vector<float> requireTextureArray(vtkFieldData* fd, const char* name, int components, int W,
                                       int H, const std::string& where) {
  vtkDataArray* a = fd->GetArray(name);
  if (!a)
    fail(where, ": field data array \"", name, "\" is missing (an adaptive layer, with ",
         kTextureDepthArray, ", carries ", kTextureColorArray, ", ", kTextureAlphaArray, " and ",
         kTextureDepthArray, ")");
  const std::vector<float> image = requireFloats(
      a, "field data", name, components, static_cast<vtkIdType>(W) * H, "one per texel", where);
  std::vector<float> out(image.size());
  const std::size_t row = static_cast<std::size_t>(W) * components;
  for (int y = 0; y < H; ++y)
    std::copy_n(image.begin() + static_cast<std::ptrdiff_t>(row * y), row,
                out.begin() + static_cast<std::ptrdiff_t>(row * (H - 1 - y)));
  return out;
}

// The texels of layer `ds` in either form (see the header).
mli::MLILayer layerTexels(vtkDataSet* ds, int W, int H, const std::string& where) {
  const vtkIdType texels = static_cast<vtkIdType>(W) * H;
  vtkFieldData* fd = ds->GetFieldData();
  mli::MLILayer layer;
  std::vector<float> rgb, a;
  if (fd && fd->GetArray(kTextureDepthArray)) {
    layer.depth = requireTextureArray(fd, kTextureDepthArray, 1, W, H, where);
    rgb = requireTextureArray(fd, kTextureColorArray, 3, W, H, where);
    a = requireTextureArray(fd, kTextureAlphaArray, 1, W, H, where);
  } else {
    if (ds->GetNumberOfPoints() != texels)
      fail(where, ": ", ds->GetNumberOfPoints(), " points, expected ", W, " x ", H, " = ", texels,
           " (one per texel of the ", kImageSizeArray, " grid)");
    layer.depth = requirePointArray(ds, kDepthArray, 1, texels, where);
    rgb = requirePointArray(ds, kColorArray, 3, texels, where);
    a = requirePointArray(ds, kAlphaArray, 1, texels, where);
  }
  layer.rgba.resize(static_cast<std::size_t>(texels) * 4);
  for (std::size_t p = 0; p < static_cast<std::size_t>(texels); ++p) {
    for (std::size_t c = 0; c < 3; ++c)
      layer.rgba[4 * p + c] = rgb[3 * p + c];
    layer.rgba[4 * p + 3] = a[p];
  }
  return layer;
}

} // namespace

std::string layerName(int k) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "Layer%02d", k);
  return buf;
}

void addCameraFieldData(vtkFieldData* fd, const scene::Camera& camera) {
  auto intr = vtkSmartPointer<vtkDoubleArray>::New();
  intr->SetName(kIntrinsicsArray);
  intr->SetNumberOfComponents(4);
  intr->SetComponentName(0, "fx");
  intr->SetComponentName(1, "fy");
  intr->SetComponentName(2, "cx");
  intr->SetComponentName(3, "cy");
  const double k[4] = {camera.fx, camera.fy, camera.cx, camera.cy};
  intr->InsertNextTuple(k);

  auto extr = vtkSmartPointer<vtkDoubleArray>::New();
  extr->SetName(kExtrinsicsArray);
  extr->SetNumberOfComponents(12);
  double e[12];
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      e[4 * r + c] = camera.R(r, c);
    e[4 * r + 3] = camera.t(r);
  }
  extr->InsertNextTuple(e);

  auto size = vtkSmartPointer<vtkIntArray>::New();
  size->SetName(kImageSizeArray);
  size->SetNumberOfComponents(2);
  size->SetComponentName(0, "width");
  size->SetComponentName(1, "height");
  const int wh[2] = {camera.width, camera.height};
  size->InsertNextTypedTuple(wh);

  // AddArray replaces an array of the same name.
  fd->AddArray(intr);
  fd->AddArray(extr);
  fd->AddArray(size);
}

scene::Camera cameraFromFieldData(vtkFieldData* fd, const std::string& context) {
  vtkDataArray* intr = requireFieldArray(fd, kIntrinsicsArray, 4, context);
  vtkDataArray* extr = requireFieldArray(fd, kExtrinsicsArray, 12, context);
  vtkDataArray* size = requireFieldArray(fd, kImageSizeArray, 2, context);
  scene::Camera cam;
  cam.fx = intr->GetComponent(0, 0);
  cam.fy = intr->GetComponent(0, 1);
  cam.cx = intr->GetComponent(0, 2);
  cam.cy = intr->GetComponent(0, 3);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      cam.R(r, c) = extr->GetComponent(0, 4 * r + c);
    cam.t(r) = extr->GetComponent(0, 4 * r + 3);
  }
  for (int c = 0; c < 2; ++c) {
    const double v = size->GetComponent(0, c);
    if (!(v >= 2 && v <= 65535) || std::floor(v) != v)
      fail(context, ": field data array \"", kImageSizeArray, "\" ", c ? "height" : "width", " = ",
           v, ", expected an integer in [2, 65535]");
  }
  cam.width = static_cast<int>(size->GetComponent(0, 0));
  cam.height = static_cast<int>(size->GetComponent(0, 1));
  mli::validateMLICamera(cam, context + " (field data " + kIntrinsicsArray + ", " +
                                  kExtrinsicsArray + ")");
  return cam;
}

namespace {

// Triangles as a cell array; offsets and connectivity are filled directly (millions of them).
vtkSmartPointer<vtkCellArray> triangleCells(const std::vector<std::int32_t>& triangles) {
  const vtkIdType nt = static_cast<vtkIdType>(triangles.size() / 3);
  auto offsets = vtkSmartPointer<vtkIdTypeArray>::New();
  offsets->SetNumberOfTuples(nt + 1);
  for (vtkIdType t = 0; t <= nt; ++t)
    offsets->SetValue(t, 3 * t);
  auto connectivity = vtkSmartPointer<vtkIdTypeArray>::New();
  connectivity->SetNumberOfTuples(3 * nt);
  for (vtkIdType i = 0; i < 3 * nt; ++i)
    connectivity->SetValue(i, triangles[static_cast<std::size_t>(i)]);
  auto polys = vtkSmartPointer<vtkCellArray>::New();
  polys->SetData(offsets, connectivity);
  return polys;
}

unsigned char toByte(float c) {
  // Rounded, not truncated: q/255 read from an 8-bit file maps back to q exactly.
  return static_cast<unsigned char>(std::lround(255.0 * c));
}

vtkSmartPointer<vtkPolyData> perTexelPolyData(const mli::MLI& mli, int k,
                                              const LayerOptions& options) {
  mli::MLIMeshOptions meshOptions;
  if (options.dropTransparentTriangles)
    meshOptions.dropAlphaBelow = static_cast<float>(options.alphaThreshold);
  const mli::MLIMesh mesh = mli::buildLayerMesh(mli, k, meshOptions);
  const vtkIdType n = static_cast<vtkIdType>(mesh.numPoints());

  auto points = vtkSmartPointer<vtkPoints>::New();
  if (options.doublePrecisionPoints)
    points->SetData(doublePoints(mli, k));
  else
    points->SetData(floatArray("Points", 3, n, mesh.points.data()));

  auto rgba = vtkSmartPointer<vtkUnsignedCharArray>::New();
  rgba->SetName(kRGBAArray);
  rgba->SetNumberOfComponents(4);
  rgba->SetNumberOfTuples(n);
  auto color = vtkSmartPointer<vtkFloatArray>::New();
  color->SetName(kColorArray);
  color->SetNumberOfComponents(3);
  color->SetNumberOfTuples(n);
  auto alpha = vtkSmartPointer<vtkFloatArray>::New();
  alpha->SetName(kAlphaArray);
  alpha->SetNumberOfTuples(n);
  auto tcoords = vtkSmartPointer<vtkFloatArray>::New();
  tcoords->SetName(kTCoordsArray);
  tcoords->SetNumberOfComponents(2);
  tcoords->SetNumberOfTuples(n);
  unsigned char* bytes = rgba->GetPointer(0);
  float* rgb = color->GetPointer(0);
  float* a = alpha->GetPointer(0);
  float* uv = tcoords->GetPointer(0);
  for (vtkIdType p = 0; p < n; ++p) {
    const float* src = mesh.rgba.data() + 4 * p;
    for (int c = 0; c < 4; ++c)
      bytes[4 * p + c] = toByte(src[c]);
    if (k == 0 && options.opaqueFarthestLayer)
      bytes[4 * p + 3] = 255; // the farthest layer is opaque on display (SIMPLIMLIToVTK.h)
    rgb[3 * p + 0] = src[0];
    rgb[3 * p + 1] = src[1];
    rgb[3 * p + 2] = src[2];
    a[p] = src[3];
    uv[2 * p + 0] = mesh.uv[static_cast<std::size_t>(2 * p)];
    uv[2 * p + 1] = 1.0f - mesh.uv[static_cast<std::size_t>(2 * p + 1)];
  }

  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(points);
  pd->SetPolys(triangleCells(mesh.triangles));
  vtkPointData* pointData = pd->GetPointData();
  pointData->SetScalars(rgba);
  pointData->AddArray(color);
  pointData->AddArray(alpha);
  pointData->AddArray(floatArray(kDepthArray, 1, n, mesh.depth.data()));
  pointData->SetTCoords(tcoords);
  return pd;
}

// The layer's texels in vtkImageData order (row 0 = MLI row H - 1) as field data arrays.
void addTextureFieldData(vtkFieldData* fd, const mli::MLI& mli, int k, bool opaque) {
  const int W = mli.width(), H = mli.height();
  const vtkIdType n = static_cast<vtkIdType>(mli.texels());
  const mli::MLILayer& layer = mli.layers[static_cast<std::size_t>(k)];
  auto rgba = vtkSmartPointer<vtkUnsignedCharArray>::New();
  rgba->SetName(kTextureRGBAArray);
  rgba->SetNumberOfComponents(4);
  rgba->SetNumberOfTuples(n);
  auto color = vtkSmartPointer<vtkFloatArray>::New();
  color->SetName(kTextureColorArray);
  color->SetNumberOfComponents(3);
  color->SetNumberOfTuples(n);
  auto alpha = vtkSmartPointer<vtkFloatArray>::New();
  alpha->SetName(kTextureAlphaArray);
  alpha->SetNumberOfTuples(n);
  auto depth = vtkSmartPointer<vtkFloatArray>::New();
  depth->SetName(kTextureDepthArray);
  depth->SetNumberOfTuples(n);
  for (int y = 0; y < H; ++y) {
    const std::size_t row = static_cast<std::size_t>(H - 1 - y) * W;
    for (int x = 0; x < W; ++x) {
      const std::size_t src = row + x;
      const vtkIdType dst = static_cast<vtkIdType>(y) * W + x;
      const float* c = &layer.rgba[4 * src];
      for (int ch = 0; ch < 4; ++ch)
        rgba->SetValue(4 * dst + ch, toByte(c[ch]));
      if (opaque)
        rgba->SetValue(4 * dst + 3, 255); // the farthest layer, see SIMPLIMLIToVTK.h
      for (int ch = 0; ch < 3; ++ch)
        color->SetValue(3 * dst + ch, c[ch]);
      alpha->SetValue(dst, c[3]);
      depth->SetValue(dst, layer.depth[src]);
    }
  }
  auto size = vtkSmartPointer<vtkIntArray>::New();
  size->SetName(kTextureSizeArray);
  size->SetNumberOfComponents(2);
  const int wh[2] = {W, H};
  size->InsertNextTypedTuple(wh);
  fd->AddArray(rgba);
  fd->AddArray(color);
  fd->AddArray(alpha);
  fd->AddArray(depth);
  fd->AddArray(size);
}

vtkSmartPointer<vtkPolyData> adaptivePolyData(const mli::MLI& mli, int k,
                                              const LayerOptions& options) {
  mli::AdaptiveMeshOptions meshOptions;
  meshOptions.tolerancePixels = options.meshTolerance;
  meshOptions.alphaThreshold = static_cast<float>(options.alphaThreshold);
  const mli::AdaptiveLayerMesh mesh = mli::buildAdaptiveLayerMesh(mli, k, meshOptions);
  const vtkIdType n = static_cast<vtkIdType>(mesh.numPoints());
  const double W = mli.width(), H = mli.height();

  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetData(floatArray("Points", 3, n, mesh.points.data()));
  auto tcoords = vtkSmartPointer<vtkFloatArray>::New();
  tcoords->SetName(kTCoordsArray);
  tcoords->SetNumberOfComponents(2);
  tcoords->SetNumberOfTuples(n);
  for (vtkIdType p = 0; p < n; ++p) {
    tcoords->SetValue(2 * p, static_cast<float>((mesh.grid[2 * p] + 0.5) / W));
    tcoords->SetValue(2 * p + 1, static_cast<float>(1.0 - (mesh.grid[2 * p + 1] + 0.5) / H));
  }

  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(points);
  pd->SetPolys(triangleCells(mesh.triangles));
  pd->GetPointData()->SetTCoords(tcoords);
  pd->GetPointData()->AddArray(floatArray(kDepthArray, 1, n, mesh.depth.data()));
  addTextureFieldData(pd->GetFieldData(), mli, k, k == 0 && options.opaqueFarthestLayer);
  auto tolerance = vtkSmartPointer<vtkDoubleArray>::New();
  tolerance->SetName(kMeshToleranceArray);
  tolerance->InsertNextValue(options.meshTolerance);
  pd->GetFieldData()->AddArray(tolerance);
  return pd;
}

} // namespace

vtkSmartPointer<vtkPolyData> layerToPolyData(const mli::MLI& mli, int k,
                                             const LayerOptions& options) {
  vtkSmartPointer<vtkPolyData> pd = options.meshMode == MeshMode::Adaptive
                                        ? adaptivePolyData(mli, k, options)
                                        : perTexelPolyData(mli, k, options);
  pd->GetFieldData()->AddArray(intValue(kLayerIndexArray, k));
  return pd;
}

vtkSmartPointer<vtkImageData> layerTexture(vtkPolyData* layer) {
  vtkFieldData* fd = layer ? layer->GetFieldData() : nullptr;
  vtkDataArray* rgba = fd ? fd->GetArray(kTextureRGBAArray) : nullptr;
  vtkDataArray* size = fd ? fd->GetArray(kTextureSizeArray) : nullptr;
  if (!rgba || !size || size->GetNumberOfComponents() != 2 || size->GetNumberOfTuples() != 1)
    return nullptr;
  const int W = static_cast<int>(size->GetComponent(0, 0));
  const int H = static_cast<int>(size->GetComponent(0, 1));
  if (W < 1 || H < 1 || rgba->GetNumberOfTuples() != static_cast<vtkIdType>(W) * H)
    return nullptr;
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(W, H, 1);
  image->GetPointData()->SetScalars(rgba);
  for (const char* name : {kTextureColorArray, kTextureAlphaArray, kTextureDepthArray})
    if (vtkDataArray* a = fd->GetArray(name))
      if (a->GetNumberOfTuples() == rgba->GetNumberOfTuples())
        image->GetPointData()->AddArray(a);
  return image;
}

bool mliToCollection(const mli::MLI& mli, const LayerOptions& options,
                     vtkPartitionedDataSetCollection* out,
                     const std::function<bool(double)>& progress) {
  mli::validateMLI(mli, "MLI to VTK");
  out->Initialize();
  std::vector<bool> skip(static_cast<std::size_t>(mli.numLayers()), false);
  if (options.skipEmptyLayers)
    for (int k : mli::emptyLayers(mli, static_cast<float>(options.alphaThreshold)))
      skip[static_cast<std::size_t>(k)] = true;

  auto assembly = vtkSmartPointer<vtkDataAssembly>::New();
  assembly->SetRootNodeName(kAssemblyRoot);
  const int layersNode = assembly->AddNode(kAssemblyLayers);
  unsigned int index = 0;
  for (int k = 0; k < mli.numLayers(); ++k) {
    if (progress && !progress(static_cast<double>(k) / mli.numLayers())) {
      out->Initialize();
      return false;
    }
    if (skip[static_cast<std::size_t>(k)])
      continue;
    const std::string name = layerName(k);
    out->SetPartition(index, 0, layerToPolyData(mli, k, options));
    out->GetMetaData(index)->Set(vtkCompositeDataSet::NAME(), name.c_str());
    assembly->AddDataSetIndex(assembly->AddNode(name.c_str(), layersNode), index);
    ++index;
  }
  out->SetDataAssembly(assembly);
  addCameraFieldData(out->GetFieldData(), mli.camera);
  out->GetFieldData()->AddArray(intValue(kNumberOfLayersArray, mli.numLayers()));
  return true;
}

mli::MLI collectionToMLI(vtkPartitionedDataSetCollection* in, const std::string& context) {
  if (!in)
    fail(context, ": no input (expected a vtkPartitionedDataSetCollection of layers)");
  mli::MLI mli;
  mli.camera = cameraFromFieldData(in->GetFieldData(), context);
  const int W = mli.camera.width, H = mli.camera.height;
  const unsigned int L = in->GetNumberOfPartitionedDataSets();
  if (L == 0)
    fail(context, ": the collection holds no layers (no partitioned data sets)");
  for (unsigned int i = 0; i < L; ++i) {
    std::ostringstream whereStream;
    whereStream << context << ": layer " << i;
    if (in->HasMetaData(i) && in->GetMetaData(i)->Has(vtkCompositeDataSet::NAME()))
      whereStream << " (" << in->GetMetaData(i)->Get(vtkCompositeDataSet::NAME()) << ")";
    const std::string where = whereStream.str();
    vtkPartitionedDataSet* pds = in->GetPartitionedDataSet(i);
    const unsigned int parts = pds ? pds->GetNumberOfPartitions() : 0;
    vtkDataSet* ds = parts == 1 ? pds->GetPartition(0) : nullptr;
    if (parts != 1 || !ds)
      fail(where, ": expected one data set (a vtkPolyData), found ", parts, " partition(s)",
           parts == 1 ? " with no data set" : "");
    mli.layers.push_back(layerTexels(ds, W, H, where));
  }
  mli::validateMLI(mli, context);
  return mli;
}

} // namespace simpli::vtkmli
