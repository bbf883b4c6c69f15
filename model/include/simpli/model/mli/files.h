#pragma once
// MLI files. An MLI is a folder; two forms exist and readMLI tells them apart by meta.json:
//
// Jpeg (the reference / project-page format, spec §10.2; XX = 00, 01, ...,
//   00 = farthest layer):
//   layer_XX.jpg        RGB trunc(255 clip(rgb, 0, 1)), quality 75, 4:2:0, optimised Huffman
//   layer_alpha_XX.jpg  trunc(255 alpha) in three identical channels, quality 75, 4:2:0
//   layer_depth_XX.jpg  one channel, quality 100, q = clip(floor(256 (D - lo)/(hi - lo)), 0, 255)
//                       with lo, hi = min, max of the layer's depth (hi == lo: q = 0)
//   meta.json           {"layer_depth_XX": [lo, hi], "frame_size": [H, W],
//                        "extrinsic_re": 12 numbers, world->camera [R|t] 3x4 row-major,
//                        "intrinsics_re": 9 numbers, relative K row-major}
//   Lossy: 8-bit colour and alpha, 8-bit depth per layer range, JPEG error on top.
//
// Lossless (ours): meta.json with the same keys plus "format": "simpli-mli-float" and
//   "num_layers": L; per layer layer_rgba_XX.tiff (32-bit float RGBA, 4 samples per pixel,
//   uncompressed) and layer_depth_XX.tiff (32-bit float, 1 sample). The floats round-trip
//   bit-exactly (checked by the tests with the system OpenCV/libtiff).
//
// Both forms also carry "written_by": "simpli" in meta.json (readers ignore it): the mark that
// lets a later write replace the folder (see writeMLI).
//
// Writes are atomic (io/staged_folder.h): everything goes into a hidden staging sibling that
// replaces the target in one step only when complete, so a failed or killed write never leaves a
// partial MLI, and an existing MLI at the target is replaced only by a complete one.
#include <functional>
#include <string>
#include <vector>

#include "simpli/model/mli/mli.h"

namespace simpli::mli {

enum class MLIFormat { Jpeg, Lossless };

/// Limits readMLI checks in meta.json before it allocates anything: at most kMaxMLILayers
/// layers (the reference's configs have 4 and 8), and at most kMaxMLITexels texels over all
/// layers (layers x H x W; 20 bytes each in memory, so at most 1.25 GiB), so that a corrupt
/// frame_size or thousands of layer_depth_XX keys are refused instead of exhausting memory.
inline constexpr int kMaxMLILayers = 64;
inline constexpr long long kMaxMLITexels = 1LL << 26;

/// How 8-bit depth codes q of the Jpeg form become depths.
enum class MLIDepthDecoding {
  /// D = lo + q (hi - lo)/255, as the official web viewer decodes (maps q = 0..255 onto exactly
  /// [lo, hi]); error against the encoder's bins < one step (hi - lo)/255.
  Viewer,
  /// D = lo + (q + 0.5)(hi - lo)/256: the centre of the encoder's bin, the exact inverse
  /// (error <= half a step), but never reaches lo or hi.
  BinCentre,
};

struct MLIReadOptions {
  MLIDepthDecoding depthDecoding = MLIDepthDecoding::Viewer;
};

/// Detects the form of the MLI folder at `path` from its meta.json (throws if it is neither).
MLIFormat detectMLIFormat(const std::string& path);

/// Reads either form. Alpha is taken as stored: files from the reference's render script have
/// layer 00 forced opaque, those from its colab (and the project page) do not; both are
/// accepted and neither is assumed. The result passes validateMLI. Errors name the file, the
/// field and the value.
MLI readMLI(const std::string& path, const MLIReadOptions& options = {});

/// What an output folder may hold besides one MLI's own files (a command's other outputs), for
/// mliReplaceRefusal.
struct MLIFolderExtras {
  /// Subfolders that are MLIs written by simpli themselves (`simpli infer`'s "lossless").
  std::vector<std::string> mliFolders;
  /// Other regular files the command writes, by name (`simpli infer`'s render_KKK.png); none
  /// when empty.
  std::function<bool(const std::string& name)> isExtraFile;
};

/// Why the existing, non-empty folder `path` must not be replaced by a new MLI; "" when it may.
/// It may when it is verifiably an MLI written by simpli and nothing else: its meta.json is
/// valid and has "written_by": "simpli", and every entry is a regular file of that MLI's form
/// and layer count (meta.json and its layer_*_XX files) or one that `extras` names. A folder
/// holding anything else (a user's notes.txt, photos/) is refused, never emptied.
std::string mliReplaceRefusal(const std::string& path, const MLIFolderExtras& extras = {});

/// Validates `mli` (nothing is created when that fails), then writes it atomically as the
/// folder `path`. An existing folder at `path` is replaced only if it is empty or
/// mliReplaceRefusal accepts it; anything else is refused with an error naming the folder and
/// the entry that is not simpli's.
void writeMLI(const std::string& path, const MLI& mli, MLIFormat format = MLIFormat::Jpeg);

/// Writes the files of `mli` into the existing folder `folder`, not atomically: the building
/// block of an output made of several parts that is staged as a whole (io::StagedFolder, as
/// `simpli infer` does). Validates `mli` first.
void writeMLIFiles(const std::string& folder, const MLI& mli, MLIFormat format);

} // namespace simpli::mli
