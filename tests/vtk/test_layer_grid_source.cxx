// vtkSIMPLILayerGridSource against analytic answers: back-projected corners, topology, areas,
// point data, clamping, bad input (reported, request fails, no crash) and abort.
#include "vtkSIMPLILayerGridSource.h"

#include <vtkCellArray.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkExecutive.h>
#include <vtkFloatArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace {

using Vec3 = std::array<double, 3>;

Vec3 point(vtkPolyData* pd, vtkIdType id) {
  Vec3 p;
  pd->GetPoint(id, p.data());
  return p;
}

// Records the messages of ErrorEvents (an observer also keeps them off stderr).
class MessageRecorder : public vtkCommand {
public:
  static MessageRecorder* New() { return new MessageRecorder; }
  void Execute(vtkObject*, unsigned long, void* callData) override {
    messages.emplace_back(callData ? static_cast<const char*>(callData) : "");
  }
  bool anyContains(const std::string& a, const std::string& b) const {
    for (const auto& m : messages) {
      if (m.find(a) != std::string::npos && m.find(b) != std::string::npos) {
        return true;
      }
    }
    return false;
  }
  std::vector<std::string> messages;
};

// Records the progress values; optionally sets the abort flag at the first progress >= abortAt.
class ProgressRecorder : public vtkCommand {
public:
  static ProgressRecorder* New() { return new ProgressRecorder; }
  void Execute(vtkObject* caller, unsigned long, void* callData) override {
    const double progress = *static_cast<double*>(callData);
    values.push_back(progress);
    if (!aborted && progress >= abortAt) {
      static_cast<vtkAlgorithm*>(caller)->SetAbortExecute(1);
      aborted = true;
    }
  }
  std::vector<double> values;
  double abortAt = 2.0; // never, unless set
  bool aborted = false;
};

// A deliberately non-trivial camera and plane.
constexpr double kDepth = 2.5, kFx = 0.8, kFy = 1.1, kCx = 0.45, kCy = 0.55;
constexpr int kW = 5, kH = 4;

void configure(vtkSIMPLILayerGridSource* s) {
  s->SetWidth(kW);
  s->SetHeight(kH);
  s->SetDepth(kDepth);
  s->SetFx(kFx);
  s->SetFy(kFy);
  s->SetCx(kCx);
  s->SetCy(kCy);
  s->SetColor(0.2, 0.4, 0.8, 0.6);
}

} // namespace

TEST(LayerGridSource, Defaults) {
  vtkNew<vtkSIMPLILayerGridSource> s;
  EXPECT_EQ(s->GetNumberOfInputPorts(), 0);
  EXPECT_EQ(s->GetWidth(), 16);
  EXPECT_EQ(s->GetHeight(), 16);
  EXPECT_EQ(s->GetDepth(), 1.0);
  EXPECT_EQ(s->GetFx(), 1.0);
  EXPECT_EQ(s->GetFy(), 1.0);
  EXPECT_EQ(s->GetCx(), 0.5);
  EXPECT_EQ(s->GetCy(), 0.5);
  const double* c = s->GetColor();
  EXPECT_EQ(c[0], 1.0);
  EXPECT_EQ(c[3], 1.0);
  EXPECT_EQ(s->GetOutputPointsPrecision(), vtkAlgorithm::SINGLE_PRECISION);
}

TEST(LayerGridSource, CornerVerticesAreBackProjected) {
  vtkNew<vtkSIMPLILayerGridSource> s;
  configure(s);
  s->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  s->Update();
  vtkPolyData* out = s->GetOutput();
  ASSERT_EQ(out->GetNumberOfPoints(), kW * kH);
  EXPECT_EQ(out->GetPoints()->GetDataType(), VTK_DOUBLE);

  // Corner (u, v) -> d * ((u - cx) / fx, (v - cy) / fy, 1), written out by hand.
  const double xl = kDepth * (0.0 - kCx) / kFx, xr = kDepth * (1.0 - kCx) / kFx;
  const double yt = kDepth * (0.0 - kCy) / kFy, yb = kDepth * (1.0 - kCy) / kFy;
  const struct {
    vtkIdType id;
    Vec3 expected;
  } corners[] = {{0, {xl, yt, kDepth}},
                 {kW - 1, {xr, yt, kDepth}},
                 {(kH - 1) * kW, {xl, yb, kDepth}},
                 {kH * kW - 1, {xr, yb, kDepth}}};
  for (const auto& c : corners) {
    const Vec3 p = point(out, c.id);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(p[k], c.expected[k], 1e-12) << "vertex " << c.id << " component " << k;
    }
  }
  // An interior vertex: row 2, column 3 -> u = 3/4, v = 2/3.
  const Vec3 p = point(out, 2 * kW + 3);
  EXPECT_NEAR(p[0], kDepth * (0.75 - kCx) / kFx, 1e-12);
  EXPECT_NEAR(p[1], kDepth * (2.0 / 3.0 - kCy) / kFy, 1e-12);
  EXPECT_NEAR(p[2], kDepth, 1e-12);

  // Re-projecting every vertex gives its grid position back (pinhole round trip).
  for (vtkIdType i = 0; i < kH; ++i) {
    for (vtkIdType j = 0; j < kW; ++j) {
      const Vec3 q = point(out, i * kW + j);
      EXPECT_NEAR(kFx * q[0] / q[2] + kCx, static_cast<double>(j) / (kW - 1), 1e-12);
      EXPECT_NEAR(kFy * q[1] / q[2] + kCy, static_cast<double>(i) / (kH - 1), 1e-12);
    }
  }
}

