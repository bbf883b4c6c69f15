// vtkMLIReader and vtkMLIWriter: the VTK layout of an MLI (layers, assembly, point arrays,
// camera field data), exact round trips through the lossless form, agreement with the model's
// reader for the JPEG form, options, abort, and bad input (reported, request fails, nothing
// written, no crash).
#include "vtkMLIReader.h"
#include "vtkMLIWriter.h"

#include <vtkCellArray.h>
#include <vtkCommand.h>
#include <vtkCompositeDataSet.h>
#include <vtkDataAssembly.h>
#include <vtkDoubleArray.h>
#include <vtkExecutive.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkInformation.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPartitionedDataSet.h>
#include <vtkPartitionedDataSetCollection.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "mli_vtk_test_util.h"
#include "simpli/model/mli/files.h"
#include "simpli/model/mli/mesh.h"
#include "support/mli_compare.h"

namespace simpli::vtktest {
namespace {

using test::expectSameMLI;

constexpr int kL = 3, kH = 5, kW = 7;

vtkPolyData* layerAt(vtkPartitionedDataSetCollection* c, unsigned int i) {
  vtkPartitionedDataSet* pds = c->GetPartitionedDataSet(i);
  return pds ? vtkPolyData::SafeDownCast(pds->GetPartition(0)) : nullptr;
}

// Reads `folder` with a fresh reader; fails the test if the read fails.
vtkSmartPointer<vtkPartitionedDataSetCollection> readCollection(const std::string& folder) {
  vtkNew<vtkMLIReader> reader;
  reader->SetFileName(folder.c_str());
  vtkNew<ErrorRecorder> errors;
  EXPECT_EQ(runWithErrors(reader, errors), 1) << errors->all();
  vtkSmartPointer<vtkPartitionedDataSetCollection> out = reader->GetOutput();
  return out;
}

TEST(MLIReader, LayoutOfTheLosslessForm) {
  TempDir dir;
  const mli::MLI mli = randomMLI(kL, kH, kW, 1);
  mli::writeMLI(dir / "scene", mli, mli::MLIFormat::Lossless);
  auto out = readCollection(dir / "scene");
  ASSERT_EQ(out->GetNumberOfPartitionedDataSets(), static_cast<unsigned>(kL));

  // Assembly /MLI/Layers/LayerKK -> dataset KK; metadata names.
  vtkDataAssembly* assembly = out->GetDataAssembly();
  ASSERT_NE(assembly, nullptr);
  EXPECT_STREQ(assembly->GetRootNodeName(), "MLI");
  for (int k = 0; k < kL; ++k) {
    const std::string name = "Layer0" + std::to_string(k);
    const int node = assembly->GetFirstNodeByPath(("/MLI/Layers/" + name).c_str());
    ASSERT_GE(node, 0) << name;
    EXPECT_EQ(assembly->GetDataSetIndices(node, false), std::vector<unsigned int>{unsigned(k)});
    EXPECT_STREQ(out->GetMetaData(k)->Get(vtkCompositeDataSet::NAME()), name.c_str());
  }

  // Camera field data: exact doubles.
  vtkFieldData* fd = out->GetFieldData();
  auto* intr = vtkDoubleArray::SafeDownCast(fd->GetArray("CameraIntrinsics"));
  auto* extr = vtkDoubleArray::SafeDownCast(fd->GetArray("CameraExtrinsics"));
  auto* size = vtkIntArray::SafeDownCast(fd->GetArray("CameraImageSize"));
  auto* nl = vtkIntArray::SafeDownCast(fd->GetArray("NumberOfLayers"));
  ASSERT_TRUE(intr && extr && size && nl);
  ASSERT_EQ(intr->GetNumberOfComponents(), 4);
  ASSERT_EQ(extr->GetNumberOfComponents(), 12);
  ASSERT_EQ(size->GetNumberOfComponents(), 2);
  EXPECT_EQ(intr->GetValue(0), mli.camera.fx);
  EXPECT_EQ(intr->GetValue(1), mli.camera.fy);
  EXPECT_EQ(intr->GetValue(2), mli.camera.cx);
  EXPECT_EQ(intr->GetValue(3), mli.camera.cy);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(extr->GetValue(4 * r + c), mli.camera.R(r, c));
    EXPECT_EQ(extr->GetValue(4 * r + 3), mli.camera.t(r));
  }
  EXPECT_EQ(size->GetValue(0), kW);
  EXPECT_EQ(size->GetValue(1), kH);
  EXPECT_EQ(nl->GetValue(0), kL);

