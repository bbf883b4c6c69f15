// Photographs as textures (synthetic/photos.h, Pattern::Photo in texture.h): reading and
// downscaling, sampling, the folder search, photo textures in generated scenes (deterministic
// per seed, taken from the photo), and the procedural fallback. Test photos are written into
// temporary folders, so nothing here needs the Debian photo packages.
#include "simpli/model/synthetic/photos.h"
#include "simpli/model/synthetic/renderer.h"
#include "simpli/model/synthetic/scene_writer.h"

#include "support/expect_error.h"
#include "synthetic_test_util.h"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <functional>
#include <set>
#include <tuple>

using namespace simpli::synthetic;
using simpli::test::expectError;
using simpli::test::TempDir;

namespace {

using Pixel = std::function<Eigen::Vector3i(int x, int y)>; // RGB 0..255

// Writes an RGB photo (OpenCV stores BGR).
void writePhoto(const std::string& file, int width, int height, const Pixel& pixel) {
  cv::Mat m(height, width, CV_8UC3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const Eigen::Vector3i c = pixel(x, y);
      m.at<cv::Vec3b>(y, x) = cv::Vec3b(uint8_t(c[2]), uint8_t(c[1]), uint8_t(c[0]));
    }
  ASSERT_TRUE(cv::imwrite(file, m)) << file;
}

Eigen::Vector3i gradientPixel(int x, int y) {
  return {(x * 5) % 256, (y * 7) % 256, 200};
}

// Green with a little structure: every pixel has G well above R and B.
Eigen::Vector3i greenPixel(int x, int y) {
  return {20 + (x % 8) * 4, 200 + (y % 5) * 10, 30 + ((x + y) % 6) * 4};
}

SyntheticSceneParams photoParams(const std::shared_ptr<const PhotoLibrary>& photos, uint64_t seed) {
  SyntheticSceneParams p = simpli::test::smallParams(48, 32, 2, seed);
  p.objects = 4;
  p.antialias = 1;
  p.textures = TextureSet::Photo;
  p.photos = photos;
  return p;
}

std::vector<const Texture*> textures(const SyntheticScene& s) {
  std::vector<const Texture*> out{&s.background.texture};
  for (const Shape& o : s.objects)
    out.push_back(&o.texture);
  return out;
}

} // namespace

TEST(Photos, ReadExactlyWhenSmallEnough) {
  TempDir dir;
  writePhoto(dir.str("a.png"), 40, 30, gradientPixel);
  const auto lib = PhotoLibrary::load({dir.str("a.png")}, 1024);
  ASSERT_EQ(lib->size(), 1u);
  const Photo& p = *lib->photo(0);
  EXPECT_EQ(p.name, "a.png");
  EXPECT_EQ(p.width, 40);
  EXPECT_EQ(p.height, 30);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x)
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(int(p.rgb[(size_t(y) * 40 + size_t(x)) * 3 + size_t(c)]), gradientPixel(x, y)[c])
            << x << "," << y << " channel " << c << " (RGB order)";
}

TEST(Photos, DownscaledToTheMaximumSize) {
  TempDir dir;
  writePhoto(dir.str("big.png"), 300, 120,
             [](int x, int) { return Eigen::Vector3i(x < 150 ? 255 : 0, 0, x < 150 ? 0 : 255); });
  const auto lib = PhotoLibrary::load({dir.str("big.png")}, 100);
  const Photo& p = *lib->photo(0);
  EXPECT_EQ(p.width, 100);
  EXPECT_EQ(p.height, 40);
  // Area averaging keeps the halves: red on the left, blue on the right.
  EXPECT_GT(p.sample(10, 20)[0], 0.95);
  EXPECT_LT(p.sample(10, 20)[2], 0.05);
  EXPECT_GT(p.sample(90, 20)[2], 0.95);
  EXPECT_NE(lib->describe().find("1 photos"), std::string::npos) << lib->describe();
  expectError([&] { PhotoLibrary::load({dir.str("big.png")}, 8); }, {"maximum size 8"});
}