TEST(LayerGridSource, SinglePrecisionPointsMatchToFloatAccuracy) {
  vtkNew<vtkSIMPLILayerGridSource> s;
  configure(s);
  s->Update();
  vtkPolyData* out = s->GetOutput();
  EXPECT_EQ(out->GetPoints()->GetDataType(), VTK_FLOAT);
  const Vec3 p = point(out, kH * kW - 1);
  EXPECT_NEAR(p[0], kDepth * (1.0 - kCx) / kFx, 1e-6);
  EXPECT_NEAR(p[1], kDepth * (1.0 - kCy) / kFy, 1e-6);
  EXPECT_NEAR(p[2], kDepth, 1e-6);
}

TEST(LayerGridSource, TrianglesCoverThePlaneFacingTheCamera) {
  vtkNew<vtkSIMPLILayerGridSource> s;
  configure(s);
  s->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  s->Update();
  vtkPolyData* out = s->GetOutput();
  ASSERT_EQ(out->GetNumberOfPolys(), 2 * (kW - 1) * (kH - 1));
  EXPECT_EQ(out->GetNumberOfCells(), out->GetNumberOfPolys());

  // The first quad, exactly as specified: (b, b+W, b+W+1) and (b, b+W+1, b+1) with b = 0.
  vtkCellArray* polys = out->GetPolys();
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  polys->GetCellAtId(0, n, ids);
  ASSERT_EQ(n, 3);
  EXPECT_EQ(ids[0], 0);
  EXPECT_EQ(ids[1], kW);
  EXPECT_EQ(ids[2], kW + 1);
  polys->GetCellAtId(1, n, ids);
  ASSERT_EQ(n, 3);
  EXPECT_EQ(ids[0], 0);
  EXPECT_EQ(ids[1], kW + 1);
  EXPECT_EQ(ids[2], 1);
  // The last quad, b = (H-2)*W + (W-2).
  const vtkIdType b = (kH - 2) * kW + (kW - 2);
  polys->GetCellAtId(out->GetNumberOfPolys() - 1, n, ids);
  ASSERT_EQ(n, 3);
  EXPECT_EQ(ids[0], b);
  EXPECT_EQ(ids[1], b + kW + 1);
  EXPECT_EQ(ids[2], b + 1);

  // Every triangle faces the camera at the origin (normal along -z, i.e. towards it), and
  // together they tile the back-projected image rectangle exactly once.
  double area = 0.0;
  for (vtkIdType c = 0; c < out->GetNumberOfPolys(); ++c) {
    polys->GetCellAtId(c, n, ids);
    ASSERT_EQ(n, 3);
    const Vec3 p0 = point(out, ids[0]), p1 = point(out, ids[1]), p2 = point(out, ids[2]);
    const double ax = p1[0] - p0[0], ay = p1[1] - p0[1];
    const double bx = p2[0] - p0[0], by = p2[1] - p0[1];
    const double nz = ax * by - ay * bx;
    EXPECT_LT(nz, 0.0) << "triangle " << c << " faces away from the camera";
    area += 0.5 * std::abs(nz);
  }
  EXPECT_NEAR(area, (kDepth / kFx) * (kDepth / kFy), 1e-12);
}

