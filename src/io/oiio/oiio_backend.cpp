// The image formats other than PNG, through OpenImageIO: a library of its own that
// io/image_io.cpp opens on first use (OpenImageIO brings in some 260 shared libraries, whose
// loading costs a process about 0.3 s before main).
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <memory>
#include <vector>

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

bool is_jpeg(const unsigned char* data, std::size_t size) { return size >= 2 && data[0] == 0xFF && data[1] == 0xD8; }

// Drops a JPEG's metadata segments that conceptmesh does not use (APP1-APP13, APP15: Exif,
// XMP, ICC, Photoshop/IPTC...; kept: APP0 JFIF and APP14 Adobe, which the decoder reads, and
// everything else), in place. OpenImageIO 2.4 parses that metadata when it opens the file,
// and its IPTC parser reads past the end of a Photoshop block whose sizes are wrong; the
// pixels do not depend on it. The walk finds markers as libjpeg does (fill 0xFF bytes
// skipped, 0xFF00 and RSTn inside entropy-coded data), through the whole file, so a segment
// between the scans of a progressive JPEG is dropped too. A dropped segment that runs past
// the end ends the bytes: the decoder then finds the file short and says so.
void drop_metadata(std::vector<unsigned char>& d) {
    const std::size_t n = d.size();
    std::size_t i = 2, kept = 0, copied = 0; // after SOI; bytes [copied, i) are not moved yet
    auto keep_to = [&](std::size_t end) {    // moves [copied, end) down to `kept`
        std::copy(d.begin() + std::ptrdiff_t(copied), d.begin() + std::ptrdiff_t(end),
                  d.begin() + std::ptrdiff_t(kept));
        kept += end - copied;
        copied = end;
    };
    while (i < n) {
        if (d[i] != 0xFF) {
            ++i;
            continue;
        }
        const std::size_t start = i;
        while (i < n && d[i] == 0xFF) ++i;
        if (i >= n) break;
        const unsigned char m = d[i++];
        if (m == 0x00 || m == 0x01 || (m >= 0xD0 && m <= 0xD9)) continue; // data, TEM, RSTn, SOI, EOI
        if (i + 2 > n) break;
        const std::size_t length = (std::size_t(d[i]) << 8) | d[i + 1];
        if (length < 2) break; // the decoder refuses it
        const std::size_t end = i + length;
        const bool metadata = (m >= 0xE1 && m <= 0xED) || m == 0xEF;
        if (!metadata) {
            i = std::min(end, n);
            continue;
        }
        keep_to(start);
        if (end > n) { // cut short: the decoder reports a file that ends early
            d.resize(kept);
            return;
        }
        copied = i = end;
    }
    keep_to(n);
    d.resize(kept);
}

// OpenImageIO's words for an error in bytes read from memory, without the name "memory" it
// gives them (the caller names the file) and one line long.
std::string without_memory_name(std::string why) {
    for (const std::string name : {" (\"memory\")", " for \"memory\""})
        for (auto at = why.find(name); at != std::string::npos; at = why.find(name)) why.erase(at, name.size());
    for (auto at = why.find('\n'); at != std::string::npos; at = why.find('\n')) why.replace(at, 1, "; ");
    while (!why.empty() && (why.back() == ' ' || why.back() == ';')) why.pop_back();
    return why;
}

// Opens JPEG bytes through the in-memory reader (which `proxy` must outlive).
std::unique_ptr<OIIO::ImageInput> open_jpeg(OIIO::Filesystem::IOMemReader& proxy, std::string& why) {
    auto in = OIIO::ImageInput::create("jpeg");
    if (!in) return why = OIIO::geterror(), nullptr;
    OIIO::ImageSpec config;
    void* ptr = &proxy;
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &ptr);
    in->set_ioproxy(&proxy);
    if (!in->open("memory", config)) {
        why = without_memory_name(in->geterror());
        if (why.empty()) why = "it is not a valid JPEG";
        return nullptr;
    }
    return in;
}