TEST(Photos, SampleIsBilinearAndMirroredBeyondTheEdges) {
  Photo p;
  p.name = "t";
  p.width = 3;
  p.height = 2;
  // Red channel = 10 * x + 100 * y, green 0, blue 255.
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x)
      p.rgb.insert(p.rgb.end(), {uint8_t(10 * x + 100 * y), 0, 255});
  auto red = [&](double x, double y) { return p.sample(x, y)[0] * 255.0; };
  EXPECT_NEAR(red(0.5, 0.5), 0, 1e-9); // pixel centres
  EXPECT_NEAR(red(2.5, 1.5), 120, 1e-9);
  EXPECT_NEAR(red(1.0, 0.5), 5, 1e-9); // halfway between two centres
  EXPECT_NEAR(red(1.5, 1.0), 60, 1e-9);
  EXPECT_NEAR(p.sample(1.2, 0.7)[2], 1.0, 1e-12);
  // Mirrored repetition: -x mirrors about 0, period 2 * width.
  for (double y : {0.5, 0.9, 1.5})
    for (double x : {0.2, 0.5, 1.3, 2.9}) {
      EXPECT_NEAR(red(-x, y), red(x, y), 1e-9) << x << "," << y;
      EXPECT_NEAR(red(x + 6.0, y), red(x, y), 1e-9) << x << "," << y;
      EXPECT_NEAR(red(6.0 - x, y), red(x, y), 1e-9) << x << "," << y;
      EXPECT_NEAR(red(x, y + 4.0), red(x, y), 1e-9) << x << "," << y;
    }
  EXPECT_TRUE(std::isfinite(red(-1e7, 3e6)));
}

TEST(Photos, FolderSearch) {
  TempDir dir;
  std::filesystem::create_directories(dir / "sub");
  writePhoto(dir.str("b.png"), 4, 4, gradientPixel);
  writePhoto(dir.str("a.JPG"), 4, 4, gradientPixel);
  writePhoto((dir / "sub" / "c.jpeg").string(), 4, 4, gradientPixel);
  simpli::test::writeText(dir / "notes.txt", "not a photo");
  const std::vector<std::string> files = findPhotoFiles(dir.str());
  ASSERT_EQ(files.size(), 3u);
  EXPECT_EQ(files[0], dir.str("a.JPG"));
  EXPECT_EQ(files[1], dir.str("b.png"));
  EXPECT_EQ(files[2], (dir / "sub" / "c.jpeg").string());
  expectError([&] { findPhotoFiles(dir.str("missing")); },
              {"photo folder", "missing", "does not exist"});
  expectError([&] { findPhotoFiles(dir.str("notes.txt")); }, {"notes.txt", "not a folder"});
  // A file that is not an image is named.
  simpli::test::writeText(dir / "broken.jpg", "JFIF? no");
  expectError([&] { PhotoLibrary::load(findPhotoFiles(dir.str())); },
              {"photo '", "broken.jpg", "cannot be read as an image"});
}

TEST(Photos, DefaultListIsPhotographsOfBothPackages) {
  int mate = 0, plasma = 0;
  for (const DebianPhoto& p : debianPhotos()) {
    EXPECT_EQ(std::string(p.path).rfind("/usr/share/", 0), 0u) << p.path;
    EXPECT_FALSE(std::string(p.licence).empty()) << p.path;
    EXPECT_FALSE(std::string(p.author).empty()) << p.path;
    mate += std::string(p.package) == "mate-backgrounds";
    plasma += std::string(p.package) == "plasma-workspace-wallpapers";
  }
  EXPECT_EQ(mate + plasma, int(debianPhotos().size()));
  EXPECT_GE(mate + plasma, 20);
  EXPECT_GT(mate, 0);
  EXPECT_GT(plasma, 0);
  EXPECT_NE(photoInstallHint().find("scripts/install-photos.sh"), std::string::npos);
}

