// GLB export, read back with an independent glTF 2.0 parser (tinygltf, Debian's
// libtinygltf-dev): structure, accessors, texture pixels against the layer RGBA, texture
// coordinates at texel centres, the camera, the frame transform on analytic points, dropped
// transparent triangles and layers, bad input.
#include "mli_test_util.h"

#include "simpli/model/mli/glb.h"
#include "simpli/model/mli/mesh.h"

#include <opencv2/imgcodecs.hpp>
#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>

namespace simpli::test {
namespace {

tinygltf::Model parse(const std::vector<std::uint8_t>& bytes) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(),
                                              static_cast<unsigned int>(bytes.size()));
  EXPECT_TRUE(ok) << "tinygltf: " << err;
  EXPECT_TRUE(err.empty()) << err;
  return model;
}

// The float (or uint32) elements of an accessor.
template <typename T> std::vector<T> elements(const tinygltf::Model& m, int accessor) {
  const tinygltf::Accessor& a = m.accessors.at(size_t(accessor));
  const tinygltf::BufferView& v = m.bufferViews.at(size_t(a.bufferView));
  const int components = tinygltf::GetNumComponentsInType(a.type);
  std::vector<T> out(a.count * size_t(components));
  std::memcpy(out.data(), m.buffers[size_t(v.buffer)].data.data() + v.byteOffset + a.byteOffset,
              out.size() * sizeof(T));
  return out;
}

// An MLI of L layers at depths 2, 4, ... with an opaque left half and a transparent right half
// in every layer but the last, which is fully transparent.
mli::MLI halfOpaqueMLI(int L, int W, int H) {
  mli::MLI m = randomMLI(L, H, W, 3, 1.0f, 2.0f);
  for (int k = 0; k < L; ++k)
    for (int i = 0; i < H; ++i)
      for (int j = 0; j < W; ++j) {
        const size_t p = size_t(i) * W + j;
        m.layers[size_t(k)].depth[p] = float(2 * (L - k));
        float& a = m.layers[size_t(k)].rgba[4 * p + 3];
        a = (k == L - 1 || j >= W / 2) ? 0.0f : 0.25f + 0.5f * float(j) / W;
      }
  return m;
}

} // namespace

