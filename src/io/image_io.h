// Reading and writing images: PNG through libpng, SVG drawings rasterised by librsvg, every
// other format OpenImageIO reads through OpenImageIO; each library opened on the first image
// that needs it.
#pragma once
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/views.h"

namespace cm {

struct ImageInfo {
    bool has_alpha = false; ///< the file has an alpha channel
    int bits = 8;           ///< bits per channel in the file
};

/// The longer side, in pixels, at which read_image() draws an SVG file unless told.
inline constexpr int kDefaultSvgSize = 2048;

/// True for an SVG file: by its extension (.svg, .svgz, any case) or, whatever the
/// extension, an `<svg` element in its first kilobyte.
bool is_svg_file(const std::filesystem::path& file);

/// Reads any format OpenImageIO reads into float RGBA in [0,1] (grey is
/// replicated; missing alpha becomes 1). Throws cm::Error naming the file.
/// `keep_bytes`: an 8-bit file is kept as bytes (Image::bytes, a quarter of the memory):
/// RGBA, or one channel for grey without alpha (a sixteenth; Image::rgba and Image::at give
/// the same values as for its RGBA expansion).
/// An SVG file (is_svg_file()) is drawn by librsvg onto white paper, its longer side
/// `svg_size` pixels, as 8-bit RGB with no alpha.
Image read_image(const std::filesystem::path& file, ImageInfo* info = nullptr, bool keep_bytes = false,
                 int svg_size = kDefaultSvgSize);

/// Writes an image (1, 3 or 4 channels, float in [0,1], or 8-bit); the format follows the
/// extension (.png is 8-bit; .tif/.exr keep more). Writes exactly to `file`.
void write_image(const Image& img, const std::filesystem::path& file);

/// The byte the PNG writer stores for the float sample `v`, as OpenImageIO 2.4 converts a
/// row of samples: in fours, rounded half away from zero; the row's last n % 4 samples
/// (`tail`) as trunc(v * 255 + 0.5). Clamped to [0, 255], NaN to 0. An 8-bit image filled
/// with these bytes writes the same PNG as the float image.
inline std::uint8_t png_byte(float v, bool tail) {
    if (tail) {
        float s = v * 255.0f + 0.5f;
        if (!(0.0f <= s)) s = 0.0f;
        if (s > 255.0f) s = 255.0f;
        return static_cast<std::uint8_t>(s);
    }
    // roundf, clamped, without a call per sample: 0 for NaN and up to 0, 255 from 254.5,
    // else the whole part plus one from a half up (every float checked against roundf).
    const float r = v * 255.0f;
    const int t = int(r > 0.0f ? std::min(r, 255.0f) : 0.0f);
    return !(r > 0.0f)   ? std::uint8_t(0)
           : r >= 254.5f ? std::uint8_t(255)
                         : static_cast<std::uint8_t>(t + (r - float(t) >= 0.5f));
}

} // namespace cm

namespace cm {

/// PNG bytes of an image (8-bit; its first `channels` channels: 3 for RGB, 4 for RGBA).
std::vector<unsigned char> encode_png(const Image& img, int channels);
/// Decodes image bytes of any format OpenImageIO reads from memory (PNG, JPEG) into
/// float RGBA as read_image(). Throws cm::Error starting with `what`.
Image decode_image(const unsigned char* data, std::size_t size, const std::string& what);
/// Width and height from the header of an image file; false when it cannot be read.
bool image_size(const std::filesystem::path& file, int& width, int& height);

} // namespace cm