  for (int k = 0; k < kL; ++k) {
    vtkPolyData* pd = layerAt(out, k);
    ASSERT_NE(pd, nullptr);
    ASSERT_EQ(pd->GetNumberOfPoints(), kW * kH);
    EXPECT_EQ(pd->GetNumberOfPolys(), 2 * (kW - 1) * (kH - 1));
    vtkPointData* p = pd->GetPointData();
    auto* rgba = vtkUnsignedCharArray::SafeDownCast(p->GetScalars());
    auto* color = vtkFloatArray::SafeDownCast(p->GetArray("Color"));
    auto* alpha = vtkFloatArray::SafeDownCast(p->GetArray("Alpha"));
    auto* depth = vtkFloatArray::SafeDownCast(p->GetArray("Depth"));
    auto* tc = vtkFloatArray::SafeDownCast(p->GetTCoords());
    ASSERT_TRUE(rgba && color && alpha && depth && tc);
    EXPECT_STREQ(rgba->GetName(), "RGBA");
    EXPECT_EQ(rgba->GetNumberOfComponents(), 4);
    EXPECT_EQ(color->GetNumberOfComponents(), 3);
    EXPECT_STREQ(tc->GetName(), "TCoords");
    auto* index = vtkIntArray::SafeDownCast(pd->GetFieldData()->GetArray("LayerIndex"));
    ASSERT_NE(index, nullptr);
    EXPECT_EQ(index->GetValue(0), k);
    const mli::MLILayer& layer = mli.layers[k];
    for (int i = 0; i < kH; ++i)
      for (int j = 0; j < kW; ++j) {
        const vtkIdType b = i * kW + j;
        const float* texel = &layer.rgba[4 * b];
        for (int c = 0; c < 3; ++c)
          EXPECT_EQ(color->GetTypedComponent(b, c), texel[c]);
        EXPECT_EQ(alpha->GetValue(b), texel[3]);
        EXPECT_EQ(depth->GetValue(b), layer.depth[b]);
        // The farthest layer is opaque on display (SIMPLIMLIToVTK.h); Alpha keeps the value.
        for (int c = 0; c < 4; ++c)
          EXPECT_EQ(rgba->GetTypedComponent(b, c),
                    k == 0 && c == 3 ? 255 : std::lround(255.0 * texel[c]));
        EXPECT_FLOAT_EQ(tc->GetTypedComponent(b, 0), j / float(kW - 1));
        EXPECT_FLOAT_EQ(tc->GetTypedComponent(b, 1), 1.0f - i / float(kH - 1));
        // World position: the reference back-projection of texel (i, j) at its depth.
        const Eigen::Vector3d X = mli::mliVertex(mli.camera, i, j, layer.depth[b]);
        double got[3];
        pd->GetPoint(b, got);
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(got[c], X(c), 1e-5 * (1.0 + X.norm()));
        // The point's camera z is the depth (it is on the layer's depth map).
        EXPECT_NEAR(mli.camera.depth(Eigen::Vector3d(got[0], got[1], got[2])), layer.depth[b],
                    1e-4 * layer.depth[b]);
      }
    // The first quad's triangles, as mli/mesh.h specifies.
    vtkNew<vtkIdList> ids;
    pd->GetPolys()->GetCellAtId(0, ids);
    EXPECT_EQ(ids->GetId(0), 0);
    EXPECT_EQ(ids->GetId(1), kW);
    EXPECT_EQ(ids->GetId(2), kW + 1);
  }
}

TEST(MLIReader, AcceptsMetaJsonAndDetectsTheForm) {
  TempDir dir;
  const mli::MLI mli = randomMLI(2, 4, 6, 2);
  mli::writeMLI(dir / "lossless", mli, mli::MLIFormat::Lossless);
  mli::writeMLI(dir / "jpeg", mli, mli::MLIFormat::Jpeg);
  vtkNew<vtkMLIReader> reader;
  EXPECT_EQ(reader->CanReadFile((dir / "lossless").c_str()), 1);
  EXPECT_EQ(reader->CanReadFile((dir / "jpeg/meta.json").c_str()), 1);
  EXPECT_EQ(reader->CanReadFile((dir / "nowhere").c_str()), 0);
  EXPECT_EQ(reader->CanReadFile(dir.path().c_str()), 0); // a folder without meta.json
  EXPECT_EQ(reader->CanReadFile(nullptr), 0);

  auto viaMeta = readCollection(dir / "lossless/meta.json");
  ASSERT_EQ(viaMeta->GetNumberOfPartitionedDataSets(), 2u);
  auto* color = vtkFloatArray::SafeDownCast(layerAt(viaMeta, 1)->GetPointData()->GetArray("Color"));
  EXPECT_EQ(color->GetTypedComponent(1, 2), mli.layers[1].rgba[4 * 1 + 2]); // texel 1, blue
}

TEST(MLIReader, JpegFormMatchesTheModelReader) {
  TempDir dir;
  const mli::MLI mli = randomMLI(2, 9, 11, 3);
  mli::writeMLI(dir / "jpeg", mli, mli::MLIFormat::Jpeg);
  for (int decoding : {vtkMLIReader::DEPTH_VIEWER, vtkMLIReader::DEPTH_BIN_CENTRE}) {
    mli::MLIReadOptions options;
    options.depthDecoding = decoding == vtkMLIReader::DEPTH_VIEWER
                                ? mli::MLIDepthDecoding::Viewer
                                : mli::MLIDepthDecoding::BinCentre;
    const mli::MLI expected = mli::readMLI(dir / "jpeg", options);
    vtkNew<vtkMLIReader> reader;
    reader->SetFileName((dir / "jpeg").c_str());
    reader->SetDepthDecoding(decoding);
    vtkNew<ErrorRecorder> errors;
    ASSERT_EQ(runWithErrors(reader, errors), 1) << errors->all();
    vtkPartitionedDataSetCollection* out = reader->GetOutput();
    ASSERT_EQ(out->GetNumberOfPartitionedDataSets(), 2u);
    for (int k = 0; k < 2; ++k) {
      vtkPointData* p = layerAt(out, k)->GetPointData();
      auto* rgba = vtkUnsignedCharArray::SafeDownCast(p->GetScalars());
      auto* depth = vtkFloatArray::SafeDownCast(p->GetArray("Depth"));
      for (vtkIdType b = 0; b < 9 * 11; ++b) {
        EXPECT_EQ(depth->GetValue(b), expected.layers[k].depth[b]);
        for (int c = 0; c < 4; ++c) {
          // 8-bit files: the float is q / 255 and the byte is q again.
          const float v = expected.layers[k].rgba[4 * b + c];
          EXPECT_EQ(rgba->GetTypedComponent(b, c),
                    k == 0 && c == 3 ? 255 : std::lround(255.0 * v)); // layer 0 opaque
          EXPECT_NEAR(255.0 * v, std::round(255.0 * v), 1e-3);
        }
      }
    }
  }
}

TEST(MLIWriter, LosslessRoundTripIsExact) {
  TempDir dir;
  const mli::MLI mli = randomMLI(kL, kH, kW, 4);
  mli::writeMLI(dir / "in", mli, mli::MLIFormat::Lossless);
  vtkNew<vtkMLIReader> reader;
  reader->SetFileName((dir / "in").c_str());
  vtkNew<vtkMLIWriter> writer;
  writer->SetInputConnection(reader->GetOutputPort());
  writer->SetFileName((dir / "out").c_str());
  writer->SetFormatToLossless();
  ASSERT_EQ(writer->Write(), 1);
  EXPECT_EQ(mli::detectMLIFormat(dir / "out"), mli::MLIFormat::Lossless);
  expectSameMLI(mli::readMLI(dir / "out"), mli);
  // Only the finished folder, no temporary left beside it.
  EXPECT_EQ(listDir(dir.path()), (std::vector<std::string>{"in", "out"}));

  // Replacing the existing MLI with a JPEG one; its content is what the model writer makes.
  writer->SetFormatToJpeg();
  ASSERT_EQ(writer->Write(), 1);
  EXPECT_EQ(mli::detectMLIFormat(dir / "out"), mli::MLIFormat::Jpeg);
  mli::writeMLI(dir / "direct", mli, mli::MLIFormat::Jpeg);
  expectSameMLI(mli::readMLI(dir / "out"), mli::readMLI(dir / "direct"));
}

TEST(MLIWriter, SkippedLayersAndDroppedTrianglesStillWrite) {
  // Layer 1 fully transparent, layer 0 transparent on its left half.
  TempDir dir;
  mli::MLI mli = randomMLI(3, 6, 8, 5);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 8; ++j) {
      mli.layers[1].rgba[4 * (i * 8 + j) + 3] = 0.0f;
      if (j < 4)
        mli.layers[0].rgba[4 * (i * 8 + j) + 3] = 0.0f;
      else
        mli.layers[0].rgba[4 * (i * 8 + j) + 3] = 0.5f;
    }
  mli::writeMLI(dir / "in", mli, mli::MLIFormat::Lossless);
  vtkNew<vtkMLIReader> reader;
  reader->SetFileName((dir / "in").c_str());
  reader->SkipEmptyLayersOn();
  reader->DropTransparentTrianglesOn();
  reader->Update();
  vtkPartitionedDataSetCollection* out = reader->GetOutput();
  ASSERT_EQ(out->GetNumberOfPartitionedDataSets(), 2u);
  EXPECT_STREQ(out->GetMetaData(1u)->Get(vtkCompositeDataSet::NAME()), "Layer02");
  EXPECT_GE(out->GetDataAssembly()->GetFirstNodeByPath("/MLI/Layers/Layer02"), 0);
  EXPECT_LT(out->GetDataAssembly()->GetFirstNodeByPath("/MLI/Layers/Layer01"), 0);
  EXPECT_EQ(vtkIntArray::SafeDownCast(layerAt(out, 1)->GetFieldData()->GetArray("LayerIndex"))
                ->GetValue(0),
            2);
  EXPECT_EQ(vtkIntArray::SafeDownCast(out->GetFieldData()->GetArray("NumberOfLayers"))->GetValue(0),
            3);
  // Layer 0: quads with columns 0..3 have three transparent corners in every triangle; the
  // triangles (b, b+W, b+W+1) and (b, b+W+1, b+1) of the quad at column 3 touch column 4.
  vtkPolyData* l0 = layerAt(out, 0);
  EXPECT_EQ(l0->GetNumberOfPoints(), 48);       // points are never dropped
  EXPECT_EQ(l0->GetNumberOfPolys(), 2 * 5 * 4); // columns 3..6 of quads, 5 rows
  EXPECT_EQ(layerAt(out, 1)->GetNumberOfPolys(), 2 * 5 * 7);

