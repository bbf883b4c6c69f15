// vtkSIMPLIImageQuality: the table against simpli's metrics and hand-computed values, single
// images and composite inputs, value scaling, and bad input.
#include "vtkSIMPLIImageQuality.h"

#include <vtkDoubleArray.h>
#include <vtkExecutive.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPartitionedDataSet.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkTable.h>
#include <vtkUnsignedCharArray.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "mli_vtk_test_util.h"
#include "simpli/model/metrics/image_quality.h"

namespace simpli::vtktest {
namespace {

// A w x h 8-bit RGB image with smooth content plus noise (VTK order: row 0 at the bottom).
vtkSmartPointer<vtkImageData> makeImage(int w, int h, unsigned seed, int components = 3) {
  auto img = vtkSmartPointer<vtkImageData>::New();
  img->SetDimensions(w, h, 1);
  vtkNew<vtkUnsignedCharArray> a;
  a->SetName("Pixels");
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(static_cast<vtkIdType>(w) * h);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> noise(-20, 20);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < components; ++c) {
        const int v =
            static_cast<int>(128 + 90 * std::sin(0.2 * x + c) * std::cos(0.15 * y)) + noise(rng);
        a->SetTypedComponent(static_cast<vtkIdType>(y) * w + x, c,
                             static_cast<unsigned char>(std::min(255, std::max(0, v))));
      }
  img->GetPointData()->SetScalars(a);
  return img;
}

// The same image as a simpli::MetricImage in [0, 1] (row 0 at the top), first 3 channels.
metrics::MetricImage asMetric(vtkImageData* img) {
  int d[3];
  img->GetDimensions(d);
  vtkDataArray* a = img->GetPointData()->GetScalars();
  const int ch = std::min(3, a->GetNumberOfComponents());
  metrics::MetricImage m(d[0], d[1], ch);
  for (int y = 0; y < d[1]; ++y)
    for (int x = 0; x < d[0]; ++x)
      for (int c = 0; c < ch; ++c)
        m.at(y, x, c) = static_cast<float>(
            a->GetComponent(static_cast<vtkIdType>(d[1] - 1 - y) * d[0] + x, c) / 255.0);
  return m;
}

struct Result {
  int rc = 0;
  vtkSmartPointer<vtkTable> table;
  vtkSmartPointer<ErrorRecorder> errors;
};

Result run(vtkDataObject* rendered, vtkDataObject* truth, double maxValue = 0.0) {
  vtkNew<vtkSIMPLIImageQuality> q;
  q->SetInputDataObject(0, rendered);
  q->SetInputDataObject(1, truth);
  q->SetMaxValue(maxValue);
  Result r;
  r.errors = vtkSmartPointer<ErrorRecorder>::New();
  q->AddObserver(vtkCommand::ErrorEvent, r.errors);
  vtkNew<ErrorRecorder> executiveErrors;
  q->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, executiveErrors);
  r.rc = q->GetExecutive()->Update();
  r.table = q->GetOutput();
  return r;
}

double cell(vtkTable* t, const char* column, int row) {
  return vtkDoubleArray::SafeDownCast(t->GetColumnByName(column))->GetValue(row);
}

TEST(ImageQuality, OnePairMatchesTheModelMetrics) {
  auto a = makeImage(48, 40, 1), b = makeImage(48, 40, 2);
  Result r = run(a, b);
  ASSERT_EQ(r.rc, 1) << r.errors->all();
  ASSERT_EQ(r.table->GetNumberOfRows(), 3); // view 0, mean, std
  auto* views = vtkStringArray::SafeDownCast(r.table->GetColumnByName("View"));
  ASSERT_NE(views, nullptr);
  EXPECT_EQ(views->GetValue(0), "0");
  EXPECT_EQ(views->GetValue(1), "mean");
  EXPECT_EQ(views->GetValue(2), "std");
  const metrics::ImageQuality expected =
      metrics::evaluateImageQuality(asMetric(a), asMetric(b), 0.9);
  EXPECT_DOUBLE_EQ(cell(r.table, "PSNR", 0), expected.psnr);
  EXPECT_DOUBLE_EQ(cell(r.table, "SSIM", 0), expected.ssim);
  EXPECT_GT(expected.ssim, 0.1);
  EXPECT_LT(expected.ssim, 0.95);
  EXPECT_DOUBLE_EQ(cell(r.table, "PSNR", 1), expected.psnr);
  EXPECT_EQ(cell(r.table, "PSNR", 2), 0.0);
}