TEST(LayerGridSource, PointDataFollowsTheLayerConventions) {
  vtkNew<vtkSIMPLILayerGridSource> s;
  configure(s);
  s->Update();
  vtkPointData* pd = s->GetOutput()->GetPointData();

  auto* rgba = vtkUnsignedCharArray::SafeDownCast(pd->GetScalars());
  ASSERT_NE(rgba, nullptr) << "RGBA must be the active scalars, as unsigned char";
  EXPECT_STREQ(rgba->GetName(), "RGBA");
  ASSERT_EQ(rgba->GetNumberOfComponents(), 4);
  ASSERT_EQ(rgba->GetNumberOfTuples(), kW * kH);
  const unsigned char expected[4] = {51, 102, 204, 153}; // round(255 * (0.2, 0.4, 0.8, 0.6))
  for (vtkIdType t = 0; t < rgba->GetNumberOfTuples(); ++t) {
    for (int k = 0; k < 4; ++k) {
      ASSERT_EQ(rgba->GetTypedComponent(t, k), expected[k]) << "tuple " << t << " comp " << k;
    }
  }

  auto* alpha = vtkFloatArray::SafeDownCast(pd->GetArray("Alpha"));
  auto* depth = vtkFloatArray::SafeDownCast(pd->GetArray("Depth"));
  ASSERT_NE(alpha, nullptr);
  ASSERT_NE(depth, nullptr);
  EXPECT_EQ(alpha->GetNumberOfComponents(), 1);
  EXPECT_EQ(depth->GetNumberOfComponents(), 1);
  for (vtkIdType t = 0; t < kW * kH; ++t) {
    ASSERT_FLOAT_EQ(alpha->GetValue(t), 0.6f);
    ASSERT_FLOAT_EQ(depth->GetValue(t), static_cast<float>(kDepth));
  }

  // Texture coordinates (u, 1 - v): image row 0 is the top (t = 1) of the texture.
  vtkDataArray* tc = pd->GetTCoords();
  ASSERT_NE(tc, nullptr);
  ASSERT_EQ(tc->GetNumberOfComponents(), 2);
  const struct {
    vtkIdType id;
    double s, t;
  } cases[] = {{0, 0.0, 1.0},
               {kW - 1, 1.0, 1.0},
               {(kH - 1) * kW, 0.0, 0.0},
               {kH * kW - 1, 1.0, 0.0},
               {1 * kW + 2, 0.5, 1.0 - 1.0 / 3.0}};
  for (const auto& c : cases) {
    EXPECT_NEAR(tc->GetComponent(c.id, 0), c.s, 1e-7) << "vertex " << c.id;
    EXPECT_NEAR(tc->GetComponent(c.id, 1), c.t, 1e-7) << "vertex " << c.id;
  }
}

TEST(LayerGridSource, SettersClampToTheirRanges) {
  vtkNew<vtkSIMPLILayerGridSource> s;
  s->SetWidth(1);
  s->SetHeight(100000);
  EXPECT_EQ(s->GetWidth(), 2);
  EXPECT_EQ(s->GetHeight(), 4096);
  s->SetColor(-0.5, 1.5, 0.25, 1.0);
  double c[4];
  s->GetColor(c);
  EXPECT_EQ(c[0], 0.0);
  EXPECT_EQ(c[1], 1.0);
  EXPECT_EQ(c[2], 0.25);
  EXPECT_EQ(c[3], 1.0);

  // Setting the same colour again must not invalidate the pipeline.
  const vtkMTimeType before = s->GetMTime();
  s->SetColor(0.0, 1.0, 0.25, 1.0);
  EXPECT_EQ(s->GetMTime(), before);
  s->SetColor(0.0, 1.0, 0.25, 0.5);
  EXPECT_GT(s->GetMTime(), before);

  // The smallest grid: one quad, two triangles.
  s->Update();
  EXPECT_EQ(s->GetOutput()->GetNumberOfPoints(), 2 * 4096);
  s->SetHeight(2);
  s->Update();
  EXPECT_EQ(s->GetOutput()->GetNumberOfPoints(), 4);
  EXPECT_EQ(s->GetOutput()->GetNumberOfPolys(), 2);
}

TEST(LayerGridSource, PrintSelfListsTheProperties) {
  vtkNew<vtkSIMPLILayerGridSource> s;
  configure(s);
  std::ostringstream os;
  s->Print(os);
  const std::string text = os.str();
  for (const char* key : {"Width: 5", "Height: 4", "Depth: 2.5", "Fx: 0.8", "Fy: 1.1", "Cx: 0.45",
                          "Cy: 0.55", "Color: (0.2, 0.4, 0.8, 0.6)", "OutputPointsPrecision: 0"}) {
    EXPECT_NE(text.find(key), std::string::npos) << "missing '" << key << "' in\n" << text;
  }
}

// One invalid property at a time: the request fails, the error names property and value, the
// output is empty, and fixing the property makes the next update succeed.
struct BadSetting {
  const char* name;
  void (*apply)(vtkSIMPLILayerGridSource*);
  const char* property;
  const char* value;
};

class LayerGridSourceBadInput : public ::testing::TestWithParam<BadSetting> {};