  // The written MLI holds the kept layers; their texels are unchanged.
  vtkNew<vtkMLIWriter> writer;
  writer->SetInputConnection(reader->GetOutputPort());
  writer->SetFileName((dir / "out").c_str());
  writer->SetFormat(vtkMLIWriter::FORMAT_LOSSLESS);
  ASSERT_EQ(writer->Write(), 1);
  const mli::MLI back = mli::readMLI(dir / "out");
  ASSERT_EQ(back.numLayers(), 2);
  EXPECT_EQ(back.layers[0].rgba, mli.layers[0].rgba);
  EXPECT_EQ(back.layers[1].depth, mli.layers[2].depth);
}

// Layer 0 a constant-depth opaque plane, layer 1 random (depth and alpha).
mli::MLI planeAndRandomMLI(int H, int W) {
  mli::MLI mli = randomMLI(2, H, W, 6);
  for (std::size_t p = 0; p < mli.texels(); ++p) {
    mli.layers[0].depth[p] = 30.0f;
    mli.layers[0].rgba[4 * p + 3] = 1.0f;
  }
  return mli;
}

TEST(MLIReader, AdaptiveLayout) {
  const int H = 9, W = 12;
  TempDir dir;
  const mli::MLI mli = planeAndRandomMLI(H, W);
  mli::writeMLI(dir / "scene", mli, mli::MLIFormat::Lossless);
  vtkNew<vtkMLIReader> reader;
  reader->SetFileName((dir / "scene").c_str());
  reader->SetMeshMode(vtkMLIReader::MESH_ADAPTIVE);
  reader->SetMeshTolerance(0.5);
  vtkNew<ErrorRecorder> errors;
  ASSERT_EQ(runWithErrors(reader, errors), 1) << errors->all();
  vtkPartitionedDataSetCollection* out = reader->GetOutput();
  ASSERT_EQ(out->GetNumberOfPartitionedDataSets(), 2u);
  // The plane: two triangles over four corner points.
  EXPECT_EQ(layerAt(out, 0)->GetNumberOfPolys(), 2);
  EXPECT_EQ(layerAt(out, 0)->GetNumberOfPoints(), 4);
  for (int k = 0; k < 2; ++k) {
    vtkPolyData* pd = layerAt(out, k);
    const mli::MLILayer& layer = mli.layers[k];
    auto* tc = vtkFloatArray::SafeDownCast(pd->GetPointData()->GetTCoords());
    auto* depth = vtkFloatArray::SafeDownCast(pd->GetPointData()->GetArray("Depth"));
    ASSERT_TRUE(tc && depth);
    EXPECT_EQ(pd->GetPointData()->GetScalars(), nullptr) << "colour comes from the texture";
    // Points on texels: their texture coordinate hits the texel centre, their depth is the
    // texel's and they lie on its reference ray.
    int onTexels = 0;
    for (vtkIdType v = 0; v < pd->GetNumberOfPoints(); ++v) {
      const double x = tc->GetTypedComponent(v, 0) * W - 0.5;
      const double y = (1.0 - tc->GetTypedComponent(v, 1)) * H - 0.5;
      const int j = static_cast<int>(std::lround(x)), i = static_cast<int>(std::lround(y));
      if (std::abs(x - j) > 1e-4 || std::abs(y - i) > 1e-4)
        continue; // a half-grid vertex of a cut quad
      ++onTexels;
      EXPECT_EQ(depth->GetValue(v), layer.depth[static_cast<std::size_t>(i) * W + j]);
      const Eigen::Vector3d X = mli::mliVertex(mli.camera, i, j, depth->GetValue(v));
      double got[3];
      pd->GetPoint(v, got);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c], X(c), 1e-5 * (1.0 + X.norm()));
    }
    EXPECT_GE(onTexels, 4);
    // The texels in the field data, vtkImageData row order (row 0 = the bottom MLI row).
    vtkFieldData* fd = pd->GetFieldData();
    auto* rgba = vtkUnsignedCharArray::SafeDownCast(fd->GetArray("TextureRGBA"));
    auto* color = vtkFloatArray::SafeDownCast(fd->GetArray("TextureColor"));
    auto* alpha = vtkFloatArray::SafeDownCast(fd->GetArray("TextureAlpha"));
    auto* tdepth = vtkFloatArray::SafeDownCast(fd->GetArray("TextureDepth"));
    auto* size = vtkIntArray::SafeDownCast(fd->GetArray("TextureSize"));
    auto* tolerance = vtkDoubleArray::SafeDownCast(fd->GetArray("MeshTolerance"));
    ASSERT_TRUE(rgba && color && alpha && tdepth && size && tolerance);
    EXPECT_EQ(size->GetValue(0), W);
    EXPECT_EQ(size->GetValue(1), H);
    EXPECT_EQ(tolerance->GetValue(0), 0.5);
    ASSERT_EQ(rgba->GetNumberOfTuples(), W * H);
    ASSERT_EQ(rgba->GetNumberOfComponents(), 4);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const vtkIdType t = static_cast<vtkIdType>(y) * W + x;
        const std::size_t p = static_cast<std::size_t>(H - 1 - y) * W + x;
        for (int c = 0; c < 4; ++c)
          EXPECT_EQ(rgba->GetTypedComponent(t, c), std::lround(255.0 * layer.rgba[4 * p + c]));
        EXPECT_EQ(color->GetTypedComponent(t, 2), layer.rgba[4 * p + 2]);
        EXPECT_EQ(alpha->GetValue(t), layer.rgba[4 * p + 3]);
        EXPECT_EQ(tdepth->GetValue(t), layer.depth[p]);
      }
  }
}

