// PNG read and written through libpng directly, giving the same pixels as OpenImageIO 2.4's
// PNG plugin did (palettes and low depths expanded, transparency as alpha, alpha associated
// on reading and unassociated on writing, no colour chunks). Reading is libpng's throughout.
// Writing leaves libpng the signature and the IHDR, oFFs and IEND chunks and makes the image
// data itself, in parallel: the rows converted to 8 bits as OpenImageIO converts, each row's
// filter chosen by libpng's heuristic (the least sum of the filtered bytes' absolute values
// taken as signed: libpng's filtered rows), and the filtered stream deflated at level 6 in
// pieces of 256 kB on every core, each primed with the 32 kB before it (as pigz does), joined
// into one zlib stream. So the bytes written are no longer OpenImageIO's byte for byte; the
// pixels are the same and the size about the same (a preview sheet: 0.2 % smaller).
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
/// empty) or appended to `bytes`. False with the reason in `why`. `pieces`, when given, is
/// set to the number of pieces the image data was deflated in (1 for up to 512 kB of it).
bool write(const Image& img, int channels, const std::string& file, std::vector<unsigned char>* bytes, std::string& why,
           std::size_t* pieces = nullptr);

} // namespace cm::png