TEST_P(LayerGridSourceBadInput, RequestFailsWithANamedError) {
  const BadSetting& bad = GetParam();
  vtkNew<vtkSIMPLILayerGridSource> s;
  configure(s);
  s->Update(); // a valid output first: a failed request must not leave it behind
  ASSERT_EQ(s->GetOutput()->GetNumberOfPoints(), kW * kH);

  vtkNew<MessageRecorder> sourceErrors;
  vtkNew<MessageRecorder> executiveErrors;
  s->AddObserver(vtkCommand::ErrorEvent, sourceErrors);
  s->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, executiveErrors);
  bad.apply(s);
  EXPECT_EQ(s->GetExecutive()->Update(), 0) << "the request must fail";
  ASSERT_EQ(sourceErrors->messages.size(), 1u);
  EXPECT_TRUE(sourceErrors->anyContains(bad.property, bad.value))
      << "error does not name " << bad.property << " = " << bad.value << ": "
      << sourceErrors->messages[0];
  EXPECT_EQ(s->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_EQ(s->GetOutput()->GetNumberOfCells(), 0);

  configure(s);
  EXPECT_EQ(s->GetExecutive()->Update(), 1);
  EXPECT_EQ(s->GetOutput()->GetNumberOfPoints(), kW * kH);
  EXPECT_EQ(sourceErrors->messages.size(), 1u);
}

INSTANTIATE_TEST_SUITE_P(
    LayerGridSource, LayerGridSourceBadInput,
    ::testing::Values(
        BadSetting{"NegativeDepth", [](vtkSIMPLILayerGridSource* s) { s->SetDepth(-1.0); }, "Depth",
                   "-1"},
        BadSetting{"ZeroDepth", [](vtkSIMPLILayerGridSource* s) { s->SetDepth(0.0); }, "Depth",
                   "0"},
        BadSetting{"InfiniteDepth",
                   [](vtkSIMPLILayerGridSource* s) {
                     s->SetDepth(std::numeric_limits<double>::infinity());
                   },
                   "Depth", "inf"},
        BadSetting{"ZeroFx", [](vtkSIMPLILayerGridSource* s) { s->SetFx(0.0); }, "Fx", "0"},
        BadSetting{"ZeroFy", [](vtkSIMPLILayerGridSource* s) { s->SetFy(0.0); }, "Fy", "0"},
        // A mirrored camera is not an MLI reference camera (validateMLICamera).
        BadSetting{"NegativeFx", [](vtkSIMPLILayerGridSource* s) { s->SetFx(-0.8); }, "Fx", "-0.8"},
        BadSetting{
            "NanCx",
            [](vtkSIMPLILayerGridSource* s) { s->SetCx(std::numeric_limits<double>::quiet_NaN()); },
            "Cx", "nan"},
        BadSetting{
            "NanCy",
            [](vtkSIMPLILayerGridSource* s) { s->SetCy(std::numeric_limits<double>::quiet_NaN()); },
            "Cy", "nan"},
        BadSetting{"NanAlpha",
                   [](vtkSIMPLILayerGridSource* s) {
                     s->SetColor(0.2, 0.4, 0.8, std::numeric_limits<double>::quiet_NaN());
                   },
                   "Color[3]", "nan"}),
    [](const ::testing::TestParamInfo<BadSetting>& info) { return std::string(info.param.name); });

TEST(LayerGridSource, ReportsProgressPerRow) {
  vtkNew<vtkSIMPLILayerGridSource> s;
  s->SetWidth(4);
  s->SetHeight(10);
  vtkNew<ProgressRecorder> progress;
  s->AddObserver(vtkCommand::ProgressEvent, progress);
  s->Update();
  EXPECT_EQ(s->GetOutput()->GetNumberOfPoints(), 40);
  // The executive adds 0 before and 1 after; in between every row i reports i / Height.
  std::vector<double> rows;
  for (double v : progress->values) {
    if (v > 0.0 && v < 1.0) {
      rows.push_back(v);
    }
  }
  ASSERT_EQ(rows.size(), 9u); // rows 1..9 (row 0 reports 0)
  for (size_t k = 0; k < rows.size(); ++k) {
    EXPECT_DOUBLE_EQ(rows[k], static_cast<double>(k + 1) / 10.0);
  }
  ASSERT_FALSE(progress->values.empty());
  EXPECT_EQ(progress->values.back(), 1.0);
}

TEST(LayerGridSource, AbortLeavesAnEmptyOutput) {
  vtkNew<vtkSIMPLILayerGridSource> s;
  s->SetWidth(32);
  s->SetHeight(32);
  vtkNew<ProgressRecorder> progress;
  progress->abortAt = 2.0 / 32.0; // during row 2
  s->AddObserver(vtkCommand::ProgressEvent, progress);
  s->Update();
  ASSERT_TRUE(progress->aborted);
  // The source stops at the row where it sees the abort: no row after row 2 reports progress.
  for (double v : progress->values) {
    EXPECT_TRUE(v <= 2.0 / 32.0 || v == 1.0) << "progress " << v << " after the abort";
  }
  EXPECT_EQ(s->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_EQ(s->GetOutput()->GetNumberOfCells(), 0);
}
