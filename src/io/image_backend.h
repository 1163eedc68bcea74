// Decoded pixels as a reader gives them, and the table of the reader for the formats other
// than PNG: OpenImageIO, in a library of its own (oiio/) opened on first use, so a process
// that reads and writes only PNG never loads it and the hundreds of libraries it pulls in;
// likewise librsvg for vector drawings (svg/).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/views.h"

namespace cm {

/// Pixels at the file's own depth, channels interleaved, row 0 at the top; alpha, when
/// there is one, associated (premultiplied), as OpenImageIO gives it.
struct RawImage {
    int width = 0, height = 0, channels = 0;
    int bits = 8;      ///< 8 or 16 (unsigned integers), 32 (float)
    int file_bits = 8; ///< bits per channel in the file (16 for half floats read as float)
    int alpha = -1;    ///< the alpha channel, or -1
    std::vector<unsigned char> data;
};

/// The words of the error for an image over the pixel limit (after `cannot read image "x": `).
inline std::string over_pixel_limit(int width, int height, std::uint64_t limit) {
    const std::uint64_t pixels = std::uint64_t(width) * std::uint64_t(height);
    return "it is " + std::to_string(width) + " x " + std::to_string(height) + " pixels (" +
           std::to_string(pixels / 1'000'000) + " megapixels), over the limit of " + std::to_string(limit / 1'000'000) +
           " megapixels (--max-image-pixels)";
}

/// The reader and writer for the formats other than PNG. Each function returns false with
/// the reason in `why` (the words after `cannot read image "x": ` or the like).
struct ImageBackend {
    int abi;
    /// Reads a file; refuses more than `max_pixels` (0: no limit) from the header.
    bool (*read)(const std::string& file, std::uint64_t max_pixels, RawImage& out, std::string& why);
    /// Reads image bytes in memory (JPEG); refuses more than `max_pixels` (0: no limit).
    bool (*decode)(const unsigned char* data, std::size_t size, std::uint64_t max_pixels, RawImage& out,
                   std::string& why);
    /// Writes 1 to 4 float channels; the format follows the extension.
    bool (*write)(const Image& img, const std::string& file, std::string& why);
    /// Width and height from the header.
    bool (*size)(const std::string& file, int& width, int& height);
};

constexpr int kImageBackendAbi = 2;

/// The rasteriser of vector drawings (SVG), through librsvg: a library of its own (svg/),
/// opened on the first SVG file.
struct VectorBackend {
    int abi;
    /// Draws the file onto white paper, its longer side `longest` pixels, as 8-bit RGB;
    /// refuses more than `max_pixels` (0: no limit).
    bool (*rasterise)(const std::string& file, int longest, std::uint64_t max_pixels, RawImage& out, std::string& why);
};

constexpr int kVectorBackendAbi = 1;

} // namespace cm

/// The entry point of the backend library.
extern "C" const cm::ImageBackend* conceptmesh_image_backend();
/// The entry point of the vector backend library.
extern "C" const cm::VectorBackend* conceptmesh_vector_backend();
