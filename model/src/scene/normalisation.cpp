#include "simpli/model/scene/normalisation.h"

#include "simpli/error.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace simpli::scene {

Camera Normalisation::toNormalised(const Camera& c) const {
  Camera out = c;
  out.t = scale * c.t;
  return out;
}

Camera Normalisation::toScene(const Camera& c) const {
  Camera out = c;
  out.t = c.t / scale;
  return out;
}

const char* toString(NormalisationMode mode) {
  switch (mode) {
  case NormalisationMode::Auto:
    return "auto";
  case NormalisationMode::None:
    return "none";
  case NormalisationMode::NearBound:
    return "near bound";
  case NormalisationMode::PointPercentile:
    return "point-depth percentile";
  }
  return "?";
}

std::string Normalisation::describe() const {
  std::ostringstream os;
  if (rule == NormalisationMode::None) {
    os << "none (scale 1)";
  } else {
    os << toString(rule) << ' ' << anchorScene << " -> " << anchorTarget << " (scale " << scale
       << ")";
  }
  return os.str();
}

double percentile(std::vector<double> values, double p) {
  if (values.empty())
    fail("percentile: no values");
  if (!(p >= 0 && p <= 100))
    fail("percentile: p = ", p, " is outside [0, 100]");
  std::sort(values.begin(), values.end());
  const double pos = p / 100.0 * double(values.size() - 1);
  const size_t lo = size_t(std::floor(pos));
  const size_t hi = std::min(lo + 1, values.size() - 1);
  const double frac = pos - double(lo);
  return values[lo] + frac * (values[hi] - values[lo]);
}

Normalisation chooseNormalisation(const NormalisationOptions& options, double sceneNear,
                                  const std::vector<double>& pointDepths) {
  NormalisationMode mode = options.mode;
  if (mode == NormalisationMode::Auto)
    mode = pointDepths.empty() ? NormalisationMode::NearBound : NormalisationMode::PointPercentile;
  Normalisation n;
  n.rule = mode;
  switch (mode) {
  case NormalisationMode::None:
    return n;
  case NormalisationMode::NearBound:
    n.anchorScene = sceneNear;
    n.anchorTarget = options.minDepth;
    break;
  case NormalisationMode::PointPercentile:
    if (pointDepths.empty())
      fail("normalisation by point-depth percentile: the scene has no SfM points in front of "
           "its cameras");
    n.anchorScene = percentile(pointDepths, options.pointPercentile);
    n.anchorTarget = options.pointTarget;
    break;
  case NormalisationMode::Auto:
    break;
  }
  if (!(n.anchorTarget > 0) || !std::isfinite(n.anchorTarget))
    fail("normalisation: target depth ", n.anchorTarget, " must be positive");
  if (!(n.anchorScene > 0) || !std::isfinite(n.anchorScene))
    fail("normalisation (", toString(mode), "): scene depth ", n.anchorScene,
         " must be positive and finite");
  n.scale = n.anchorTarget / n.anchorScene;
  return n;
}

} // namespace simpli::scene
