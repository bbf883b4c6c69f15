// `simpli convert IN OUT [--format jpeg|lossless|glb]`: converts an MLI folder between the
// reference JPEG form and simpli's lossless float form (model/mli/files.h), or exports it as a
// binary glTF file (OUT ending in .glb, or --format glb; model/mli/glb.h). The input is read and
// validated completely before anything is written, and the output folder appears atomically
// (writeMLI), so a failure leaves no partial OUT and never damages an existing one. --force
// replaces only an MLI that simpli wrote and that holds nothing else (mli::mliReplaceRefusal), and
// never a folder that contains, or lies inside, the input.
#include "commands.h"
#include "output_file.h"

#include "simpli/error.h"
#include "simpli/model/io/staged_folder.h"
#include "simpli/model/mli/files.h"
#include "simpli/model/mli/glb.h"
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

namespace simpli::app {

namespace {

struct ConvertOptions {
  std::string input, output;
  std::string format = "auto";
  std::string depthDecoding = "viewer";
  std::string mesh = "adaptive"; ///< GLB export: the layers' meshes
  double meshTolerance = mli::AdaptiveMeshOptions{}.tolerancePixels;
  bool force = false;
};

/// Whether `inner` is `outer` or lies inside it, after resolving symbolic links and "..".
bool isSameOrInside(const std::filesystem::path& inner, const std::filesystem::path& outer) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path a = fs::weakly_canonical(fs::absolute(inner, ec), ec);
  const fs::path b = fs::weakly_canonical(fs::absolute(outer, ec), ec);
  if (ec)
    return false;
  auto ai = a.begin();
  for (auto bi = b.begin(); bi != b.end(); ++bi, ++ai) {
    if (bi->empty()) // a trailing separator
      continue;
    if (ai == a.end() || *ai != *bi)
      return false;
  }
  return true;
}

const char* formatName(mli::MLIFormat f) {
  return f == mli::MLIFormat::Lossless ? "lossless" : "jpeg";
}

// OUT is one file: written atomically; an existing file is replaced only with --force, and
// never a folder.
void exportGlb(const ConvertOptions& o, const mli::MLIReadOptions& readOptions) {
  if (isSameOrInside(o.output, o.input))
    fail("output ", o.output, " lies inside the input ", o.input,
         "; refusing to write into it (choose an output outside the input)");
  checkOutputFile(o.output, "output", o.force,
                  "a GLB export writes one file (e.g. " + o.output + "/scene.glb)");
  const mli::MLI mli = mli::readMLI(o.input, readOptions);
  mli::GlbOptions glbOptions;
  if (o.mesh == "adaptive") {
    mli::AdaptiveMeshOptions a;
    a.tolerancePixels = o.meshTolerance;
    glbOptions.layerMesh = mli::adaptiveGlbMesh(a);
  } else if (o.mesh != "per-texel") {
    fail("--mesh: unknown value '", o.mesh, "' (expected adaptive or per-texel)");
  }
  const mli::GlbSummary s = mli::writeGlb(mli, o.output, glbOptions);
  std::printf("exported %s (%d layers, %d x %d) -> %s (glTF binary: %d layers with triangles, "
              "%zu vertices, %zu triangles, %.1f MB)\n",
              o.input.c_str(), mli.numLayers(), mli.width(), mli.height(), o.output.c_str(),
              s.layers, s.vertices, s.triangles, double(s.bytes) / 1e6);
}

void runConvert(const ConvertOptions& o) {
  namespace fs = std::filesystem;
  mli::MLIReadOptions readOptions;
  if (o.depthDecoding == "viewer")
    readOptions.depthDecoding = mli::MLIDepthDecoding::Viewer;
  else if (o.depthDecoding == "bin-centre")
    readOptions.depthDecoding = mli::MLIDepthDecoding::BinCentre;
  else
    fail("--depth-decoding: unknown value '", o.depthDecoding, "' (expected viewer or bin-centre)");
  if (o.format != "auto" && o.format != "jpeg" && o.format != "lossless" && o.format != "glb")
    fail("--format: unknown value '", o.format, "' (expected jpeg, lossless, glb or auto)");
  const bool glb =
      o.format == "glb" || (o.format == "auto" && fs::path(o.output).extension() == ".glb");
  if (glb) {
    exportGlb(o, readOptions);
    return;
  }

  // Replacing OUT deletes it: never when it holds the input (or is it), and writing into the
  // input would change the MLI being read.
  if (isSameOrInside(o.input, o.output))
    fail("output ", o.output, " is or contains the input ", o.input,
         "; refusing to replace it (choose an output folder outside the input)");
  if (isSameOrInside(o.output, o.input))
    fail("output ", o.output, " lies inside the input ", o.input,
         "; refusing to write into it (choose an output folder outside the input)");

  // An output that cannot be written fails before the input is read.
  io::checkOutputLocation(o.output, "output");

  // Refuse to replace an existing, non-empty OUT unless asked to (writeMLI itself never
  // replaces a folder that is not an MLI written by simpli).
  std::error_code ec;
  if (fs::exists(o.output, ec) && !o.force &&
      !(fs::is_directory(o.output, ec) && fs::is_empty(o.output, ec)))
    fail("output ", o.output, " already exists (use --force to replace an existing MLI)");

  const mli::MLIFormat inFormat = mli::detectMLIFormat(o.input);
  const mli::MLI mli = mli::readMLI(o.input, readOptions);
  // auto: the other form, so that a plain `simpli convert IN OUT` always converts.
  const mli::MLIFormat outFormat =
      o.format == "jpeg" ? mli::MLIFormat::Jpeg
      : o.format == "lossless"
          ? mli::MLIFormat::Lossless
          : (inFormat == mli::MLIFormat::Jpeg ? mli::MLIFormat::Lossless : mli::MLIFormat::Jpeg);
  mli::writeMLI(o.output, mli, outFormat);
  std::printf("converted %s (%s, %d layers, %d x %d) -> %s (%s)\n", o.input.c_str(),
              formatName(inFormat), mli.numLayers(), mli.width(), mli.height(), o.output.c_str(),
              formatName(outFormat));
}

} // namespace

