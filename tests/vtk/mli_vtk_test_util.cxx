#include "mli_vtk_test_util.h"

#include <vtkExecutive.h>
#include <vtkNew.h>

#include <algorithm>
#include <random>
#include <sstream>

#include <Eigen/Geometry>

namespace simpli::vtktest {

scene::Camera testCamera(int W, int H) {
  scene::Camera c;
  c.R = Eigen::AngleAxisd(0.4, Eigen::Vector3d(0.3, 1.0, -0.2).normalized()).toRotationMatrix();
  c.t = Eigen::Vector3d(-0.6, 1.1, 1.7);
  c.fx = 0.87;
  c.fy = 1.19;
  c.cx = 0.52;
  c.cy = 0.4167;
  c.width = W;
  c.height = H;
  return c;
}

mli::MLI randomMLI(int L, int H, int W, unsigned seed) {
  mli::MLI mli = mli::MLI::allocate(testCamera(W, H), L);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int k = 0; k < L; ++k) {
    const float d = 20.0f / static_cast<float>(k + 1);
    std::uniform_real_distribution<float> depth(d, 2.0f * d);
    mli::MLILayer& layer = mli.layers[static_cast<std::size_t>(k)];
    for (float& v : layer.depth)
      v = depth(rng);
    for (float& v : layer.rgba)
      v = unit(rng);
  }
  return mli;
}

bool ErrorRecorder::has(const std::vector<std::string>& parts) const {
  for (const auto& m : messages) {
    bool all = true;
    for (const auto& p : parts)
      all = all && m.find(p) != std::string::npos;
    if (all)
      return true;
  }
  return false;
}

std::string ErrorRecorder::all() const {
  std::ostringstream os;
  for (const auto& m : messages)
    os << "[" << m << "]\n";
  return os.str();
}

int runWithErrors(vtkAlgorithm* alg, ErrorRecorder* errors) {
  const unsigned long a = alg->AddObserver(vtkCommand::ErrorEvent, errors);
  vtkNew<ErrorRecorder> executiveErrors;
  const unsigned long b = alg->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, executiveErrors);
  const int rc = alg->GetExecutive()->Update();
  alg->RemoveObserver(a);
  alg->GetExecutive()->RemoveObserver(b);
  return rc;
}

} // namespace simpli::vtktest
