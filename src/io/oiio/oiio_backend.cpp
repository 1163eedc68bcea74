// The image formats other than PNG, through OpenImageIO: a library of its own that
// io/image_io.cpp opens on first use (OpenImageIO brings in some 260 shared libraries, whose
// loading costs a process about 0.3 s before main).
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cstdint>

#include "core/data.h"
#include "io/image_backend.h"

namespace {

using cm::RawImage;

// Alpha as the reader names it, else by the channel count (grey + alpha, RGBA).
int alpha_of(const OIIO::ImageSpec& spec) {
    const int nc = spec.nchannels;
    return spec.alpha_channel >= 0 ? spec.alpha_channel : (nc == 4 ? 3 : (nc == 2 ? 1 : -1));
}

// Reads an open input at its own depth (8 or 16 bits, float otherwise), not widened to
// float first: the buffer is a quarter or half of a float one.
bool read_open(OIIO::ImageInput& in, const OIIO::ImageSpec& spec, RawImage& out, std::string& why) {
    const int nc = spec.nchannels;
    const OIIO::TypeDesc src = spec.format.basetype == OIIO::TypeDesc::UINT8    ? OIIO::TypeDesc::UINT8
                               : spec.format.basetype == OIIO::TypeDesc::UINT16 ? OIIO::TypeDesc::UINT16
                                                                                : OIIO::TypeDesc::FLOAT;
    const std::size_t values = std::size_t(spec.width) * std::size_t(spec.height) * std::size_t(nc);
    out.data.resize(values * src.size());
    if (!in.read_image(0, 0, 0, nc, src, out.data.data())) return why = in.geterror(), false;
    // A reader may fill what it could not decode (a truncated JPEG comes back grey at the
    // bottom) and still say it succeeded; the error it recorded says so.
    if (in.has_error()) {
        why = in.geterror();
        if (const auto at = why.find(" (\""); at != std::string::npos) why.erase(at); // the path, said already
        why += " (is the file complete?)";
        return false;
    }
    out.width = spec.width;
    out.height = spec.height;
    out.channels = nc;
    out.bits = int(src.size() * 8);
    out.file_bits = int(spec.format.size() * 8);
    out.alpha = alpha_of(spec);
    return true;
}

bool read(const std::string& file, std::uint64_t max_pixels, RawImage& out, std::string& why) {
    auto in = OIIO::ImageInput::open(file);
    if (!in) return why = OIIO::geterror(), false;
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) return why = "it is empty", false;
    // The size is in the header: refuse a huge image before a pixel of it is allocated (a
    // few hundred bytes of PNG can claim 20000 x 20000).
    const std::uint64_t pixels = std::uint64_t(spec.width) * std::uint64_t(spec.height);
    if (max_pixels != 0 && pixels > max_pixels)
        return why = cm::over_pixel_limit(spec.width, spec.height, max_pixels), false;
    if (spec.nchannels > 64) return why = "it has " + std::to_string(spec.nchannels) + " channels", false;
    const bool ok = read_open(*in, spec, out, why);
    in->close();
    return ok;
}

bool decode(const unsigned char* data, std::size_t size, RawImage& out, std::string& why) {
    OIIO::Filesystem::IOMemReader proxy(const_cast<unsigned char*>(data), size);
    OIIO::ImageSpec config;
    void* ptr = &proxy;
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &ptr);
    const bool jpeg = size >= 2 && data[0] == 0xFF && data[1] == 0xD8;
    if (!jpeg) return why = "the image is neither PNG nor JPEG", false;
    auto in = OIIO::ImageInput::create("jpeg");
    if (!in) return why = OIIO::geterror(), false;
    in->set_ioproxy(&proxy);
    if (!in->open("memory", config)) return why = in->geterror(), false;
    const OIIO::ImageSpec spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) return why = "the image is empty", false;
    if (!read_open(*in, spec, out, why)) return false;
    out.alpha = spec.nchannels == 4 ? 3 : (spec.nchannels == 2 ? 1 : -1);
    return true;
}

bool write(const cm::Image& img, const std::string& file, std::string& why) {
    const std::string ext = cm::lower_extension(file);
    auto out = OIIO::ImageOutput::create(file);
    if (!out) return why = OIIO::geterror(), false;
    const bool eight = ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp";
    OIIO::ImageSpec spec(img.width, img.height, img.channels, eight ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
    if (!out->open(file, spec)) return why = out->geterror(), false;
    if (!out->write_image(OIIO::TypeDesc::FLOAT, img.pixels.data())) return why = out->geterror(), false;
    out->close();
    return true;
}

bool size(const std::string& file, int& width, int& height) {
    auto in = OIIO::ImageInput::open(file);
    if (!in) return false;
    width = in->spec().width;
    height = in->spec().height;
    return true;
}

constexpr cm::ImageBackend kBackend{cm::kImageBackendAbi, read, decode, write, size};

} // namespace

extern "C" __attribute__((visibility("default"))) const cm::ImageBackend* conceptmesh_image_backend() {
    return &kBackend;
}
