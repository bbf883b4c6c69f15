// MLI -> binary glTF 2.0 (mli/glb.h). Layout: a 12-byte header, a JSON chunk, a BIN chunk, each
// chunk 4-byte aligned (JSON padded with spaces, BIN with zeros), as the glTF 2.0 spec's GLB
// section says.
#include "simpli/model/mli/glb.h"

#include "simpli/error.h"
#include "simpli/model/io/files.h"

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace simpli::mli {
namespace {
using nlohmann::json;

constexpr std::uint32_t kMagic = 0x46546C67, kJsonChunk = 0x4E4F534A, kBinChunk = 0x004E4942;
constexpr int kFloat = 5126, kUnsignedInt = 5125, kArrayBuffer = 34962, kElementArray = 34963;
constexpr int kLinear = 9729, kClampToEdge = 33071;

// The BIN chunk and the JSON arrays that describe its pieces.
class GlbBuilder {
public:
  json doc = json::object();
  std::vector<std::uint8_t> bin;

  GlbBuilder() {
    for (const char* k :
         {"bufferViews", "accessors", "images", "textures", "materials", "meshes", "nodes"})
      doc[k] = json::array();
  }
  int view(const void* data, std::size_t bytes, int target) {
    while (bin.size() % 4)
      bin.push_back(0);
    const std::size_t offset = bin.size();
    bin.resize(offset + bytes);
    std::memcpy(bin.data() + offset, data, bytes);
    json v = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}};
    if (target)
      v["target"] = target;
    doc["bufferViews"].push_back(v);
    return int(doc["bufferViews"].size()) - 1;
  }
  int accessor(int view, int componentType, std::size_t count, const char* type,
               const json& min = nullptr, const json& max = nullptr) {
    json a = {
        {"bufferView", view}, {"componentType", componentType}, {"count", count}, {"type", type}};
    if (!min.is_null()) {
      a["min"] = min;
      a["max"] = max;
    }
    doc["accessors"].push_back(a);
    return int(doc["accessors"].size()) - 1;
  }
  int push(const char* array, const json& item) {
    doc[array].push_back(item);
    return int(doc[array].size()) - 1;
  }
};

// Layer k's RGBA as an 8-bit PNG (straight alpha, rows top to bottom).
std::vector<std::uint8_t> layerPng(const MLI& mli, int k) {
  const int W = mli.width(), H = mli.height();
  const std::vector<float>& rgba = mli.layers[std::size_t(k)].rgba;
  cv::Mat bgra(H, W, CV_8UC4);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const float* p = rgba.data() + 4 * (std::size_t(y) * W + x);
      auto q = [](float v) { return std::uint8_t(std::lround(255.0 * std::clamp(v, 0.0f, 1.0f))); };
      bgra.at<cv::Vec4b>(y, x) = cv::Vec4b(q(p[2]), q(p[1]), q(p[0]), q(p[3]));
    }
  std::vector<std::uint8_t> png;
  if (!cv::imencode(".png", bgra, png))
    fail("GLB: cannot encode layer ", k, " as PNG");
  return png;
}

// Column-major 4x4 of F [R | t] (world -> reference camera -> glTF camera axes).
json rootMatrix(const scene::Camera& c) {
  const double F[3] = {1, -1, -1};
  json m = json::array();
  for (int col = 0; col < 4; ++col)
    for (int row = 0; row < 4; ++row) {
      if (row == 3)
        m.push_back(col == 3 ? 1.0 : 0.0);
      else
        m.push_back(F[row] * (col < 3 ? c.R(row, col) : c.t(row)));
    }
  return m;
}