TEST(MLIWriter, AdaptiveLosslessRoundTripIsExact) {
  TempDir dir;
  const mli::MLI mli = planeAndRandomMLI(7, 10);
  mli::writeMLI(dir / "in", mli, mli::MLIFormat::Lossless);
  vtkNew<vtkMLIReader> reader;
  reader->SetFileName((dir / "in").c_str());
  reader->SetMeshMode(vtkMLIReader::MESH_ADAPTIVE);
  vtkNew<vtkMLIWriter> writer;
  writer->SetInputConnection(reader->GetOutputPort());
  writer->SetFileName((dir / "out").c_str());
  writer->SetFormatToLossless();
  ASSERT_EQ(writer->Write(), 1);
  expectSameMLI(mli::readMLI(dir / "out"), mli);
}

TEST(MLIReader, AbortLeavesAnEmptyOutput) {
  TempDir dir;
  mli::writeMLI(dir / "in", randomMLI(4, 4, 4, 6), mli::MLIFormat::Lossless);
  vtkNew<vtkMLIReader> reader;
  reader->SetFileName((dir / "in").c_str());
  class Abort : public vtkCommand {
  public:
    static Abort* New() { return new Abort; }
    void Execute(vtkObject* caller, unsigned long, void* data) override {
      if (*static_cast<double*>(data) >= 0.6)
        static_cast<vtkAlgorithm*>(caller)->SetAbortExecute(1);
    }
  };
  vtkNew<Abort> abort;
  reader->AddObserver(vtkCommand::ProgressEvent, abort);
  vtkNew<ErrorRecorder> errors;
  EXPECT_EQ(runWithErrors(reader, errors), 1);
  EXPECT_TRUE(errors->messages.empty()) << errors->all();
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPartitionedDataSets(), 0u);
}

