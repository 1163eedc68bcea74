#include "io/image_io.h"

#include <dlfcn.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/data.h"
#include "core/error.h"
#include "io/image_backend.h"
#include "io/limits.h"
#include "io/png_codec.h"

namespace fs = std::filesystem;

namespace cm {

namespace {

template <typename Backend>
struct Loaded {
    const Backend* backend = nullptr;
    std::string why;
};

// A backend library of conceptmesh, beside this one (the build tree and an installed tree
// alike), else wherever the dynamic loader finds it. Opened once, on the first image that
// needs it. `what` names it in the error ("OpenImageIO", "librsvg").
template <typename Backend>
Loaded<Backend> load_backend(const char* name, const char* entry_name, int abi, const char* what) {
    Loaded<Backend> l;
    Dl_info self{};
    void* h = nullptr;
    if (::dladdr(reinterpret_cast<void*>(&is_svg_file), &self) && self.dli_fname)
        h = ::dlopen((fs::path(self.dli_fname).parent_path() / name).c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
    if (!h) h = ::dlopen(name, RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
    if (!h) {
        const char* e = ::dlerror();
        l.why = std::string("the ") + what + " library of conceptmesh (" + name + ") cannot be opened: " + (e ? e : "");
        return l;
    }
    using Entry = const Backend* (*)();
    auto entry = reinterpret_cast<Entry>(::dlsym(h, entry_name));
    const Backend* b = entry ? entry() : nullptr;
    if (!b || b->abi != abi) l.why = std::string(name) + " is not the one this conceptmesh was built with";
    else l.backend = b;
    return l;
}

// Throws `prefix` + why when the backend is missing.
const ImageBackend& backend(const std::string& prefix) {
    static const auto loaded = load_backend<ImageBackend>("libconceptmesh_image_oiio.so", "conceptmesh_image_backend",
                                                          kImageBackendAbi, "OpenImageIO");
    if (!loaded.backend) throw Error(prefix + loaded.why);
    return *loaded.backend;
}

const VectorBackend& vector_backend(const std::string& prefix) {
    static const auto loaded = load_backend<VectorBackend>("libconceptmesh_image_svg.so", "conceptmesh_vector_backend",
                                                           kVectorBackendAbi, "librsvg");
    if (!loaded.backend) throw Error(prefix + loaded.why + " (SVG drawings need librsvg: Debian's librsvg2-dev)");
    return *loaded.backend;
}

// RGBA from the raw samples, rows side by side: value(k) is sample k as T; grey is
// replicated and a missing alpha becomes `opaque`.
template <typename T, typename Value>
void expand_rgba(const RawImage& raw, T* out, Value&& value, T opaque) {
    const int nc = raw.channels, alpha = raw.alpha, w = raw.width;
    // One loop per layout, so that no pixel asks which layout it has.
    auto rows_of = [&](auto&& pixel) {
        tbb::parallel_for(tbb::blocked_range<int>(0, raw.height, 16), [&](const tbb::blocked_range<int>& rows) {
            const std::size_t b = std::size_t(rows.begin()) * w, e = std::size_t(rows.end()) * w;
            for (std::size_t i = b; i < e; ++i) pixel(i * std::size_t(nc), out + i * 4);
        });
    };
    if (nc >= 3 && alpha >= 0)
        rows_of([&](std::size_t s, T* d) {
            d[0] = value(s);
            d[1] = value(s + 1);
            d[2] = value(s + 2);
            d[3] = value(s + std::size_t(alpha));
        });
    else if (nc >= 3)
        rows_of([&](std::size_t s, T* d) {
            d[0] = value(s);
            d[1] = value(s + 1);
            d[2] = value(s + 2);
            d[3] = opaque;
        });
    else if (alpha >= 0)
        rows_of([&](std::size_t s, T* d) {
            d[0] = d[1] = d[2] = value(s);
            d[3] = value(s + std::size_t(alpha));
        });
    else
        rows_of([&](std::size_t s, T* d) {
            d[0] = d[1] = d[2] = value(s);
            d[3] = opaque;
        });
}

// Float RGBA in [0,1] from pixels at their own depth.
Image to_rgba(const RawImage& raw) {
    Image img{raw.width, raw.height, 4, std::vector<float>(std::size_t(raw.width) * raw.height * 4), {}};
    float* out = img.pixels.data();
    if (raw.bits == 8) {
        expand_rgba(
            raw, out, [&](std::size_t k) { return float(raw.data[k]) * (1.0f / 255.0f); }, 1.0f);
    } else if (raw.bits == 16) {
        expand_rgba(
            raw, out,
            [&](std::size_t k) {
                std::uint16_t v;
                std::memcpy(&v, &raw.data[k * 2], 2);
                return float(v) * (1.0f / 65535.0f);
            },
            1.0f);
    } else {
        expand_rgba(
            raw, out,
            [&](std::size_t k) {
                float v;
                std::memcpy(&v, &raw.data[k * 4], 4);
                return v;
            },
            1.0f);
    }
    return img;
}

// An 8-bit source as RGBA bytes (the samples as read, missing alpha 255).
Image to_rgba_bytes(const RawImage& raw) {
    Image img{raw.width, raw.height, 4, {}, std::vector<std::uint8_t>(std::size_t(raw.width) * raw.height * 4)};
    expand_rgba(
        raw, img.bytes.data(), [&](std::size_t k) { return std::uint8_t(raw.data[k]); }, std::uint8_t(255));
    return img;
}

// An 8-bit grey source as it is (one byte per pixel: a quarter of RGBA; Image::rgba and
// Image::at read it as grey).
Image grey_bytes(RawImage&& raw) { return Image{raw.width, raw.height, 1, {}, std::move(raw.data)}; }

} // namespace

bool is_svg_file(const fs::path& file) {
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".svg" || ext == ".svgz") return true;
    std::ifstream in(file, std::ios::binary);
    char head[1024] = {};
    in.read(head, sizeof head);
    const std::string text(head, std::size_t(in.gcount()));
    return text.find("<svg") != std::string::npos;
}

Image read_image(const fs::path& file, ImageInfo* info, bool keep_bytes, int svg_size) {
    std::error_code ec;
    const std::string prefix = "cannot read image \"" + file.string() + "\": ";
    if (!fs::exists(file, ec)) throw Error(prefix + "no such file");
    const std::uint64_t limit = resource_limits().max_image_pixels;
    RawImage raw;
    std::string why;
    // PNG by its signature (whatever the extension says) through libpng; SVG drawn by
    // librsvg; the rest through OpenImageIO. The last two are loaded for it.
    const bool ok = png::is_png_file(file.string()) ? png::read(file.string(), nullptr, 0, limit, raw, why)
                    : is_svg_file(file) ? vector_backend(prefix).rasterise(file.string(), svg_size, limit, raw, why)
                                        : backend(prefix).read(file.string(), limit, raw, why);
    if (!ok) throw Error(prefix + why);
    const bool grey = raw.channels == 1 && raw.alpha < 0;
    Image img = keep_bytes && raw.bits == 8 ? (grey ? grey_bytes(std::move(raw)) : to_rgba_bytes(raw)) : to_rgba(raw);
    if (info) {
        info->has_alpha = raw.alpha >= 0;
        info->bits = raw.file_bits;
    }
    return img;
}

void write_image(const Image& img, const fs::path& file) {
    const std::string prefix = "cannot write image \"" + file.string() + "\": ";
    std::string why;
    const bool ok = lower_extension(file) == ".png" ? png::write(img, img.channels, file.string(), nullptr, why)
                                                    : backend(prefix).write(img, file.string(), why);
    if (!ok) throw Error(prefix + why);
}

std::vector<unsigned char> encode_png(const Image& img, int channels) {
    if (img.empty() || channels < 1 || channels > img.channels) throw Error("cannot encode an empty image as PNG");
    std::vector<unsigned char> bytes;
    std::string why;
    if (!png::write(img, channels, {}, &bytes, why)) throw Error("cannot encode PNG: " + why);
    return bytes;
}

Image decode_image(const unsigned char* data, std::size_t size, const std::string& what) {
    RawImage raw;
    std::string why;
    const bool png = png::is_png(data, size), jpeg = size >= 2 && data[0] == 0xFF && data[1] == 0xD8;
    if (!png && !jpeg) throw Error(what + ": the image is neither PNG nor JPEG");
    const std::uint64_t limit = resource_limits().max_image_pixels;
    const bool ok =
        png ? png::read({}, data, size, limit, raw, why) : backend(what + ": ").decode(data, size, limit, raw, why);
    if (!ok) throw Error(what + ": " + why);
    if (raw.width <= 0 || raw.height <= 0 || raw.channels <= 0) throw Error(what + ": the image is empty");
    return to_rgba(raw);
}

bool image_size(const fs::path& file, int& width, int& height) {
    if (png::size(file.string(), width, height)) return true;
    std::error_code ec;
    if (!fs::exists(file, ec) || is_svg_file(file)) return false; // an SVG's size is the reader's choice
    try {
        return backend("").size(file.string(), width, height);
    } catch (const Error&) {
        return false;
    }
}

} // namespace cm