TEST(Glb, ReadsBackAsTheLayersTexturesAndCamera) {
  const int W = 12, H = 8, L = 3;
  const mli::MLI m = halfOpaqueMLI(L, W, H);
  mli::GlbSummary summary;
  const std::vector<std::uint8_t> bytes = mli::encodeGlb(m, {}, &summary);
  EXPECT_EQ(summary.bytes, bytes.size());
  const tinygltf::Model g = parse(bytes);
  EXPECT_EQ(g.asset.version, "2.0");
  // The last layer is fully transparent: left out; the others back to front.
  ASSERT_EQ(summary.layers, 2);
  ASSERT_EQ(g.meshes.size(), 2u);
  EXPECT_EQ(g.meshes[0].name, "layer 00");
  EXPECT_EQ(g.meshes[1].name, "layer 01");
  ASSERT_EQ(g.scenes.size(), 1u);
  const tinygltf::Node& root = g.nodes.at(size_t(g.scenes[0].nodes.at(0)));
  EXPECT_EQ(root.name, "MLI");
  ASSERT_EQ(root.children.size(), 2u);

  for (int k = 0; k < 2; ++k) {
    const tinygltf::Primitive& prim = g.meshes[size_t(k)].primitives.at(0);
    const tinygltf::Material& mat = g.materials.at(size_t(prim.material));
    EXPECT_EQ(mat.alphaMode, "BLEND");
    EXPECT_TRUE(mat.doubleSided);
    EXPECT_EQ(mat.extensions.count("KHR_materials_unlit"), 1u);
    const std::vector<float> pos = elements<float>(g, prim.attributes.at("POSITION"));
    const std::vector<float> uv = elements<float>(g, prim.attributes.at("TEXCOORD_0"));
    const std::vector<std::uint32_t> idx = elements<std::uint32_t>(g, prim.indices);
    ASSERT_EQ(pos.size(), size_t(3 * W * H));
    ASSERT_EQ(uv.size(), size_t(2 * W * H));
    // Triangles only where some vertex is visible: the left half (columns 0 .. W/2 - 1 and
    // the quads touching them), never a quad entirely in the transparent right half.
    ASSERT_FALSE(idx.empty());
    for (size_t t = 0; t < idx.size(); t += 3) {
      int minCol = W;
      for (int c = 0; c < 3; ++c)
        minCol = std::min(minCol, int(idx[t + c] % W));
      EXPECT_LT(minCol, W / 2) << "triangle " << t / 3 << " of layer " << k;
    }
    // Vertex (i, j) is mliVertex at the layer depth; uv at the texel centre.
    const mli::MLIMesh mesh = mli::buildLayerMesh(m, k);
    for (int p = 0; p < W * H; ++p) {
      for (int a = 0; a < 3; ++a)
        EXPECT_FLOAT_EQ(pos[size_t(3 * p + a)], mesh.points[size_t(3 * p + a)]);
      EXPECT_NEAR(uv[size_t(2 * p)], (p % W + 0.5) / W, 1e-6);
      EXPECT_NEAR(uv[size_t(2 * p + 1)], (p / W + 0.5) / H, 1e-6);
    }
    // The texture: the layer's RGBA at 8 bits, straight alpha, row 0 at the top.
    const tinygltf::Texture& tex =
        g.textures.at(size_t(mat.pbrMetallicRoughness.baseColorTexture.index));
    const tinygltf::Image& im = g.images.at(size_t(tex.source));
    const tinygltf::BufferView& v = g.bufferViews.at(size_t(im.bufferView));
    const std::vector<std::uint8_t> png(g.buffers[0].data.begin() + long(v.byteOffset),
                                        g.buffers[0].data.begin() +
                                            long(v.byteOffset + v.byteLength));
    EXPECT_EQ(im.mimeType, "image/png");
    const cv::Mat bgra = cv::imdecode(png, cv::IMREAD_UNCHANGED);
    ASSERT_EQ(bgra.type(), CV_8UC4);
    ASSERT_EQ(bgra.cols, W);
    ASSERT_EQ(bgra.rows, H);
    for (int i = 0; i < H; ++i)
      for (int j = 0; j < W; ++j) {
        const float* c = m.layers[size_t(k)].rgba.data() + 4 * (size_t(i) * W + j);
        const cv::Vec4b b = bgra.at<cv::Vec4b>(i, j);
        EXPECT_EQ(b[2], std::lround(255.0 * c[0]));
        EXPECT_EQ(b[1], std::lround(255.0 * c[1]));
        EXPECT_EQ(b[0], std::lround(255.0 * c[2]));
        EXPECT_EQ(b[3], std::lround(255.0 * c[3]));
      }
  }
}

TEST(Glb, CameraAndRootTransformShowTheLayersAsTheReferenceCameraSawThem) {
  const int W = 16, H = 12;
  mli::MLI m = halfOpaqueMLI(2, W, H);
  const tinygltf::Model g = parse(mli::encodeGlb(m));
  const tinygltf::Node& root = g.nodes.at(size_t(g.scenes[0].nodes.at(0)));
  const tinygltf::Node& camNode = g.nodes.at(size_t(g.scenes[0].nodes.at(1)));
  ASSERT_EQ(camNode.camera, 0);
  EXPECT_TRUE(camNode.matrix.empty() && camNode.translation.empty() && camNode.rotation.empty())
      << "the camera sits at the origin";
  const tinygltf::PerspectiveCamera& p = g.cameras.at(0).perspective;
  EXPECT_NEAR(p.yfov, 2 * std::atan(0.5 / m.camera.fy), 1e-12);
  EXPECT_NEAR(p.aspectRatio, m.camera.fy / m.camera.fx, 1e-12);
  ASSERT_EQ(root.matrix.size(), 16u);
  Eigen::Matrix4d M;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      M(r, c) = root.matrix[size_t(4 * c + r)];
  // Every vertex, through the root matrix, lands where a glTF camera (-z forward, +y up) with
  // the reference camera's intrinsics projects it to its texel: u = fx x / (-z) + cx,
  // v = -fy y / (-z) + cy, at depth -z = the layer depth.
  const tinygltf::Primitive& prim = g.meshes[0].primitives.at(0);
  const std::vector<float> pos = elements<float>(g, prim.attributes.at("POSITION"));
  for (int i = 0; i < H; i += 3)
    for (int j = 0; j < W; j += 5) {
      const size_t q = size_t(i) * W + j;
      const Eigen::Vector4d x = M * Eigen::Vector4d(pos[3 * q], pos[3 * q + 1], pos[3 * q + 2], 1);
      const double depth = -x.z();
      EXPECT_NEAR(depth, m.layers[0].depth[q], 1e-4);
      EXPECT_NEAR(m.camera.fx * x.x() / depth + m.camera.cx, double(j) / (W - 1), 1e-5);
      EXPECT_NEAR(-m.camera.fy * x.y() / depth + m.camera.cy, double(i) / (H - 1), 1e-5);
    }
}