// --- bad input ------------------------------------------------------------------------------

class MLIReaderErrors : public ::testing::Test {
protected:
  void SetUp() override {
    mli::writeMLI(dir_ / "scene", randomMLI(2, 4, 5, 7), mli::MLIFormat::Lossless);
  }

  // Reads `path`; expects a failed request, an error naming all of `parts`, an empty output.
  void expectFailure(const std::string& path, const std::vector<std::string>& parts) {
    vtkNew<vtkMLIReader> reader;
    reader->SetFileName(path.c_str());
    vtkNew<ErrorRecorder> errors;
    EXPECT_EQ(runWithErrors(reader, errors), 0) << path;
    EXPECT_TRUE(errors->has(parts)) << errors->all();
    EXPECT_EQ(reader->GetOutput()->GetNumberOfPartitionedDataSets(), 0u);
  }

  std::string meta() const { return dir_ / "scene/meta.json"; }
  TempDir dir_;
};

TEST_F(MLIReaderErrors, MissingFolder) {
  expectFailure(dir_ / "no_such_mli", {"no_such_mli", "does not exist"});
}

TEST_F(MLIReaderErrors, NoFileName) {
  vtkNew<vtkMLIReader> reader;
  vtkNew<ErrorRecorder> errors;
  EXPECT_EQ(runWithErrors(reader, errors), 0);
  EXPECT_TRUE(errors->has({"FileName is not set"})) << errors->all();
}