TEST(Photos, CachedOncePerFolder) {
  TempDir dir;
  writePhoto(dir.str("a.png"), 8, 8, gradientPixel);
  const auto first = PhotoLibrary::cached(dir.str(), 64);
  const auto second = PhotoLibrary::cached(dir.str(), 64);
  EXPECT_EQ(first.get(), second.get());
  EXPECT_EQ(first->size(), 1u);
  EXPECT_NE(PhotoLibrary::cached(dir.str(), 32).get(), first.get()); // another size
  TempDir empty;
  EXPECT_TRUE(PhotoLibrary::cached(empty.str())->empty());
}

TEST(PhotoTexture, IdentityMappingIsThePhoto) {
  TempDir dir;
  writePhoto(dir.str("a.png"), 40, 30, gradientPixel);
  Texture t;
  t.pattern = Pattern::Photo;
  t.photo = PhotoLibrary::load({dir.str("a.png")})->photo(0);
  for (double s : {0.5, 3.25, 17.0, 39.5})
    for (double u : {0.5, 8.75, 29.5}) {
      const Eigen::Vector3d a = t.evaluate({s, u}), b = t.photo->sample(s, u);
      EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-12) << s << "," << u;
    }
  // Scale, offset, rotation and mirror move the lookup: p = offset + scale * R (-s, t).
  t.mapping.scale = 2.0;
  t.mapping.offset = Eigen::Vector2d(10, 7);
  t.angle = M_PI / 2;
  t.mapping.mirror = true;
  const Eigen::Vector3d a = t.evaluate({1.5, 2.0});
  // Mirrored (-1.5, 2) rotated by 90 degrees is (-2, -1.5); times 2, plus the offset: (6, 4).
  EXPECT_LT((a - t.photo->sample(6.0, 4.0)).cwiseAbs().maxCoeff(), 1e-9);
  Texture none;
  none.pattern = Pattern::Photo;
  expectError([&] { none.evaluate({0, 0}); }, {"photo texture without a photo"});
}

TEST(PhotoTexture, SceneTexturesAreDeterministicPerSeedAndDifferAcrossSeeds) {
  TempDir dir;
  writePhoto(dir.str("a.png"), 64, 48, gradientPixel);
  writePhoto(dir.str("b.png"), 50, 50, greenPixel);
  const auto lib = PhotoLibrary::load(findPhotoFiles(dir.str()));
  for (SceneStyle style : {SceneStyle::Objects, SceneStyle::World}) {
    SCOPED_TRACE(toString(style));
    SyntheticSceneParams p = photoParams(lib, 3);
    p.style = style;
    p.photoProbability = 1.0;
    const SyntheticScene a = generateSyntheticScene(p), b = generateSyntheticScene(p);
    EXPECT_EQ(sceneDescriptionJson(a, {}, 1), sceneDescriptionJson(b, {}, 1));
    const RenderedView va = renderView(a, 0), vb = renderView(b, 0);
    EXPECT_EQ(va.rgb, vb.rgb);
    for (const Texture* t : textures(a))
      EXPECT_EQ(t->pattern, Pattern::Photo);
    p.seed = 4;
    const SyntheticScene c = generateSyntheticScene(p);
    EXPECT_NE(sceneDescriptionJson(a, {}, 1), sceneDescriptionJson(c, {}, 1));
    EXPECT_NE(va.rgb, renderView(c, 0).rgb);
    // Per shape: different crops, scales and jitter across seeds.
    EXPECT_NE(a.background.texture.mapping.offset, c.background.texture.mapping.offset);
    EXPECT_NE(a.background.texture.mapping.scale, c.background.texture.mapping.scale);
  }
}