TEST(Glb, UsesTheGivenLayerMeshAndWritesAtomically) {
  const mli::MLI m = halfOpaqueMLI(2, 10, 6);
  mli::GlbOptions o;
  int calls = 0;
  o.layerMesh = [&](const mli::MLI& mli, int k, const mli::MLIMeshOptions& mo) {
    ++calls;
    mli::MLIMesh mesh = mli::buildLayerMesh(mli, k, mo);
    if (mesh.triangles.size() > 3)
      mesh.triangles.resize(3); // one triangle
    return mesh;
  };
  TempDir dir;
  const mli::GlbSummary s = mli::writeGlb(m, dir.str("a.glb"), o);
  EXPECT_EQ(calls, 2);
  EXPECT_EQ(s.triangles, 1u);
  EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"a.glb"}) << "no temporary left";
  const std::string text = readText(dir / "a.glb");
  const tinygltf::Model g = parse(std::vector<std::uint8_t>(text.begin(), text.end()));
  EXPECT_EQ(g.meshes.size(), 1u);
}

// Constant-depth layers through the adaptive mesh: a handful of triangles instead of one pair
// per texel quad, every vertex still where the reference camera sees its texel, with uv at that
// texel's centre.
TEST(Glb, AdaptiveMeshesOfPlanesAreSmallAndExact) {
  const int W = 40, H = 24;
  const mli::MLI m = halfOpaqueMLI(3, W, H);
  mli::GlbOptions o;
  o.layerMesh = mli::adaptiveGlbMesh({});
  mli::GlbSummary adaptive, perTexel;
  const tinygltf::Model g = parse(mli::encodeGlb(m, o, &adaptive));
  mli::encodeGlb(m, {}, &perTexel);
  EXPECT_EQ(adaptive.layers, 2);
  EXPECT_LT(adaptive.triangles * 20, perTexel.triangles)
      << adaptive.triangles << " vs " << perTexel.triangles;
  for (const tinygltf::Mesh& mesh : g.meshes) {
    const tinygltf::Primitive& prim = mesh.primitives.at(0);
    const std::vector<float> pos = elements<float>(g, prim.attributes.at("POSITION"));
    const std::vector<float> uv = elements<float>(g, prim.attributes.at("TEXCOORD_0"));
    ASSERT_EQ(pos.size() / 3, uv.size() / 2);
    const int k = mesh.name == "layer 00" ? 0 : 1;
    const double d = m.layers[size_t(k)].depth[0];
    for (size_t p = 0; p < uv.size() / 2; ++p) {
      // uv -> grid (x, y) -> the back-projection at the layer depth.
      const double x = uv[2 * p] * W - 0.5, y = uv[2 * p + 1] * H - 0.5;
      const double u = x / (W - 1), v = y / (H - 1);
      const Eigen::Vector3d c(d * (u - m.camera.cx) / m.camera.fx,
                              d * (v - m.camera.cy) / m.camera.fy, d);
      const Eigen::Vector3d w = m.camera.R.transpose() * (c - m.camera.t);
      for (int a = 0; a < 3; ++a)
        EXPECT_NEAR(pos[3 * p + size_t(a)], w[a], 1e-4) << mesh.name << " vertex " << p;
    }
  }
}

TEST(Glb, RejectsAnInvalidMLIAndNamesTheValue) {
  mli::MLI m = halfOpaqueMLI(2, 10, 6);
  m.layers[1].depth[7] = -1.0f;
  expectError([&] { mli::encodeGlb(m); }, {"GLB export", "layer 1", "-1"});
  TempDir dir;
  expectError([&] { mli::writeGlb(m, dir.str("x.glb")); }, {"layer 1"});
  EXPECT_TRUE(listDir(dir.path()).empty()) << "a failed export writes nothing";
}

} // namespace simpli::test