TEST_F(MLIReaderErrors, NotAnMLIFolder) {
  fs::create_directories(dir_.path() / "empty");
  expectFailure(dir_ / "empty", {"meta.json", "missing"});
}

TEST_F(MLIReaderErrors, MalformedMetaJson) {
  writeText(meta(), "{\"frame_size\": [4, 5], ");
  expectFailure(dir_ / "scene", {meta(), "not valid JSON"});
  writeText(meta(), "[1, 2, 3]");
  expectFailure(dir_ / "scene", {meta(), "expected a JSON object"});
  writeText(meta(), "{\"format\": \"simpli-mli-float\", \"num_layers\": 2, "
                    "\"frame_size\": [1, 5], \"layer_depth_00\": [1, 2]}");
  expectFailure(dir_ / "scene", {meta(), "frame_size", "1"});
}

TEST_F(MLIReaderErrors, MissingOrBrokenLayerFile) {
  fs::remove(dir_.path() / "scene/layer_rgba_01.tiff");
  expectFailure(dir_ / "scene", {"layer_rgba_01.tiff"});
  writeText(dir_.path() / "scene/layer_rgba_01.tiff", "not a tiff");
  expectFailure(dir_ / "scene", {"layer_rgba_01.tiff"});
}

// The model's warnings (a valid but extreme focal length) reach the reader's WarningEvent, where
// ParaView shows them, and the request still succeeds.
TEST_F(MLIReaderErrors, WarningsBecomeVtkWarnings) {
  mli::MLI m = randomMLI(2, 4, 5, 7);
  m.camera.fx = 0.05;
  mli::writeMLI(dir_ / "wide", m, mli::MLIFormat::Lossless);
  vtkNew<vtkMLIReader> reader;
  reader->SetFileName((dir_ / "wide").c_str());
  vtkNew<ErrorRecorder> warnings, errors;
  reader->AddObserver(vtkCommand::WarningEvent, warnings);
  EXPECT_EQ(runWithErrors(reader, errors), 1);
  EXPECT_TRUE(errors->messages.empty()) << errors->all();
  EXPECT_TRUE(warnings->has({"meta.json", "\"intrinsics_re\" fx = 0.05", "result will be poor"}))
      << warnings->all();
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPartitionedDataSets(), 2u);
}