void addLayer(GlbBuilder& g, const MLI& mli, int k, const MLIMesh& mesh, GlbSummary& summary) {
  const std::size_t n = mesh.numPoints();
  std::vector<float> uv(2 * n);
  for (std::size_t p = 0; p < n; ++p) {
    uv[2 * p] = texelCentre(mesh.uv[2 * p], mli.width());
    uv[2 * p + 1] = texelCentre(mesh.uv[2 * p + 1], mli.height());
  }
  json lo = json::array(), hi = json::array();
  for (int a = 0; a < 3; ++a) {
    float mn = std::numeric_limits<float>::infinity(), mx = -mn;
    for (std::size_t p = 0; p < n; ++p) {
      mn = std::min(mn, mesh.points[3 * p + a]);
      mx = std::max(mx, mesh.points[3 * p + a]);
    }
    lo.push_back(mn);
    hi.push_back(mx);
  }
  std::vector<std::uint32_t> indices(mesh.triangles.begin(), mesh.triangles.end());
  const int position = g.accessor(g.view(mesh.points.data(), 4 * mesh.points.size(), kArrayBuffer),
                                  kFloat, n, "VEC3", lo, hi);
  const int texcoord =
      g.accessor(g.view(uv.data(), 4 * uv.size(), kArrayBuffer), kFloat, n, "VEC2");
  const int index = g.accessor(g.view(indices.data(), 4 * indices.size(), kElementArray),
                               kUnsignedInt, indices.size(), "SCALAR");
  const std::vector<std::uint8_t> png = layerPng(mli, k);
  const int image = g.push(
      "images", {{"bufferView", g.view(png.data(), png.size(), 0)}, {"mimeType", "image/png"}});
  const int texture = g.push("textures", {{"sampler", 0}, {"source", image}});
  char name[32];
  std::snprintf(name, sizeof name, "layer %02d", k);
  const int material =
      g.push("materials", {{"name", name},
                           {"pbrMetallicRoughness",
                            {{"baseColorTexture", {{"index", texture}}},
                             {"metallicFactor", 0.0},
                             {"roughnessFactor", 1.0}}},
                           {"alphaMode", "BLEND"},
                           {"doubleSided", true},
                           {"extensions", {{"KHR_materials_unlit", json::object()}}}});
  const int meshIndex = g.push(
      "meshes", {{"name", name},
                 {"primitives",
                  json::array({{{"attributes", {{"POSITION", position}, {"TEXCOORD_0", texcoord}}},
                                {"indices", index},
                                {"material", material},
                                {"mode", 4}}})}});
  g.doc["nodes"][0]["children"].push_back(g.push("nodes", {{"name", name}, {"mesh", meshIndex}}));
  summary.layers += 1;
  summary.vertices += n;
  summary.triangles += mesh.numTriangles();
}

void appendChunk(std::vector<std::uint8_t>& out, std::uint32_t type,
                 const std::vector<std::uint8_t>& data, std::uint8_t pad) {
  const std::uint32_t length = std::uint32_t((data.size() + 3) / 4 * 4);
  const std::uint32_t header[2] = {length, type};
  const auto* h = reinterpret_cast<const std::uint8_t*>(header);
  out.insert(out.end(), h, h + 8);
  out.insert(out.end(), data.begin(), data.end());
  out.resize(out.size() + (length - data.size()), pad);
}

} // namespace

std::function<MLIMesh(const MLI&, int, const MLIMeshOptions&)>
adaptiveGlbMesh(const AdaptiveMeshOptions& options) {
  validateAdaptiveMeshOptions(options);
  return [options](const MLI& mli, int k, const MLIMeshOptions& meshOptions) {
    AdaptiveMeshOptions o = options;
    o.alphaThreshold = std::max(o.alphaThreshold, meshOptions.dropAlphaBelow);
    const AdaptiveLayerMesh a = buildAdaptiveLayerMesh(mli, k, o);
    MLIMesh m;
    m.points = a.points;
    m.depth = a.depth;
    m.triangles = a.triangles;
    m.uv.resize(a.grid.size());
    for (std::size_t p = 0; p < a.grid.size(); p += 2) { // grid (x, y) in texels -> corner-grid uv
      m.uv[p] = a.grid[p] / float(mli.width() - 1);
      m.uv[p + 1] = a.grid[p + 1] / float(mli.height() - 1);
    }
    m.rgba.assign(4 * a.depth.size(), 0.0f); // not used: the texture holds the colours
    return m;
  };
}