void addConvertCommand(CLI::App& app) {
  auto opts = std::make_shared<ConvertOptions>();
  CLI::App* cmd = app.add_subcommand(
      "convert", "Convert an MLI folder between the reference JPEG form and the lossless float "
                 "form (written atomically)");
  cmd->add_option("input", opts->input, "MLI folder to read (either form)")->required();
  cmd->add_option("output", opts->output, "MLI folder to write, or a .glb file (glTF export)")
      ->required();
  cmd->add_option("--format", opts->format,
                  "Output form: jpeg (reference, lossy), lossless (float TIFF, exact), glb "
                  "(binary glTF: textured layer meshes and the reference camera) or auto "
                  "(glb for an output ending in .glb, else the form the input is not in)")
      ->capture_default_str();
  cmd->add_option("--depth-decoding", opts->depthDecoding,
                  "How 8-bit depths of a JPEG input are decoded: viewer (lo + q (hi - lo)/255) "
                  "or bin-centre (lo + (q + 0.5)(hi - lo)/256)")
      ->capture_default_str();
  cmd->add_option("--mesh", opts->mesh,
                  "GLB export: adaptive (density follows the depth, mli/adaptive_mesh.h) or "
                  "per-texel (one vertex per texel, as the rasterizer draws it)")
      ->capture_default_str();
  cmd->add_option("--mesh-tolerance", opts->meshTolerance,
                  "GLB export, adaptive mesh: largest reprojection error in pixels for a camera "
                  "moved off the reference one")
      ->capture_default_str();
  cmd->add_flag("--force", opts->force,
                "Replace an existing MLI folder at the output (only one simpli wrote, holding "
                "nothing else), or an existing .glb file");
  cmd->callback([opts] { runConvert(*opts); });
}

} // namespace simpli::app
