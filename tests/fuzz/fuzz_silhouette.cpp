// Arbitrary bytes as a drawing: decoded (PNG, JPEG, TIFF... whatever the bytes claim) and
// turned into a silhouette as a drawing and as a photograph, or cm::Error; nothing else.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "core/error.h"
#include "fuzz_support.h"
#include "io/image_io.h"
#include "io/limits.h"
#include "silhouette.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    // Small images only: the pixel limit is what keeps a header's claim from allocating.
    cm::resource_limits().max_image_pixels = 1 << 20;
    const char* name = size >= 4 && std::memcmp(data, "\x89PNG", 4) == 0 ? "in.png"
                       : size >= 2 && data[0] == 0xFF && data[1] == 0xD8 ? "in.jpg"
                                                                         : "in.tif";
    const auto file = cm::fuzz::as_file(data, size, name);
    try {
        cm::ImageInfo info;
        const cm::Image img = cm::read_image(file, &info);
        (void)cm::extract_silhouette(img, info, cm::SilhouetteOptions{});
        cm::SilhouetteOptions photo;
        photo.photo = "on";
        (void)cm::extract_silhouette(img, info, photo);
    } catch (const cm::Error&) {}
    return 0;
}