class MLIWriterErrors : public ::testing::Test {
protected:
  void SetUp() override {
    mli::writeMLI(dir_ / "in", randomMLI(2, 4, 5, 8), mli::MLIFormat::Lossless);
    vtkNew<vtkMLIReader> reader;
    reader->SetFileName((dir_ / "in").c_str());
    reader->Update();
    collection_ = vtkSmartPointer<vtkPartitionedDataSetCollection>::New();
    collection_->DeepCopy(reader->GetOutput());
  }

  // Writes the (broken) collection; expects failure, an error with all `parts`, and nothing
  // new in the folder.
  void expectFailure(const std::vector<std::string>& parts) {
    vtkNew<vtkMLIWriter> writer;
    writer->SetInputData(collection_);
    writer->SetFileName((dir_ / "out").c_str());
    writer->SetFormatToLossless();
    vtkNew<ErrorRecorder> errors;
    writer->AddObserver(vtkCommand::ErrorEvent, errors);
    vtkNew<ErrorRecorder> executiveErrors;
    writer->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, executiveErrors);
    EXPECT_EQ(writer->Write(), 0);
    EXPECT_NE(writer->GetErrorCode(), 0ul);
    EXPECT_TRUE(errors->has(parts)) << errors->all();
    EXPECT_EQ(listDir(dir_.path()), std::vector<std::string>{"in"}) << "partial output left";
  }

  vtkPolyData* layer(unsigned i) { return layerAt(collection_, i); }
  TempDir dir_;
  vtkSmartPointer<vtkPartitionedDataSetCollection> collection_;
};

TEST_F(MLIWriterErrors, MissingPointArray) {
  layer(1)->GetPointData()->RemoveArray("Color");
  expectFailure({"out", "layer 1 (Layer01)", "\"Color\" is missing", "RGBA"});
}

