#pragma once
// Decoding image files (PNG, JPEG, TIFF) with the checks every reader of them needs: the
// declared size against kMaxImagePixels (io/image_header.h) and completeness, before OpenCV
// sees the bytes. libjpeg decodes a truncated JPEG with only a warning on stderr (the missing
// rows come out grey) and libpng / libtiff print their own errors, so a cut file is recognised
// here and named instead. Used by io::readImage and the MLI layer reader (mli/files_image.cpp).
#include <opencv2/core.hpp>

#include <cstddef>
#include <string>

namespace simpli::io {

/// Why the image file in `data` is cut short: a PNG that ends before its IEND chunk, a JPEG
/// before its end-of-image marker, a TIFF whose directory, tag values, strips or tiles reach past
/// the end; or why its
/// data cannot hold the size its header declares (less than deflate's densest PNG, less than one
/// bit per 8x8 block of a Huffman-coded JPEG: a corrupt header, or a cut file with an end
/// marker). Empty when it is complete, or when its structure is not recognised (the decoder
/// then judges it).
std::string imageTruncation(const unsigned char* data, std::size_t size);

/// Reads and decodes `path` with cv::imdecode(flags). Throws simpli::Error "<what> '<path>':
/// ..." when the file is missing, empty, declares more than kMaxImagePixels pixels, is
/// truncated (imageTruncation) or cannot be decoded.
cv::Mat decodeImageFile(const std::string& path, int imreadFlags, const std::string& what);

} // namespace simpli::io
