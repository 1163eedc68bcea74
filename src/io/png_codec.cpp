#include "io/png_codec.h"

#include <png.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

namespace cm::png {

namespace {

// libpng reports errors through a callback that must not return: it records the words
// and jumps back to the setjmp of the function that called libpng. Everything with a
// destructor lives in this context, made before that setjmp, so the jump skips none.
struct Context {
    std::string error;
    FILE* file = nullptr;
    const unsigned char* data = nullptr; // reading from memory
    std::size_t size = 0, at = 0;
    std::vector<unsigned char>* bytes = nullptr; // writing to memory
    std::vector<png_bytep> rows;
    std::vector<unsigned char> row;
};

void on_error(png_structp sp, png_const_charp message) {
    auto* c = static_cast<Context*>(png_get_error_ptr(sp));
    if (c->error.empty()) c->error = message ? message : "libpng error";
    png_longjmp(sp, 1);
}

void on_warning(png_structp, png_const_charp) {}

void read_bytes(png_structp sp, png_bytep out, png_size_t n) {
    auto* c = static_cast<Context*>(png_get_io_ptr(sp));
    if (c->file) {
        if (std::fread(out, 1, n, c->file) != n) png_error(sp, "Read Error");
    } else {
        if (c->size - c->at < n) png_error(sp, "Read Error");
        std::memcpy(out, c->data + c->at, n);
        c->at += n;
    }
}

void write_bytes(png_structp sp, png_bytep in, png_size_t n) {
    auto* c = static_cast<Context*>(png_get_io_ptr(sp));
    if (c->file) {
        if (std::fwrite(in, 1, n, c->file) != n) png_error(sp, "Write Error");
    } else {
        c->bytes->insert(c->bytes->end(), in, in + n);
    }
}

void flush_bytes(png_structp) {}

struct ReadStruct {
    png_structp sp = nullptr;
    png_infop ip = nullptr;
    ~ReadStruct() {
        if (sp) png_destroy_read_struct(&sp, ip ? &ip : nullptr, nullptr);
    }
};

struct WriteStruct {
    png_structp sp = nullptr;
    png_infop ip = nullptr;
    ~WriteStruct() {
        if (sp) png_destroy_write_struct(&sp, ip ? &ip : nullptr);
    }
};

// PNG alpha is unassociated; OpenImageIO associates it on reading (by the file's gamma
// when it has a gAMA chunk and no sRGB one), and so does this, with the same arithmetic.
template <class T>
void associate(T* p, std::size_t pixels, int channels, int alpha, float gamma) {
    const T max = std::numeric_limits<T>::max();
    if (gamma == 1) {
        for (std::size_t x = 0; x < pixels; ++x, p += channels)
            for (int c = 0; c < channels; ++c)
                if (c != alpha) {
                    const unsigned int f = p[c];
                    p[c] = T((f * p[alpha]) / max);
                }
    } else {
        const float inv_max = float(1.0 / max);
        for (std::size_t x = 0; x < pixels; ++x, p += channels) {
            const float a = std::pow(float(p[alpha]) * inv_max, gamma);
            for (int c = 0; c < channels; ++c)
                if (c != alpha) p[c] = static_cast<T>(float(p[c]) * a);
        }
    }
}

bool read_png(Context& c, ReadStruct& rs, std::uint64_t max_pixels, RawImage& out) {
    rs.sp = png_create_read_struct(PNG_LIBPNG_VER_STRING, &c, on_error, on_warning);
    if (!rs.sp) return c.error = "cannot make a PNG reader", false;
    rs.ip = png_create_info_struct(rs.sp);
    if (!rs.ip) return c.error = "cannot make a PNG reader", false;
    if (setjmp(png_jmpbuf(rs.sp))) return false;
    png_set_read_fn(rs.sp, &c, read_bytes);
    png_read_info(rs.sp, rs.ip);
    png_set_expand(rs.sp); // 1, 2, 4 bits to 8, palette to RGB, transparency to alpha
    if constexpr (std::endian::native == std::endian::little) png_set_swap(rs.sp);
    png_read_update_info(rs.sp, rs.ip);
    png_uint_32 w = 0, h = 0;
    int depth = 0, colour = 0, interlace = 0;
    png_get_IHDR(rs.sp, rs.ip, &w, &h, &depth, &colour, &interlace, nullptr, nullptr);
    const int nc = png_get_channels(rs.sp, rs.ip);
    if (max_pixels != 0 && std::uint64_t(w) * h > max_pixels) {
        c.error = over_pixel_limit(int(w), int(h), max_pixels);
        return false;
    }
    float gamma = 1.0f;
    int intent = 0;
    double file_gamma = 0.0;
    if (!png_get_sRGB(rs.sp, rs.ip, &intent) && png_get_gAMA(rs.sp, rs.ip, &file_gamma) && file_gamma > 0.0) {
        const float g = float(1.0 / file_gamma);
        gamma = std::roundf(float(100.0 * g)) / 100.0f; // 2.2, not 2.19998
    }
    out.width = int(w);
    out.height = int(h);
    out.channels = nc;
    out.bits = out.file_bits = depth == 16 ? 16 : 8;
    out.alpha = nc == 2 ? 1 : (nc == 4 ? 3 : -1);
    const std::size_t row_bytes = png_get_rowbytes(rs.sp, rs.ip);
    if (row_bytes != std::size_t(w) * std::size_t(nc) * std::size_t(out.bits / 8))
        return c.error = "unexpected PNG row size", false;
    out.data.resize(row_bytes * h);
    if (interlace != PNG_INTERLACE_NONE) {
        c.rows.resize(h);
        for (png_uint_32 y = 0; y < h; ++y) c.rows[y] = out.data.data() + y * row_bytes;
        png_read_image(rs.sp, c.rows.data());
        png_read_end(rs.sp, nullptr);
    } else { // row by row, the end of the file not asked for (OpenImageIO did not either)
        for (png_uint_32 y = 0; y < h; ++y) png_read_row(rs.sp, out.data.data() + y * row_bytes, nullptr);
    }
    if (out.alpha >= 0) {
        const std::size_t pixels = std::size_t(w) * h;
        if (out.bits == 16) associate(reinterpret_cast<std::uint16_t*>(out.data.data()), pixels, nc, out.alpha, gamma);
        else associate(out.data.data(), pixels, nc, out.alpha, gamma);
    }
    return true;
}

// Float to 8 bits as OpenImageIO 2.4 converts a run of n values: in fours, rounded half
// away from zero and clamped (NaN to 0); the last n % 4 as trunc(v * 255 + 0.5), clamped.
void to_bytes(const float* in, unsigned char* out, std::size_t n) {
    std::size_t i = 0;
    for (const std::size_t fours = n - n % 4; i < fours; ++i) {
        float r = std::roundf(in[i] * 255.0f);
        r = r > 0.0f ? r : 0.0f;
        r = r < 255.0f ? r : 255.0f;
        out[i] = static_cast<unsigned char>(int(r));
    }
    for (; i < n; ++i) {
        float s = in[i] * 255.0f + 0.5f;
        if (!(0.0f <= s)) s = 0.0f;
        if (s > 255.0f) s = 255.0f;
        out[i] = static_cast<unsigned char>(s);
    }
}

bool write_png(Context& c, WriteStruct& ws, const Image& img, int nc) {
    ws.sp = png_create_write_struct(PNG_LIBPNG_VER_STRING, &c, on_error, on_warning);
    if (!ws.sp) return c.error = "cannot make a PNG writer", false;
    ws.ip = png_create_info_struct(ws.sp);
    if (!ws.ip) return c.error = "cannot make a PNG writer", false;
    if (setjmp(png_jmpbuf(ws.sp))) return false;
    png_set_write_fn(ws.sp, &c, write_bytes, flush_bytes);
    png_set_compression_level(ws.sp, 6);
    png_set_compression_strategy(ws.sp, Z_DEFAULT_STRATEGY);
    png_set_filter(ws.sp, 0, PNG_NO_FILTERS); // libpng then picks per row among all filters
    static constexpr int kColour[] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                      PNG_COLOR_TYPE_RGB_ALPHA};
    png_set_IHDR(ws.sp, ws.ip, png_uint_32(img.width), png_uint_32(img.height), 8, kColour[nc - 1], PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_oFFs(ws.sp, ws.ip, 0, 0, PNG_OFFSET_PIXEL);
    png_write_info(ws.sp, ws.ip);
    const int alpha = nc == 2 ? 1 : (nc == 4 ? 3 : -1);
    const std::size_t w = std::size_t(img.width);
    c.row.resize(w * std::size_t(nc));
    for (int y = 0; y < img.height; ++y) {
        const float* src = img.pixels.data() + std::size_t(y) * w * std::size_t(img.channels);
        unsigned char* row = c.row.data();
        if (nc == img.channels) {
            to_bytes(src, row, w * std::size_t(nc)); // a whole row in one run
        } else {
            for (std::size_t x = 0; x < w; ++x) to_bytes(src + x * img.channels, row + x * nc, std::size_t(nc));
        }
        if (alpha >= 0) // PNG wants unassociated alpha
            for (std::size_t x = 0; x < w; ++x) {
                unsigned char* p = row + x * nc;
                if (p[alpha])
                    for (int k = 0; k < nc; ++k)
                        if (k != alpha) p[k] = static_cast<unsigned char>(std::min(255u, (p[k] * 255u) / p[alpha]));
            }
        png_write_row(ws.sp, row);
    }
    png_write_end(ws.sp, ws.ip);
    return true;
}

} // namespace

bool is_png(const unsigned char* data, std::size_t size) {
    return size >= 8 && png_sig_cmp(const_cast<unsigned char*>(data), 0, 8) == 0;
}

bool is_png_file(const std::string& file) {
    FILE* f = std::fopen(file.c_str(), "rb");
    if (!f) return false;
    unsigned char sig[8];
    const bool ok = std::fread(sig, 1, 8, f) == 8 && is_png(sig, 8);
    std::fclose(f);
    return ok;
}

bool read(const std::string& file, const unsigned char* data, std::size_t size, std::uint64_t max_pixels, RawImage& out,
          std::string& why) {
    Context c;
    if (!file.empty()) {
        c.file = std::fopen(file.c_str(), "rb");
        if (!c.file) return why = std::strerror(errno), false;
    } else {
        c.data = data;
        c.size = size;
    }
    bool ok;
    {
        ReadStruct rs;
        ok = read_png(c, rs, max_pixels, out);
    }
    if (c.file) std::fclose(c.file);
    if (!ok) why = c.error;
    return ok;
}

bool size(const std::string& file, int& width, int& height) {
    // The IHDR chunk comes first: signature (8), length (4), "IHDR" (4), width, height.
    FILE* f = std::fopen(file.c_str(), "rb");
    if (!f) return false;
    unsigned char b[24];
    const bool ok = std::fread(b, 1, 24, f) == 24 && is_png(b, 8) && std::memcmp(b + 12, "IHDR", 4) == 0;
    std::fclose(f);
    if (!ok) return false;
    const png_uint_32 w = png_get_uint_32(b + 16), h = png_get_uint_32(b + 20);
    if (w > 0x7fffffffu || h > 0x7fffffffu) return false;
    width = int(w);
    height = int(h);
    return true;
}

bool write(const Image& img, int channels, const std::string& file, std::vector<unsigned char>* bytes,
           std::string& why) {
    if (img.width < 1 || img.height < 1 || channels < 1 || channels > 4 || channels > img.channels ||
        img.pixels.size() < std::size_t(img.width) * img.height * img.channels)
        return why = "PNG takes 1 to 4 channels of a non-empty image", false;
    Context c;
    c.bytes = bytes;
    if (!file.empty()) {
        c.file = std::fopen(file.c_str(), "wb");
        if (!c.file) return why = std::strerror(errno), false;
    }
    bool ok;
    {
        WriteStruct ws;
        ok = write_png(c, ws, img, channels);
    }
    if (c.file && std::fclose(c.file) != 0 && ok) {
        c.error = std::strerror(errno);
        ok = false;
    }
    if (!ok) why = c.error;
    return ok;
}

} // namespace cm::png