TEST(ImageQuality, IdenticalAndKnownDifference) {
  auto a = makeImage(32, 32, 3);
  Result r = run(a, a);
  ASSERT_EQ(r.rc, 1) << r.errors->all();
  EXPECT_TRUE(std::isinf(cell(r.table, "PSNR", 0)));
  EXPECT_NEAR(cell(r.table, "SSIM", 0), 1.0, 1e-12);

  // Constant images 100 and 120 (of 255): MSE = (20/255)^2 everywhere -> exact PSNR.
  auto c1 = makeImage(32, 32, 3), c2 = makeImage(32, 32, 3);
  auto* p1 = vtkUnsignedCharArray::SafeDownCast(c1->GetPointData()->GetScalars());
  auto* p2 = vtkUnsignedCharArray::SafeDownCast(c2->GetPointData()->GetScalars());
  p1->FillValue(100);
  p2->FillValue(120);
  r = run(c1, c2);
  ASSERT_EQ(r.rc, 1) << r.errors->all();
  const double d = 120.0f / 255.0f - 100.0f / 255.0f; // the float values compared
  EXPECT_NEAR(cell(r.table, "PSNR", 0), 10.0 * std::log10(1.0 / (d * d)), 1e-9);
  const double m = 100.0f / 255.0f, n = 120.0f / 255.0f;
  EXPECT_NEAR(cell(r.table, "SSIM", 0), (2 * m * n + 1e-4) / (m * m + n * n + 1e-4), 1e-9);
}

TEST(ImageQuality, OnlyTheCentralCropCounts) {
  // 40 x 40: margins round(40 * 0.02566) = 1 pixel. A changed border pixel does not count.
  auto a = makeImage(40, 40, 4);
  auto b = vtkSmartPointer<vtkImageData>::New();
  b->DeepCopy(a);
  auto* p = vtkUnsignedCharArray::SafeDownCast(b->GetPointData()->GetScalars());
  p->SetTypedComponent(0, 0, 255 - p->GetTypedComponent(0, 0)); // corner pixel (0, 0)
  Result r = run(a, b);
  ASSERT_EQ(r.rc, 1) << r.errors->all();
  EXPECT_TRUE(std::isinf(cell(r.table, "PSNR", 0)));
  // With the whole image kept, it does count.
  vtkNew<vtkSIMPLIImageQuality> q;
  q->SetInputDataObject(0, a);
  q->SetInputDataObject(1, b);
  q->SetCropAreaFraction(1.0);
  q->Update();
  EXPECT_FALSE(std::isinf(
      vtkDoubleArray::SafeDownCast(q->GetOutput()->GetColumnByName("PSNR"))->GetValue(0)));
}

TEST(ImageQuality, SeveralViewsInCompositeInputs) {
  vtkNew<vtkPartitionedDataSet> rendered;
  vtkNew<vtkMultiBlockDataSet> truth; // different composite types pair by leaf order
  std::vector<metrics::ImageQuality> expected;
  for (unsigned v = 0; v < 3; ++v) {
    auto r = makeImage(30 + 2 * v, 28, 10 + v), g = makeImage(30 + 2 * v, 28, 20 + v);
    rendered->SetPartition(v, r);
    truth->SetBlock(v, g);
    expected.push_back(metrics::evaluateImageQuality(asMetric(r), asMetric(g)));
  }
  Result r = run(rendered, truth);
  ASSERT_EQ(r.rc, 1) << r.errors->all();
  ASSERT_EQ(r.table->GetNumberOfRows(), 5);
  std::vector<double> psnrs, ssims;
  for (int v = 0; v < 3; ++v) {
    EXPECT_DOUBLE_EQ(cell(r.table, "PSNR", v), expected[v].psnr);
    EXPECT_DOUBLE_EQ(cell(r.table, "SSIM", v), expected[v].ssim);
    psnrs.push_back(expected[v].psnr);
    ssims.push_back(expected[v].ssim);
  }
  const double mean = (psnrs[0] + psnrs[1] + psnrs[2]) / 3.0;
  double var = 0;
  for (double p : psnrs)
    var += (p - mean) * (p - mean) / 3.0;
  EXPECT_NEAR(cell(r.table, "PSNR", 3), mean, 1e-12);
  EXPECT_NEAR(cell(r.table, "PSNR", 4), std::sqrt(var), 1e-12);
  EXPECT_NEAR(cell(r.table, "SSIM", 3), metrics::meanAndStd(ssims).mean, 1e-15);
}

