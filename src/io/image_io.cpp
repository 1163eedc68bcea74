#include "io/image_io.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cstdint>
#include <cstring>

#include "core/data.h"
#include "core/error.h"
#include "io/limits.h"

namespace fs = std::filesystem;

namespace cm {

Image read_image(const fs::path& file, ImageInfo* info) {
    std::error_code ec;
    if (!fs::exists(file, ec)) throw Error("cannot read image \"" + file.string() + "\": no such file");
    auto in = OIIO::ImageInput::open(file.string());
    if (!in) throw Error("cannot read image \"" + file.string() + "\": " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
        throw Error("cannot read image \"" + file.string() + "\": it is empty");
    // The size is in the header: refuse a huge image before a pixel of it is allocated (a
    // few hundred bytes of PNG can claim 20000 x 20000).
    const std::uint64_t pixels = std::uint64_t(spec.width) * std::uint64_t(spec.height);
    const std::uint64_t limit = resource_limits().max_image_pixels;
    if (limit != 0 && pixels > limit)
        throw Error("cannot read image \"" + file.string() + "\": it is " + std::to_string(spec.width) + " x " +
                    std::to_string(spec.height) + " pixels (" + std::to_string(pixels / 1'000'000) +
                    " megapixels), over the limit of " + std::to_string(limit / 1'000'000) +
                    " megapixels (--max-image-pixels)");
    const int nc = spec.nchannels;
    if (nc > 64) throw Error("cannot read image \"" + file.string() + "\": it has " + std::to_string(nc) + " channels");
    // Decoded at the file's own depth (8 or 16 bits, float otherwise), not widened to float
    // first: the buffer is a quarter or half of a float one.
    const OIIO::TypeDesc src = spec.format.basetype == OIIO::TypeDesc::UINT8    ? OIIO::TypeDesc::UINT8
                               : spec.format.basetype == OIIO::TypeDesc::UINT16 ? OIIO::TypeDesc::UINT16
                                                                                : OIIO::TypeDesc::FLOAT;
    const std::size_t values = std::size_t(pixels) * std::size_t(nc);
    std::vector<unsigned char> raw(values * src.size());
    if (!in->read_image(0, 0, 0, nc, src, raw.data()))
        throw Error("cannot read image \"" + file.string() + "\": " + in->geterror());
    // A reader may fill what it could not decode (a truncated JPEG comes back grey at the
    // bottom) and still say it succeeded; the error it recorded says so.
    if (in->has_error()) {
        std::string why = in->geterror();
        if (const auto at = why.find(" (\""); at != std::string::npos) why.erase(at); // the path, said already
        throw Error("cannot read image \"" + file.string() + "\": " + why + " (is the file complete?)");
    }
    in->close();
    Image img;
    img.width = spec.width;
    img.height = spec.height;
    img.channels = 4;
    img.pixels.resize(std::size_t(img.width) * img.height * 4);
    const int alpha = spec.alpha_channel >= 0 ? spec.alpha_channel : (nc == 4 ? 3 : (nc == 2 ? 1 : -1));
    auto value = [&](std::size_t k) -> float {
        if (src == OIIO::TypeDesc::UINT8) return float(raw[k]) * (1.0f / 255.0f);
        if (src == OIIO::TypeDesc::UINT16) {
            std::uint16_t v;
            std::memcpy(&v, &raw[k * 2], 2);
            return float(v) * (1.0f / 65535.0f);
        }
        float v;
        std::memcpy(&v, &raw[k * 4], 4);
        return v;
    };
    for (std::size_t i = 0, n = std::size_t(img.width) * img.height; i < n; ++i) {
        const std::size_t s = i * std::size_t(nc);
        float* d = &img.pixels[i * 4];
        if (nc >= 3) {
            d[0] = value(s);
            d[1] = value(s + 1);
            d[2] = value(s + 2);
        } else {
            d[0] = d[1] = d[2] = value(s);
        }
        d[3] = alpha >= 0 ? value(s + std::size_t(alpha)) : 1.0f;
    }
    if (info) {
        info->has_alpha = alpha >= 0;
        info->bits = int(spec.format.size() * 8);
    }
    return img;
}

void write_image(const Image& img, const fs::path& file) {
    const std::string ext = lower_extension(file);
    auto out = OIIO::ImageOutput::create(file.string());
    if (!out) throw Error("cannot write image \"" + file.string() + "\": " + OIIO::geterror());
    const bool eight = ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp";
    OIIO::ImageSpec spec(img.width, img.height, img.channels, eight ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
    if (!out->open(file.string(), spec))
        throw Error("cannot write image \"" + file.string() + "\": " + out->geterror());
    if (!out->write_image(OIIO::TypeDesc::FLOAT, img.pixels.data()))
        throw Error("cannot write image \"" + file.string() + "\": " + out->geterror());
    out->close();
}

std::vector<unsigned char> encode_png(const Image& img, int channels) {
    if (img.empty() || channels < 1 || channels > img.channels) throw Error("cannot encode an empty image as PNG");
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput proxy(bytes);
    auto out = OIIO::ImageOutput::create("png");
    if (!out) throw Error("cannot encode PNG: " + OIIO::geterror());
    out->set_ioproxy(&proxy);
    OIIO::ImageSpec spec(img.width, img.height, channels, OIIO::TypeDesc::UINT8);
    if (!out->open("memory.png", spec)) throw Error("cannot encode PNG: " + out->geterror());
    const OIIO::stride_t xstride = OIIO::stride_t(img.channels * sizeof(float));
    if (!out->write_image(OIIO::TypeDesc::FLOAT, img.pixels.data(), xstride))
        throw Error("cannot encode PNG: " + out->geterror());
    out->close();
    return bytes;
}

Image decode_image(const unsigned char* data, std::size_t size, const std::string& what) {
    OIIO::Filesystem::IOMemReader proxy(const_cast<unsigned char*>(data), size);
    OIIO::ImageSpec config;
    void* ptr = &proxy;
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &ptr);
    const bool png = size >= 4 && data[0] == 0x89 && data[1] == 'P' && data[2] == 'N' && data[3] == 'G';
    const bool jpeg = size >= 2 && data[0] == 0xFF && data[1] == 0xD8;
    if (!png && !jpeg) throw Error(what + ": the image is neither PNG nor JPEG");
    auto in = OIIO::ImageInput::create(png ? "png" : "jpeg");
    if (!in) throw Error(what + ": " + OIIO::geterror());
    in->set_ioproxy(&proxy);
    if (!in->open("memory", config)) throw Error(what + ": " + in->geterror());
    const OIIO::ImageSpec spec = in->spec();
    const int nc = spec.nchannels;
    if (spec.width <= 0 || spec.height <= 0 || nc <= 0) throw Error(what + ": the image is empty");
    std::vector<float> raw(std::size_t(spec.width) * spec.height * nc);
    if (!in->read_image(0, 0, 0, nc, OIIO::TypeDesc::FLOAT, raw.data()) || in->has_error())
        throw Error(what + ": " + in->geterror());
    Image img;
    img.width = spec.width;
    img.height = spec.height;
    img.channels = 4;
    img.pixels.resize(std::size_t(img.width) * img.height * 4);
    for (std::size_t i = 0, n = std::size_t(img.width) * img.height; i < n; ++i) {
        const float* s = &raw[i * nc];
        float* d = &img.pixels[i * 4];
        for (int k = 0; k < 3; ++k) d[k] = s[nc >= 3 ? k : 0];
        d[3] = nc == 4 ? s[3] : (nc == 2 ? s[1] : 1.0f);
    }
    return img;
}

} // namespace cm