TEST_F(MLIWriterErrors, AdaptiveLayerMissingTextureArray) {
  vtkNew<vtkMLIReader> reader;
  reader->SetFileName((dir_ / "in").c_str());
  reader->SetMeshMode(vtkMLIReader::MESH_ADAPTIVE);
  reader->Update();
  collection_->DeepCopy(reader->GetOutput());
  layer(1)->GetFieldData()->RemoveArray("TextureAlpha");
  expectFailure({"layer 1 (Layer01)", "\"TextureAlpha\" is missing", "TextureDepth"});
}

TEST_F(MLIWriterErrors, WrongComponentCount) {
  vtkNew<vtkFloatArray> alpha;
  alpha->SetName("Alpha");
  alpha->SetNumberOfComponents(2);
  alpha->SetNumberOfTuples(20);
  alpha->Fill(0.5);
  layer(0)->GetPointData()->AddArray(alpha);
  expectFailure({"layer 0", "\"Alpha\" has 2 component(s), expected 1"});
}

TEST_F(MLIWriterErrors, InconsistentLayerSize) {
  vtkNew<vtkMLIReader> other;
  TempDir d;
  mli::writeMLI(d / "bigger", randomMLI(1, 6, 5, 9), mli::MLIFormat::Lossless);
  other->SetFileName((d / "bigger").c_str());
  other->Update();
  collection_->SetPartition(1, 0, layerAt(other->GetOutput(), 0));
  expectFailure({"layer 1", "30 points, expected 5 x 4 = 20"});
}

TEST_F(MLIWriterErrors, MissingOrBadCamera) {
  collection_->GetFieldData()->RemoveArray("CameraExtrinsics");
  expectFailure({"out", "field data array \"CameraExtrinsics\" is missing"});
  SetUp();
  vtkDataArray* size = collection_->GetFieldData()->GetArray("CameraImageSize");
  size->SetComponent(0, 0, 1.0);
  expectFailure({"CameraImageSize", "width = 1"});
  SetUp();
  vtkDataArray* intr = collection_->GetFieldData()->GetArray("CameraIntrinsics");
  intr->SetComponent(0, 1, -2.0);
  expectFailure({"fy", "-2"});
}

TEST_F(MLIWriterErrors, ValuesOutOfRange) {
  auto* alpha = vtkFloatArray::SafeDownCast(layer(1)->GetPointData()->GetArray("Alpha"));
  alpha->SetValue(7, 1.5f);
  expectFailure({"layer 1", "1.5"});
  SetUp();
  auto* depth = vtkFloatArray::SafeDownCast(layer(0)->GetPointData()->GetArray("Depth"));
  depth->SetValue(3, -1.0f);
  expectFailure({"layer 0", "-1"});
}

TEST_F(MLIWriterErrors, NoLayersOrNoFileName) {
  collection_->SetNumberOfPartitionedDataSets(0);
  expectFailure({"no layers"});
  vtkNew<vtkMLIWriter> writer;
  writer->SetInputData(collection_);
  vtkNew<ErrorRecorder> errors;
  writer->AddObserver(vtkCommand::ErrorEvent, errors);
  vtkNew<ErrorRecorder> executiveErrors;
  writer->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, executiveErrors);
  EXPECT_EQ(writer->Write(), 0);
  EXPECT_TRUE(errors->has({"FileName is not set"})) << errors->all();
}

TEST_F(MLIWriterErrors, NeverReplacesAForeignFolder) {
  fs::create_directories(dir_.path() / "out");
  writeText(dir_.path() / "out/precious.txt", "keep me");
  vtkNew<vtkMLIWriter> writer;
  writer->SetInputData(collection_);
  writer->SetFileName((dir_ / "out").c_str());
  vtkNew<ErrorRecorder> errors;
  writer->AddObserver(vtkCommand::ErrorEvent, errors);
  vtkNew<ErrorRecorder> executiveErrors;
  writer->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, executiveErrors);
  EXPECT_EQ(writer->Write(), 0);
  EXPECT_TRUE(errors->has({"out"})) << errors->all();
  EXPECT_EQ(listDir(dir_.path() / "out"), std::vector<std::string>{"precious.txt"});
  EXPECT_EQ(listDir(dir_.path()), (std::vector<std::string>{"in", "out"}));
}

} // namespace
} // namespace simpli::vtktest
