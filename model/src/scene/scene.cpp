// readScene: format detection, image loading and checks, bounds, normalisation.
#include "simpli/model/scene/scene.h"

#include "simpli/error.h"
#include "simpli/model/scene/camera_checks.h"
#include "simpli/model/scene/readers.h"
#include "simpli/warning.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

namespace fs = std::filesystem;

namespace simpli::scene {

const char* toString(SceneFormat format) {
  switch (format) {
  case SceneFormat::Auto:
    return "auto";
  case SceneFormat::LLFF:
    return "LLFF";
  case SceneFormat::Colmap:
    return "COLMAP";
  case SceneFormat::RealEstate10K:
    return "RealEstate10K";
  }
  return "?";
}

SceneFormat parseSceneFormat(const std::string& name) {
  std::string s = name;
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (s == "auto")
    return SceneFormat::Auto;
  if (s == "llff")
    return SceneFormat::LLFF;
  if (s == "colmap")
    return SceneFormat::Colmap;
  if (s == "re10k" || s == "realestate10k" || s == "sword")
    return SceneFormat::RealEstate10K;
  fail("unknown scene format '", name, "' (expected auto, llff, colmap or re10k)");
}

std::vector<Camera> Scene::cameras() const {
  std::vector<Camera> out;
  for (const SceneView& v : views)
    out.push_back(v.camera);
  return out;
}

std::vector<io::Image> Scene::images() const {
  std::vector<io::Image> out;
  for (const SceneView& v : views)
    out.push_back(v.image);
  return out;
}

double maxBaseline(const std::vector<Camera>& cameras) {
  double best = 0;
  for (size_t i = 0; i < cameras.size(); ++i)
    for (size_t j = i + 1; j < cameras.size(); ++j)
      best = std::max(best, (cameras[i].centre() - cameras[j].centre()).norm());
  return best;
}

SceneFormat detectSceneFormat(const std::string& path) {
  std::error_code ec;
  const fs::path p(path);
  if (!fs::exists(p, ec))
    fail("scene path '", path, "' does not exist");
  if (!fs::is_directory(p, ec)) {
    if (p.filename() == "poses_bounds.npy")
      return SceneFormat::LLFF;
    if (p.extension() == ".txt")
      return SceneFormat::RealEstate10K;
    fail("cannot detect the scene format of file '", path,
         "': give a scene folder, a poses_bounds.npy or a RealEstate10K .txt camera file");
  }
  if (fs::is_regular_file(p / "poses_bounds.npy", ec))
    return SceneFormat::LLFF;
  for (const fs::path& dir : {p / "sparse" / "0", p / "sparse", p}) {
    if (fs::is_regular_file(dir / "cameras.txt", ec) && fs::is_regular_file(dir / "images.txt", ec))
      return SceneFormat::Colmap;
    if (fs::is_regular_file(dir / "cameras.bin", ec))
      return SceneFormat::Colmap; // the COLMAP reader explains how to convert it to text
  }
  const fs::path folder = p.lexically_normal().has_filename() ? p.lexically_normal()
                                                              : p.lexically_normal().parent_path();
  if (fs::is_regular_file(folder / (folder.filename().string() + ".txt"), ec) ||
      fs::is_regular_file(p / "cameras.txt", ec))
    return SceneFormat::RealEstate10K;
  fail("cannot detect the scene format of '", path,
       "': expected poses_bounds.npy (LLFF), cameras.txt + images.txt in ., sparse/ or "
       "sparse/0/ (COLMAP), or <folder name>.txt / cameras.txt (RealEstate10K)");
}

namespace {

SceneSource readSource(const std::string& path, SceneFormat format, const std::string& imagesDir) {
  std::error_code ec;
  const bool isFile = fs::exists(path, ec) && !fs::is_directory(path, ec);
  switch (format) {
  case SceneFormat::LLFF: {
    if (isFile) {
      if (fs::path(path).filename() != "poses_bounds.npy")
        fail("LLFF scene: '", path, "' is not a folder or a poses_bounds.npy");
      const fs::path parent = fs::path(path).parent_path();
      return readLlffSource(parent.empty() ? "." : parent.string(), imagesDir);
    }
    return readLlffSource(path, imagesDir);
  }
  case SceneFormat::Colmap:
    if (isFile)
      fail("COLMAP scene: '", path, "' is a file; give the scene folder");
    return readColmapSource(path, imagesDir);
  case SceneFormat::RealEstate10K:
    return readRealEstateSource(path, imagesDir);
  case SceneFormat::Auto:
    break;
  }
  fail("readScene: no format given for '", path, "'");
}

// LLFF and COLMAP scenes may hold down-sampled copies of their images (images_N).
std::string imagesFolder(const std::string& path, SceneFormat format,
                         const SceneReadOptions& options) {
  if (!options.imagesDir.empty() || format == SceneFormat::RealEstate10K)
    return options.imagesDir;
  std::error_code ec;
  const fs::path root = fs::is_directory(path, ec) ? fs::path(path) : fs::path(path).parent_path();
  return chooseImageFolder(root.empty() ? "." : root.string(), options.imagesFactor,
                           options.preferredWidth);
}

// The declared size (for which the intrinsics were written) and the image must have the same
// aspect ratio up to pixel rounding: relative intrinsics survive down-sampling, not cropping.
void checkDeclaredSize(const SceneSource& src, size_t i, int width, int height) {
  const Camera& c = src.cameras[i];
  if (c.width <= 0 || c.height <= 0 || (c.width == width && c.height == height))
    return;
  const double predictedHeight = double(c.height) * width / c.width;
  if (std::abs(predictedHeight - height) > 1.0 + 0.01 * height)
    fail(src.posesFile, ": view '", src.names[i], "': the cameras are for ", c.width, " x ",
         c.height, " images, but '", src.imagePaths[i], "' is ", width, " x ", height,
         " (a different aspect ratio, so not a down-sampled copy)");
}

// One warning per camera field for what cameraConcerns finds, naming the first view with it
// and how many views share it (a scene's views usually share their intrinsics).
void warnAboutCameras(const SceneSource& src) {
  struct Seen {
    CameraConcern concern;
    std::string view;
    size_t views = 0;
  };
  std::vector<Seen> seen;
  for (size_t i = 0; i < src.cameras.size(); ++i) {
    for (const CameraConcern& c : cameraConcerns(src.cameras[i])) {
      auto it = std::find_if(seen.begin(), seen.end(),
                             [&](const Seen& s) { return s.concern.field == c.field; });
      if (it == seen.end())
        seen.push_back({c, src.names[i], 1});
      else
        ++it->views;
    }
  }
  for (const Seen& s : seen)
    warn(src.posesFile, ": view '", s.view, "'",
         s.views > 1 ? " (and " + std::to_string(s.views - 1) + " more)" : std::string(), ": ",
         s.concern.field, " = ", s.concern.value, ": ", s.concern.why);
}

// The network's planes span depths kDefaultNear..kDefaultFar (a ratio of 100) once the scene is
// scaled; bounds whose ratio is far beyond that put most of the scene on the farthest planes.
void warnAboutBounds(const std::string& file, double nearB, double farB,
                     const std::string& source) {
  const double ratio = farB / nearB;
  if (ratio > kMaxGoodDepthRatio)
    warn(file, ": near..far bounds ", nearB, "..", farB, " (", source, ") span a depth ratio of ",
         ratio, ", more than ", kMaxGoodDepthRatio, ": the network's planes span depths ",
         kDefaultNear, "..", kDefaultFar, " after the near bound is scaled to ", kDefaultNear,
         ", so most of the scene lands on the farthest planes and the result will be poor "
         "(a near bound far below the scene's content?)");
}

// Views that all share one centre show no parallax: the plane sweep cannot tell depths apart.
void warnAboutBaseline(const SceneSource& src, double nearB) {
  if (src.cameras.size() < 2)
    return;
  const double baseline = maxBaseline(src.cameras);
  if (!(baseline > kMinGoodBaseline * nearB))
    warn(src.posesFile, ": the ", src.cameras.size(), " views' camera centres lie within ",
         baseline, " of each other (near bound ", nearB,
         "): without parallax between the views the depth of the scene cannot be inferred, so "
         "the result will be poor");
}

} // namespace

Scene readScene(const std::string& path, const SceneReadOptions& options) {
  if (options.near < 0 || !std::isfinite(options.near))
    fail("near bound option ", options.near, " must be > 0");
  if (options.far < 0 || !std::isfinite(options.far))
    fail("far bound option ", options.far, " must be > 0");

  const SceneFormat format =
      options.format == SceneFormat::Auto ? detectSceneFormat(path) : options.format;
  const std::string imagesDir = imagesFolder(path, format, options);
  const SceneSource src = readSource(path, format, imagesDir);

  Scene scene;
  scene.root = src.root;
  scene.imagesDir = imagesDir;
  scene.format = src.format;
  scene.posesFile = src.posesFile;
  for (size_t i = 0; i < src.cameras.size(); ++i) {
    SceneView view;
    view.name = src.names[i];
    view.imagePath = src.imagePaths[i];
    io::ImageSize original;
    view.image = io::readImage(view.imagePath, options.sizeMultiple, &original);
    view.originalWidth = original.width;
    view.originalHeight = original.height;
    if (i > 0 && (original.width != scene.views[0].originalWidth ||
                  original.height != scene.views[0].originalHeight))
      fail("images differ in size: '", scene.views[0].imagePath, "' is ",
           scene.views[0].originalWidth, " x ", scene.views[0].originalHeight, " but '",
           view.imagePath, "' is ", original.width, " x ", original.height);
    checkDeclaredSize(src, i, original.width, original.height);
    view.camera = src.cameras[i];
    view.camera.width = view.image.width;
    view.camera.height = view.image.height;
    if (!options.loadImages)
      view.image = io::Image();
    scene.views.push_back(std::move(view));
  }

  // Bounds in scene units: explicit options, then the format's own, then the defaults.
  double nearB = src.near, farB = src.far;
  std::string source = src.boundsSource;
  if (nearB <= 0 || farB <= 0) {
    nearB = kDefaultNear;
    farB = kDefaultFar;
    source = "default (the reference network's plane range; scene assumed in network units)";
  }
  if (options.near > 0) {
    nearB = options.near;
    source = options.far > 0 ? "explicit" : "explicit near, far from " + source;
  }
  if (options.far > 0) {
    farB = options.far;
    if (options.near <= 0)
      source = "explicit far, near from " + source;
  }
  if (!(nearB > 0))
    fail("near bound ", nearB, " (", source, ") must be > 0");
  if (!(farB > nearB))
    fail("far bound ", farB, " must be > near bound ", nearB, " (", source, ")");
  warnAboutCameras(src);
  warnAboutBounds(src.posesFile, nearB, farB, source);
  warnAboutBaseline(src, nearB);

  std::vector<double> depths;
  for (const Camera& c : src.cameras) {
    const std::vector<double> d = visiblePointDepths(c, src.points);
    depths.insert(depths.end(), d.begin(), d.end());
  }
  const Normalisation n = chooseNormalisation(options.normalisation, nearB, depths);
  scene.normalisation = n;
  scene.near = n.toNormalised(nearB);
  scene.far = n.toNormalised(farB);
  scene.boundsSource = source;
  for (SceneView& v : scene.views)
    v.camera = n.toNormalised(v.camera);
  for (const Eigen::Vector3d& X : src.points)
    scene.points.push_back(n.toNormalised(X));
  return scene;
}

} // namespace simpli::scene