// world.bushSharedTexture: a bush's leaves take one photo with one colour jitter (foliage whose
// leaves differ only by crop and turn), placed exactly where they stand without it; every other
// surface keeps its own texture draw.
TEST(PhotoTexture, BushLeavesCanShareOnePhoto) {
  TempDir dir;
  writePhoto(dir.str("a.png"), 64, 48, gradientPixel);
  writePhoto(dir.str("b.png"), 50, 50, greenPixel);
  writePhoto(dir.str("c.png"), 40, 40, [](int x, int y) { return Eigen::Vector3i(200, x, y); });
  const auto lib = PhotoLibrary::load(findPhotoFiles(dir.str()));
  for (uint64_t seed = 0; seed < 4; ++seed) {
    SyntheticSceneParams p = photoParams(lib, seed);
    p.style = SceneStyle::World;
    p.photoProbability = 1.0;
    p.world.bushesMin = p.world.bushesMax = 2;
    const SyntheticScene each = generateSyntheticScene(p);
    p.world.bushSharedTexture = 1.0;
    const SyntheticScene shared = generateSyntheticScene(p);
    ASSERT_EQ(each.objects.size(), shared.objects.size());
    auto jitter = [](const Texture& t) {
      const PhotoMapping& m = t.mapping;
      return std::make_tuple(t.photo.get(), m.scale, m.gain[0], m.gain[1], m.gain[2], m.saturation,
                             m.contrast, m.brightness);
    };
    std::set<decltype(jitter(Texture{}))> eachLooks, sharedLooks;
    std::set<std::pair<double, double>> sharedCrops;
    int leaves = 0;
    for (size_t i = 0; i < shared.objects.size(); ++i) {
      const Shape &a = each.objects[i], &b = shared.objects[i];
      EXPECT_EQ(a.centre, b.centre) << "seed " << seed << ", object " << i;
      ASSERT_EQ(b.texture.pattern, Pattern::Photo);
      if (b.role != ShapeRole::Leaf) {
        EXPECT_EQ(jitter(a.texture), jitter(b.texture));
        EXPECT_EQ(a.texture.mapping.offset, b.texture.mapping.offset);
        continue;
      }
      ++leaves;
      eachLooks.insert(jitter(a.texture));
      sharedLooks.insert(jitter(b.texture));
      sharedCrops.insert({b.texture.mapping.offset.x(), b.texture.mapping.offset.y()});
    }
    EXPECT_GE(leaves, 40);
    EXPECT_EQ(sharedLooks.size(), 2u) << "seed " << seed; // one look per bush
    EXPECT_GT(eachLooks.size(), 30u) << "seed " << seed;  // a look per leaf
    EXPECT_EQ(sharedCrops.size(), size_t(leaves));        // each leaf its own crop
    const std::string json = sceneDescriptionJson(shared, {}, 1);
    EXPECT_NE(json.find("\"bush_shared_texture\": 1"), std::string::npos);
  }
}

TEST(PhotoTexture, SomeSurfacesStayProceduralBelowProbabilityOne) {
  TempDir dir;
  writePhoto(dir.str("a.png"), 32, 32, gradientPixel);
  const auto lib = PhotoLibrary::load(findPhotoFiles(dir.str()));
  int photo = 0, procedural = 0;
  for (uint64_t seed = 0; seed < 20; ++seed) {
    SyntheticSceneParams p = photoParams(lib, seed);
    p.photoProbability = 0.5;
    // The scene must outlive the loop: textures() points into it (a temporary in the range
    // expression would die before the loop body; AddressSanitizer found it).
    const auto scene = generateSyntheticScene(p);
    for (const Texture* t : textures(scene))
      (t->pattern == Pattern::Photo ? photo : procedural)++;
  }
  EXPECT_GT(photo, 20);
  EXPECT_GT(procedural, 20);
}