std::vector<std::uint8_t> encodeGlb(const MLI& mli, const GlbOptions& options,
                                    GlbSummary* summaryOut) {
  validateMLI(mli, "GLB export");
  GlbBuilder g;
  GlbSummary summary;
  const scene::Camera& c = mli.camera;
  g.doc["asset"] = {{"version", "2.0"}, {"generator", "simpli"}};
  g.doc["extensionsUsed"] = json::array({"KHR_materials_unlit"});
  g.doc["samplers"] = json::array({{{"magFilter", kLinear},
                                    {"minFilter", kLinear},
                                    {"wrapS", kClampToEdge},
                                    {"wrapT", kClampToEdge}}});
  g.doc["cameras"] = json::array(
      {{{"name", "reference camera"},
        {"type", "perspective"},
        {"perspective",
         {{"yfov", 2.0 * std::atan(0.5 / c.fy)},
          {"aspectRatio", c.fy / c.fx},
          {"znear",
           0.01 * std::max(1e-6, double(*std::min_element(mli.layers.front().depth.begin(),
                                                          mli.layers.front().depth.end())))}}}}});
  g.push("nodes", {{"name", "MLI"}, {"matrix", rootMatrix(c)}, {"children", json::array()}});
  g.push("nodes", {{"name", "reference camera"}, {"camera", 0}});
  MLIMeshOptions meshOptions;
  meshOptions.dropAlphaBelow = options.dropAlphaBelow;
  for (int k = 0; k < mli.numLayers(); ++k) { // back to front
    const MLIMesh mesh = options.layerMesh ? options.layerMesh(mli, k, meshOptions)
                                           : buildLayerMesh(mli, k, meshOptions);
    if (mesh.numTriangles() > 0)
      addLayer(g, mli, k, mesh, summary);
  }
  g.doc["scenes"] = json::array({{{"name", "MLI"}, {"nodes", json::array({0, 1})}}});
  g.doc["scene"] = 0;
  g.doc["extras"] = {{"simpli_mli",
                      {{"layers", mli.numLayers()},
                       {"width", mli.width()},
                       {"height", mli.height()},
                       {"intrinsics", {c.fx, c.fy, c.cx, c.cy}}}}};
  for (const char* k : {"images", "textures", "materials", "meshes", "accessors", "bufferViews"})
    if (g.doc[k].empty())
      g.doc.erase(k);
  if (!g.bin.empty())
    g.doc["buffers"] = json::array({{{"byteLength", (g.bin.size() + 3) / 4 * 4}}});

  const std::string text = g.doc.dump();
  std::vector<std::uint8_t> out(12);
  appendChunk(out, kJsonChunk, std::vector<std::uint8_t>(text.begin(), text.end()), ' ');
  if (!g.bin.empty())
    appendChunk(out, kBinChunk, g.bin, 0);
  if (out.size() > std::numeric_limits<std::uint32_t>::max())
    fail("GLB export: ", out.size(), " bytes is beyond the 4 GiB a GLB file can hold");
  const std::uint32_t header[3] = {kMagic, 2, std::uint32_t(out.size())}; // little-endian hosts
  std::memcpy(out.data(), header, 12);
  summary.bytes = out.size();
  if (summaryOut)
    *summaryOut = summary;
  return out;
}

GlbSummary writeGlb(const MLI& mli, const std::string& path, const GlbOptions& options) {
  GlbSummary summary;
  const std::vector<std::uint8_t> bytes = encodeGlb(mli, options, &summary);
  io::writeFileAtomically(path, bytes.data(), bytes.size());
  return summary;
}

} // namespace simpli::mli