// A JPEG file's bytes without its metadata, or false when the file is not a JPEG.
bool jpeg_file(const std::string& file, std::vector<unsigned char>& bytes) {
    std::ifstream f(file, std::ios::binary);
    unsigned char magic[2] = {0, 0};
    if (!f.read(reinterpret_cast<char*>(magic), 2) || !is_jpeg(magic, 2)) return false;
    f.seekg(0);
    bytes.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
    drop_metadata(bytes);
    return true;
}

// A file opened for reading: a JPEG from its bytes without metadata (which the input reads
// through `proxy`), anything else by OpenImageIO from the file.
struct OpenFile {
    std::vector<unsigned char> bytes;
    std::unique_ptr<OIIO::Filesystem::IOMemReader> proxy; // declared before `in`: outlives it
    std::unique_ptr<OIIO::ImageInput> in;
};

bool open_file(const std::string& file, OpenFile& f, std::string& why) {
    if (jpeg_file(file, f.bytes)) {
        f.proxy = std::make_unique<OIIO::Filesystem::IOMemReader>(f.bytes.data(), f.bytes.size());
        f.in = open_jpeg(*f.proxy, why);
    } else {
        f.in = OIIO::ImageInput::open(file);
        if (!f.in) why = OIIO::geterror();
    }
    return f.in != nullptr;
}

// The header's checks, then the pixels.
bool read_checked(OIIO::ImageInput& in, std::uint64_t max_pixels, RawImage& out, std::string& why) {
    const OIIO::ImageSpec spec = in.spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) return why = "it is empty", false;
    // The size is in the header: refuse a huge image before a pixel of it is allocated (a
    // few hundred bytes of PNG can claim 20000 x 20000).
    const std::uint64_t pixels = std::uint64_t(spec.width) * std::uint64_t(spec.height);
    if (max_pixels != 0 && pixels > max_pixels)
        return why = cm::over_pixel_limit(spec.width, spec.height, max_pixels), false;
    if (spec.nchannels > 64) return why = "it has " + std::to_string(spec.nchannels) + " channels", false;
    const bool ok = read_open(in, spec, out, why);
    in.close();
    return ok;
}

bool read(const std::string& file, std::uint64_t max_pixels, RawImage& out, std::string& why) {
    OpenFile f;
    return open_file(file, f, why) && read_checked(*f.in, max_pixels, out, why);
}

bool decode(const unsigned char* data, std::size_t size, std::uint64_t max_pixels, RawImage& out, std::string& why) {
    if (!is_jpeg(data, size)) return why = "the image is neither PNG nor JPEG", false;
    std::vector<unsigned char> bytes(data, data + size);
    drop_metadata(bytes);
    OIIO::Filesystem::IOMemReader proxy(bytes.data(), bytes.size());
    const auto in = open_jpeg(proxy, why);
    return in && read_checked(*in, max_pixels, out, why);
}

bool write(const cm::Image& img, const std::string& file, std::string& why) {
    const std::string ext = cm::lower_extension(file);
    auto out = OIIO::ImageOutput::create(file);
    if (!out) return why = OIIO::geterror(), false;
    const bool eight = ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp";
    OIIO::ImageSpec spec(img.width, img.height, img.channels, eight ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
    if (!out->open(file, spec)) return why = out->geterror(), false;
    const bool ok = img.eight_bit() ? out->write_image(OIIO::TypeDesc::UINT8, img.bytes.data())
                                    : out->write_image(OIIO::TypeDesc::FLOAT, img.pixels.data());
    if (!ok) return why = out->geterror(), false;
    out->close();
    return true;
}

bool size(const std::string& file, int& width, int& height) {
    OpenFile f;
    std::string why;
    if (!open_file(file, f, why)) return false;
    width = f.in->spec().width;
    height = f.in->spec().height;
    return true;
}

constexpr cm::ImageBackend kBackend{cm::kImageBackendAbi, read, decode, write, size};

} // namespace

extern "C" __attribute__((visibility("default"))) const cm::ImageBackend* conceptmesh_image_backend() {
    return &kBackend;
}