TEST(PhotoTexture, RenderedColoursComeFromThePhoto) {
  // A green photo: every photo-textured pixel is green whatever the crop, scale, rotation
  // and jitter (gain, contrast and brightness move it, saturation >= 0.6 keeps the hue), except
  // on textures the jitter turned grey (saturation 0). Procedural textures would fail this.
  TempDir dir;
  writePhoto(dir.str("green.png"), 64, 64, greenPixel);
  const auto lib = PhotoLibrary::load(findPhotoFiles(dir.str()));
  int checked = 0;
  for (uint64_t seed = 0; seed < 6; ++seed) {
    SyntheticSceneParams p = photoParams(lib, seed);
    p.photoProbability = 1.0;
    const SyntheticScene s = generateSyntheticScene(p);
    ASSERT_EQ(s.params.textures, TextureSet::Photo);
    const RenderedView v = renderView(s, 0);
    for (int y = 0; y < v.height; ++y)
      for (int x = 0; x < v.width; ++x) {
        const SurfaceHit hit =
            castRay(s, cameraRay(s.cameras[0], (x + 0.5) / v.width, (y + 0.5) / v.height));
        ASSERT_TRUE(hit.hit());
        const Texture& t = s.shape(hit.shape).texture;
        ASSERT_EQ(t.pattern, Pattern::Photo);
        EXPECT_EQ(t.photo->name, "green.png");
        if (t.mapping.saturation == 0)
          continue;
        const uint8_t* rgb = &v.rgb[(size_t(y) * size_t(v.width) + size_t(x)) * 3];
        ASSERT_GT(int(rgb[1]), int(rgb[0]) + 8) << "seed " << seed << " pixel " << x << "," << y;
        ASSERT_GT(int(rgb[1]), int(rgb[2]) + 8) << "seed " << seed << " pixel " << x << "," << y;
        ++checked;
      }
  }
  EXPECT_GT(checked, 4 * 48 * 32);
}

TEST(PhotoTexture, FallsBackToProceduralWithoutPhotos) {
  TempDir empty;
  const SyntheticSceneParams procedural = photoParams(nullptr, 7);
  SyntheticSceneParams plain = procedural;
  plain.textures = TextureSet::Procedural;
  const SyntheticScene reference = generateSyntheticScene(plain);
  for (const auto& lib :
       {std::shared_ptr<const PhotoLibrary>(), PhotoLibrary::cached(empty.str())}) {
    SyntheticSceneParams p = photoParams(lib, 7);
    const SyntheticScene s = generateSyntheticScene(p);
    EXPECT_EQ(s.params.textures, TextureSet::Procedural); // records what was used
    EXPECT_EQ(sceneDescriptionJson(s, {}, 1), sceneDescriptionJson(reference, {}, 1));
    EXPECT_EQ(renderView(s, 0).rgb, renderView(reference, 0).rgb);
  }
}

TEST(PhotoTexture, SceneJsonNamesThePhotos) {
  TempDir dir;
  writePhoto(dir.str("a.png"), 32, 32, gradientPixel);
  const auto lib = PhotoLibrary::cached(dir.str());
  const SyntheticSceneParams p = photoParams(lib, 1); // default probability: a command
  const SyntheticScene s = generateSyntheticScene(p);
  const std::string json = sceneDescriptionJson(s, {}, 1);
  for (const char* part :
       {"\"textures\": \"photo\"", "\"photos\": [", "\"a.png\"", "\"pattern\": \"photo\"",
        "\"photo\": \"a.png\"", "--textures photo", "--photo-dir '"})
    EXPECT_NE(json.find(part), std::string::npos) << part;
}

TEST(PhotoTexture, ParamsValidated) {
  SyntheticSceneParams p;
  p.photoProbability = 1.5;
  expectError([&] { p.validate(); }, {"'photoProbability' is 1.5"});
  expectError([] { parseTextureSet("photos", "--textures"); },
              {"--textures 'photos'", "\"procedural\"", "\"photo\""});
}