TEST(ImageQuality, FloatDataAndAlphaChannel) {
  // Float data in [0, 1] compares as is; an RGBA image's alpha is ignored.
  auto a = makeImage(24, 24, 5, 4), b = makeImage(24, 24, 6, 4);
  auto toFloat = [](vtkImageData* img) {
    auto out = vtkSmartPointer<vtkImageData>::New();
    out->SetDimensions(img->GetDimensions());
    vtkDataArray* src = img->GetPointData()->GetScalars();
    vtkNew<vtkFloatArray> f;
    f->SetNumberOfComponents(4);
    f->SetNumberOfTuples(src->GetNumberOfTuples());
    for (vtkIdType t = 0; t < src->GetNumberOfTuples(); ++t)
      for (int c = 0; c < 4; ++c)
        f->SetTypedComponent(t, c, static_cast<float>(src->GetComponent(t, c) / 255.0));
    out->GetPointData()->SetScalars(f);
    return out;
  };
  auto fa = toFloat(a), fb = toFloat(b);
  Result r8 = run(a, b), rf = run(fa, fb);
  ASSERT_EQ(r8.rc, 1) << r8.errors->all();
  ASSERT_EQ(rf.rc, 1) << rf.errors->all();
  EXPECT_NEAR(cell(r8.table, "PSNR", 0), cell(rf.table, "PSNR", 0), 1e-5);
  EXPECT_NEAR(cell(r8.table, "SSIM", 0), cell(rf.table, "SSIM", 0), 1e-6);
  auto* alpha = vtkUnsignedCharArray::SafeDownCast(b->GetPointData()->GetScalars());
  for (vtkIdType t = 0; t < alpha->GetNumberOfTuples(); ++t)
    alpha->SetTypedComponent(t, 3, static_cast<unsigned char>(t % 256));
  alpha->Modified();
  Result ra = run(a, b);
  EXPECT_DOUBLE_EQ(cell(ra.table, "PSNR", 0), cell(r8.table, "PSNR", 0));
  // MaxValue scales: 8-bit data declared as 0..510 halves every value.
  Result rh = run(a, a, 510.0);
  EXPECT_TRUE(std::isinf(cell(rh.table, "PSNR", 0)));
}

TEST(ImageQuality, BadInput) {
  auto a = makeImage(32, 32, 7);
  Result r = run(a, makeImage(32, 30, 8));
  EXPECT_EQ(r.rc, 0);
  EXPECT_TRUE(r.errors->has({"view 0", "32 x 32", "32 x 30"})) << r.errors->all();
  EXPECT_EQ(r.table->GetNumberOfRows(), 0);

  vtkNew<vtkPartitionedDataSet> two;
  two->SetPartition(0, makeImage(32, 32, 9));
  two->SetPartition(1, makeImage(32, 32, 10));
  r = run(two, a);
  EXPECT_EQ(r.rc, 0);
  EXPECT_TRUE(r.errors->has({"holds 2 view(s)", "holds 1"})) << r.errors->all();

  // Signed float data: a [-1, 1] image is not silently compared.
  auto f = vtkSmartPointer<vtkImageData>::New();
  f->SetDimensions(32, 32, 1);
  vtkNew<vtkFloatArray> fa;
  fa->SetName("Signed");
  fa->SetNumberOfComponents(3);
  fa->SetNumberOfTuples(32 * 32);
  fa->Fill(0.2);
  fa->SetTypedComponent(5, 1, -0.7f);
  f->GetPointData()->SetScalars(fa);
  r = run(f, f);
  EXPECT_EQ(r.rc, 0);
  EXPECT_TRUE(r.errors->has({"\"Signed\"", "-0.7", "outside [0, 1]"})) << r.errors->all();

  // Too small for the SSIM window after cropping.
  r = run(makeImage(10, 40, 11), makeImage(10, 40, 12));
  EXPECT_EQ(r.rc, 0);
  EXPECT_TRUE(r.errors->has({"view 0", "smaller than the 11 x 11 window"})) << r.errors->all();

  // Two-component data, no scalars, wrong data type.
  auto g = makeImage(20, 20, 13, 2);
  r = run(g, g);
  EXPECT_TRUE(r.errors->has({"2 components"})) << r.errors->all();
  auto none = vtkSmartPointer<vtkImageData>::New();
  none->SetDimensions(20, 20, 1);
  r = run(none, none);
  EXPECT_EQ(r.rc, 0);
  EXPECT_TRUE(r.errors->has({"array to compare is missing"})) << r.errors->all();
  vtkNew<vtkPartitionedDataSet> poly;
  poly->SetPartition(0, vtkSmartPointer<vtkPolyData>::New());
  r = run(poly, poly);
  EXPECT_EQ(r.rc, 0);
  EXPECT_TRUE(r.errors->has({"vtkPolyData", "expected a vtkImageData"})) << r.errors->all();
}

} // namespace
} // namespace simpli::vtktest
