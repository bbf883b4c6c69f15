#pragma once
// "WIDTHxHEIGHT", the one spelling of an image size on the command line and in configs (e.g.
// "512x384"). Every --size option and config field parses it here, each with its own bounds, so
// they all accept the same text and name the same faults.
#include "simpli/model/io/image.h" // ImageSize

#include <string>

namespace simpli::io {

/// What a caller accepts: each side in [minSide, maxSide] and a multiple of `multiple`.
struct ImageSizeLimits {
  int minSide = 1;
  int maxSide = 16384;
  int multiple = 1;
};

/// Parses `text` (spaces around the numbers and an upper-case X allowed). Throws simpli::Error
/// "<what> '<text>': ..." naming the fault: not WIDTHxHEIGHT, or a side outside the limits.
ImageSize parseImageSize(const std::string& text, const std::string& what,
                         const ImageSizeLimits& limits = {});

} // namespace simpli::io
