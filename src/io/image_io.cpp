#include "io/image_io.h"

#include <OpenImageIO/imageio.h>

#include "core/data.h"
#include "core/error.h"

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
    const int nc = spec.nchannels;
    std::vector<float> raw(std::size_t(spec.width) * spec.height * nc);
    if (!in->read_image(0, 0, 0, nc, OIIO::TypeDesc::FLOAT, raw.data()))
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
    for (std::size_t i = 0, n = std::size_t(img.width) * img.height; i < n; ++i) {
        const float* s = &raw[i * nc];
        float* d = &img.pixels[i * 4];
        if (nc >= 3) {
            d[0] = s[0];
            d[1] = s[1];
            d[2] = s[2];
        } else {
            d[0] = d[1] = d[2] = s[0];
        }
        d[3] = alpha >= 0 ? s[alpha] : 1.0f;
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

} // namespace cm
