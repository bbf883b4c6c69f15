// Exact ray intersections of the synthetic primitives (see synthetic/shapes.h).
#include "simpli/model/synthetic/shapes.h"

#include "simpli/error.h"

#include <Eigen/Geometry>

#include <cmath>

namespace simpli::synthetic {

const char* toString(ShapeKind kind) {
  switch (kind) {
  case ShapeKind::Plane:
    return "plane";
  case ShapeKind::Rectangle:
    return "rectangle";
  case ShapeKind::Box:
    return "box";
  case ShapeKind::Sphere:
    return "sphere";
  case ShapeKind::Cylinder:
    return "cylinder";
  case ShapeKind::Leaf:
    return "leaf";
  }
  return "?";
}

const char* toString(ShapeRole role) {
  switch (role) {
  case ShapeRole::Background:
    return "background";
  case ShapeRole::FrontoPlane:
    return "fronto-parallel plane";
  case ShapeRole::SlantedPlane:
    return "slanted plane";
  case ShapeRole::Box:
    return "box";
  case ShapeRole::Sphere:
    return "sphere";
  case ShapeRole::Pole:
    return "pole";
  case ShapeRole::Wire:
    return "wire";
  case ShapeRole::Distant:
    return "distant wall";
  case ShapeRole::Post:
    return "post";
  case ShapeRole::Branch:
    return "branch";
  case ShapeRole::Leaf:
    return "leaf";
  }
  return "?";
}

Eigen::Matrix3d frameFromAxis(const Eigen::Vector3d& axis, const Eigen::Vector3d& away) {
  const Eigen::Vector3d z = axis.normalized();
  const Eigen::Vector3d yRaw = away - away.dot(z) * z;
  if (!(yRaw.norm() > 1e-9 * away.norm()))
    fail("frameFromAxis: 'away' direction is parallel to the axis");
  const Eigen::Vector3d y = yRaw.normalized();
  Eigen::Matrix3d m;
  m.col(0) = y.cross(z); // right-handed: x = y x z gives x x y = z
  m.col(1) = y;
  m.col(2) = z;
  return m;
}

namespace {

// Longitude measured from local -y (towards the cameras), so the +-pi seam is on local +y.
double longitude(double x, double y) {
  return std::atan2(x, -y);
}

bool planeHit(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double tMin, double tMax,
              double& t) {
  if (d.z() == 0)
    return false;
  t = -o.z() / d.z();
  return t > tMin && t < tMax;
}

// Smallest root of a t^2 + 2 b t + c in (tMin, tMax), if any.
bool quadraticHit(double a, double b, double c, double tMin, double tMax, double& t) {
  const double disc = b * b - a * c;
  if (a <= 0 || disc < 0)
    return false;
  const double s = std::sqrt(disc);
  // Numerically stable pair of roots.
  const double q = b >= 0 ? -(b + s) : -(b - s);
  double t0 = q / a, t1 = q != 0 ? c / q : t0;
  if (t0 > t1)
    std::swap(t0, t1);
  if (t0 > tMin && t0 < tMax) {
    t = t0;
    return true;
  }
  if (t1 > tMin && t1 < tMax) {
    t = t1;
    return true;
  }
  return false;
}

// Whether local (x, y) lies on a leaf of half length a and half width b.
bool insideLeaf(double x, double y, double a, double b) {
  const double r = x / a;
  return std::abs(r) <= 1 && std::abs(y) <= b * (1 - r * r);
}

// max over the leaf of (lx, ly) . (x, y): on the upper edge y = b (1 - x^2 / a^2) (the leaf is
// symmetric in y, so |ly| serves both edges), where the derivative lx - 2 b |ly| x / a^2 vanishes,
// or at a tip.
double leafSupport(double lx, double ly, double a, double b) {
  const double c = std::abs(ly);
  if (c * b <= 1e-300) // a segment along x
    return std::abs(lx) * a;
  const double x = std::max(-a, std::min(a, lx * a * a / (2 * b * c)));
  return lx * x + c * b * (1 - x * x / (a * a));
}

} // namespace

bool Shape::intersect(const Ray& ray, double tMin, SurfaceHit& hit) const {
  const Eigen::Vector3d o = axes.transpose() * (ray.origin - centre);
  const Eigen::Vector3d d = axes.transpose() * ray.direction;
  const double tMax = hit.t;
  double t = 0;
  Eigen::Vector2d st = Eigen::Vector2d::Zero();
  Eigen::Vector3d nLocal = Eigen::Vector3d::UnitZ();

  switch (kind) {
  case ShapeKind::Plane:
  case ShapeKind::Rectangle:
  case ShapeKind::Leaf: {
    if (!planeHit(o, d, tMin, tMax, t))
      return false;
    const Eigen::Vector3d p = o + t * d;
    if (kind == ShapeKind::Rectangle && (std::abs(p.x()) > size.x() || std::abs(p.y()) > size.y()))
      return false;
    if (kind == ShapeKind::Leaf && !insideLeaf(p.x(), p.y(), size.x(), size.y()))
      return false;
    st = {p.x(), p.y()};
    nLocal = Eigen::Vector3d::UnitZ();
    break;
  }
  case ShapeKind::Box: {
    // Slab method: the entry parameter is the largest of the per-axis near planes.
    double tNear = -std::numeric_limits<double>::infinity();
    double tFar = std::numeric_limits<double>::infinity();
    int nearAxis = -1, farAxis = -1;
    for (int k = 0; k < 3; ++k) {
      if (d[k] == 0) {
        if (std::abs(o[k]) > size[k])
          return false;
        continue;
      }
      double t0 = (-size[k] - o[k]) / d[k], t1 = (size[k] - o[k]) / d[k];
      if (t0 > t1)
        std::swap(t0, t1);
      if (t0 > tNear) {
        tNear = t0;
        nearAxis = k;
      }
      if (t1 < tFar) {
        tFar = t1;
        farAxis = k;
      }
    }
    if (tNear > tFar)
      return false;
    int axis = nearAxis;
    t = tNear;
    if (!(t > tMin)) { // origin inside the box: the exit face is what the ray sees
      t = tFar;
      axis = farAxis;
    }
    if (!(t > tMin && t < tMax) || axis < 0)
      return false;
    const Eigen::Vector3d p = o + t * d;
    const double side = p[axis] >= 0 ? 1.0 : -1.0;
    nLocal = Eigen::Vector3d::Zero();
    nLocal[axis] = side;
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    // A different texture window per face, so that adjacent faces do not continue each other.
    const double offset = 37.0 * (2 * axis + (side > 0 ? 1 : 0));
    st = {p[u] + offset, p[v] - offset};
    break;
  }
  case ShapeKind::Sphere: {
    const double r = size.x();
    if (!quadraticHit(d.dot(d), o.dot(d), o.dot(o) - r * r, tMin, tMax, t))
      return false;
    const Eigen::Vector3d p = o + t * d;
    nLocal = p / r;
    st = {r * longitude(p.x(), p.y()), r * std::asin(std::max(-1.0, std::min(1.0, p.z() / r)))};
    break;
  }
  case ShapeKind::Cylinder: {
    const double r = size.x(), h = size.z();
    bool found = false;
    double tSide = 0;
    if (quadraticHit(d.x() * d.x() + d.y() * d.y(), o.x() * d.x() + o.y() * d.y(),
                     o.x() * o.x() + o.y() * o.y() - r * r, tMin, tMax, tSide)) {
      // The nearer root may lie beyond the caps; then the far root can still be valid only
      // from inside, which the caps below cover for closed cylinders.
      const Eigen::Vector3d p = o + tSide * d;
      if (std::abs(p.z()) <= h) {
        t = tSide;
        nLocal = Eigen::Vector3d(p.x(), p.y(), 0) / r;
        st = {r * longitude(p.x(), p.y()), p.z()};
        found = true;
      }
    }
    if (d.z() != 0) {
      for (double capZ : {-h, h}) {
        const double tc = (capZ - o.z()) / d.z();
        if (!(tc > tMin && tc < (found ? t : tMax)))
          continue;
        const Eigen::Vector3d p = o + tc * d;
        if (p.x() * p.x() + p.y() * p.y() > r * r)
          continue;
        t = tc;
        nLocal = Eigen::Vector3d(0, 0, capZ > 0 ? 1 : -1);
        st = {p.x() + 53.0, p.y() + (capZ > 0 ? 53.0 : -53.0)};
        found = true;
      }
    }
    if (!found)
      return false;
    break;
  }
  }
  hit.t = t;
  hit.st = st;
  hit.normal = axes * nLocal;
  return true;
}

double Shape::boundingRadius() const {
  switch (kind) {
  case ShapeKind::Plane:
    return std::numeric_limits<double>::infinity();
  case ShapeKind::Rectangle:
    return std::hypot(size.x(), size.y());
  case ShapeKind::Box:
    return size.norm();
  case ShapeKind::Sphere:
    return size.x();
  case ShapeKind::Cylinder:
    return std::hypot(size.x(), size.z());
  case ShapeKind::Leaf: // |p|^2 = a^2 s + b^2 (1 - s)^2 with s = x^2 / a^2: largest at s = 0 or 1
    return std::max(size.x(), size.y());
  }
  return std::numeric_limits<double>::infinity();
}

double Shape::extent(const Eigen::Vector3d& dir) const {
  const Eigen::Vector3d l = axes.transpose() * dir; // dir in local coordinates
  switch (kind) {
  case ShapeKind::Plane:
    return std::abs(l.x()) + std::abs(l.y()) > 1e-12 ? std::numeric_limits<double>::infinity()
                                                     : 0.0;
  case ShapeKind::Rectangle:
    return std::abs(l.x()) * size.x() + std::abs(l.y()) * size.y();
  case ShapeKind::Box:
    return std::abs(l.x()) * size.x() + std::abs(l.y()) * size.y() + std::abs(l.z()) * size.z();
  case ShapeKind::Sphere:
    return size.x() * l.norm();
  case ShapeKind::Cylinder: // the end discs reach r * |dir component across the axis|
    return std::abs(l.z()) * size.z() + size.x() * std::hypot(l.x(), l.y());
  case ShapeKind::Leaf:
    return leafSupport(l.x(), l.y(), size.x(), size.y());
  }
  return std::numeric_limits<double>::infinity();
}

} // namespace simpli::synthetic
