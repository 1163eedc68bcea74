// PNG read and written through libpng directly, giving the same pixels and bytes as
// OpenImageIO 2.4's PNG plugin did (palettes and low depths expanded, transparency as
// alpha, alpha associated on reading and unassociated on writing, no colour chunks).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "io/image_backend.h"

namespace cm::png {

/// Whether the bytes start with the PNG signature.
bool is_png(const unsigned char* data, std::size_t size);
/// Whether the file starts with the PNG signature (false when it cannot be read).
bool is_png_file(const std::string& file);

/// Reads a PNG file (or, with `file` empty, `size` bytes at `data`). Refuses an image over
/// `max_pixels` (0: none) from its header. False with the reason in `why`.
bool read(const std::string& file, const unsigned char* data, std::size_t size, std::uint64_t max_pixels, RawImage& out,
          std::string& why);
/// Width and height from the header of a PNG file.
bool size(const std::string& file, int& width, int& height);

/// 8-bit PNG of the first `channels` (1 to 4) of a float image, to a file (`file` not
/// empty) or appended to `bytes`. False with the reason in `why`.
bool write(const Image& img, int channels, const std::string& file, std::vector<unsigned char>* bytes,
           std::string& why);

} // namespace cm::png
