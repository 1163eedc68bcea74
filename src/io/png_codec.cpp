#include "io/png_codec.h"

#include "io/image_io.h"

#include <png.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <new>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

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

// Float to 8 bits as OpenImageIO 2.4 converts a run of n values (see png_byte).
void to_bytes(const float* in, unsigned char* out, std::size_t n) {
    const std::size_t fours = n - n % 4;
    for (std::size_t i = 0; i < fours; ++i) out[i] = png_byte(in[i], false);
    for (std::size_t i = fours; i < n; ++i) out[i] = png_byte(in[i], true);
}

// One row of the first `nc` channels to 8 bits, as OpenImageIO wrote it: a whole row in one
// run when those are all the image's channels, a pixel at a time otherwise; alpha unassociated.
void row_to_bytes(const Image& img, int nc, int y, unsigned char* row) {
    const std::size_t w = std::size_t(img.width);
    const std::size_t first = std::size_t(y) * w * std::size_t(img.channels);
    if (img.eight_bit()) { // as stored
        const unsigned char* b = img.bytes.data() + first;
        if (nc == img.channels) std::copy_n(b, w * std::size_t(nc), row);
        else
            for (std::size_t x = 0; x < w; ++x) std::copy_n(b + x * img.channels, nc, row + x * nc);
    } else if (nc == img.channels) {
        to_bytes(img.pixels.data() + first, row, w * std::size_t(nc));
    } else {
        for (std::size_t x = 0; x < w; ++x)
            to_bytes(img.pixels.data() + first + x * img.channels, row + x * nc, std::size_t(nc));
    }
    const int alpha = nc == 2 ? 1 : (nc == 4 ? 3 : -1);
    if (alpha >= 0) // PNG wants unassociated alpha
        for (std::size_t x = 0; x < w; ++x) {
            unsigned char* p = row + x * nc;
            if (p[alpha])
                for (int k = 0; k < nc; ++k)
                    if (k != alpha) p[k] = static_cast<unsigned char>(std::min(255u, (p[k] * 255u) / p[alpha]));
        }
}

// Stores f(i) at out[i] for i in [from, to) and returns the sum of the bytes' absolute values
// taken as signed (summed in 16 bits 256 bytes at a time, which the compiler vectorises).
template <class F>
std::size_t store_and_sum(std::size_t from, std::size_t to, unsigned char* out, F f) {
    std::size_t sum = 0;
    for (std::size_t s = from; s < to;) {
        const std::size_t e = std::min(to, s + 256);
        std::uint16_t part = 0; // at most 256 x 128
        for (std::size_t i = s; i < e; ++i) {
            const unsigned char v = f(i);
            out[i] = v;
            part = std::uint16_t(part + std::min(v, static_cast<unsigned char>(-v)));
        }
        sum += part;
        s = e;
    }
    return sum;
}

// The bytes of a row under PNG filter `type` (0 None, 1 Sub, 2 Up, 3 Average, 4 Paeth) in
// `out`, given the row above (`prev`, zeros above the first) and the bytes per pixel; the
// result is the sum of the filtered bytes' absolute values taken as signed, libpng's measure.
std::size_t filter_row(int type, const unsigned char* row, const unsigned char* prev, std::size_t n, std::size_t bpp,
                       unsigned char* out) {
    using u8 = unsigned char;
    const std::size_t left = std::min(bpp, n); // the bytes with no pixel to their left
    switch (type) {
    case 0: return store_and_sum(0, n, out, [&](std::size_t i) { return row[i]; });
    case 1:
        return store_and_sum(0, left, out, [&](std::size_t i) { return row[i]; }) +
               store_and_sum(left, n, out, [&](std::size_t i) { return u8(row[i] - row[i - bpp]); });
    case 2: return store_and_sum(0, n, out, [&](std::size_t i) { return u8(row[i] - prev[i]); });
    case 3:
        return store_and_sum(0, left, out, [&](std::size_t i) { return u8(row[i] - prev[i] / 2); }) +
               store_and_sum(left, n, out, [&](std::size_t i) { return u8(row[i] - (prev[i] + row[i - bpp]) / 2); });
    default: // in 16 bits, twice as fast as in int
        return store_and_sum(0, left, out, [&](std::size_t i) { return u8(row[i] - prev[i]); }) +
               store_and_sum(left, n, out, [&](std::size_t i) {
                   using i16 = std::int16_t;
                   const i16 a = row[i - bpp], b = prev[i], c = prev[i - bpp];
                   const i16 p = i16(b - c), q = i16(a - c), r = i16(p + q);
                   const i16 pa = p < 0 ? i16(-p) : p, pb = q < 0 ? i16(-q) : q, pc = r < 0 ? i16(-r) : r;
                   return u8(row[i] - (((pa <= pb) & (pa <= pc)) ? a : (pb <= pc ? b : c)));
               });
    }
}

// The filtered image data, (width x channels + 1) x height bytes at `out`: each row behind
// its filter type byte, the filter chosen per row as libpng chooses it (the least sum of
// absolute values, the first such in the order None, Sub, Up, Average, Paeth; a single row
// leaves out the filters looking up, a single column those looking left). Blocks of rows in
// parallel, each converting its rows to bytes and the row above it.
void filter_image(const Image& img, int nc, unsigned char* out) {
    const std::size_t n = std::size_t(img.width) * std::size_t(nc);
    const bool use[5] = {true, img.width > 1, img.height > 1, img.width > 1 && img.height > 1,
                         img.width > 1 && img.height > 1};
    tbb::parallel_for(tbb::blocked_range<int>(0, img.height, 64), [&](const tbb::blocked_range<int>& rows) {
        std::vector<unsigned char> prev(n, 0), row(n), best(n), trial(n);
        if (rows.begin() > 0) row_to_bytes(img, nc, rows.begin() - 1, prev.data());
        for (int y = rows.begin(); y < rows.end(); ++y) {
            row_to_bytes(img, nc, y, row.data());
            std::size_t least = std::numeric_limits<std::size_t>::max();
            int chosen = 0;
            for (int type = 0; type < 5; ++type) {
                if (!use[type]) continue;
                const std::size_t sum = filter_row(type, row.data(), prev.data(), n, std::size_t(nc), trial.data());
                if (sum < least) {
                    least = sum;
                    chosen = type;
                    best.swap(trial);
                }
            }
            unsigned char* o = out + std::size_t(y) * (n + 1);
            o[0] = static_cast<unsigned char>(chosen);
            std::copy(best.begin(), best.end(), o + 1);
            prev.swap(row);
        }
    });
}

constexpr std::size_t kPiece = 256 * 1024;  // filtered bytes per deflate piece
constexpr std::size_t kWindow = 32 * 1024;  // deflate's window: what a piece is primed with
constexpr std::size_t kChunk = 1024 * 1024; // the most data in one IDAT chunk

// One piece of the stream deflated on its own: raw deflate primed with the 32 kB before it,
// ending byte-aligned with a sync flush (the last one with the final block).
struct Piece {
    std::unique_ptr<unsigned char[]> out; // `size` bytes of deflate data
    std::size_t size = 0;
    uLong adler = 1;
    std::string error;
};

struct Deflater {
    z_stream zs{};
    bool open = false;
    ~Deflater() {
        if (open) deflateEnd(&zs);
    }
};

void deflate_piece(const unsigned char* data, std::size_t begin, std::size_t end, bool last, Piece& p) {
    Deflater d;
    z_stream& zs = d.zs;
    int err = deflateInit2(&zs, 6, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY);
    d.open = err == Z_OK;
    if (err == Z_OK && begin > 0) {
        const std::size_t from = begin > kWindow ? begin - kWindow : 0;
        err = deflateSetDictionary(&zs, data + from, uInt(begin - from));
    }
    if (err == Z_OK) {
        // deflateBound holds the deflated data; a sync flush adds its few bytes of marker.
        const std::size_t room = deflateBound(&zs, uLong(end - begin)) + 64;
        p.out = std::make_unique_for_overwrite<unsigned char[]>(room);
        zs.next_in = const_cast<Bytef*>(data + begin);
        zs.avail_in = uInt(end - begin);
        zs.next_out = p.out.get();
        zs.avail_out = uInt(room);
        err = deflate(&zs, last ? Z_FINISH : Z_SYNC_FLUSH);
        const bool done = last ? err == Z_STREAM_END : err == Z_OK && zs.avail_in == 0 && zs.avail_out != 0;
        err = done ? Z_OK : (err == Z_OK || err == Z_STREAM_END ? Z_BUF_ERROR : err);
        p.size = zs.total_out;
    }
    if (err != Z_OK) p.error = zs.msg ? zs.msg : zError(err);
    p.adler = adler32(adler32(0, nullptr, 0), data + begin, uInt(end - begin));
}

// The zlib stream of `n` bytes, deflated at level 6 in pieces of about kPiece bytes in
// parallel (one piece up to 2 kPiece), as pigz does; the pieces concatenated make one
// deflate stream, between the zlib header and the Adler-32 of the whole. The number of
// pieces, or 0 with the reason in `why`.
std::size_t deflate_stream(const unsigned char* data, std::size_t n, std::vector<unsigned char>& out,
                           std::string& why) {
    const std::size_t count = n > 2 * kPiece ? (n + kPiece - 1) / kPiece : 1;
    std::vector<Piece> pieces(count);
    const auto start = [&](std::size_t k) { return n / count * k + n % count * k / count; }; // n k / count
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t k = r.begin(); k < r.end(); ++k)
            deflate_piece(data, start(k), start(k + 1), k + 1 == count, pieces[k]);
    });
    std::size_t total = 6;
    uLong adler = pieces[0].adler;
    for (std::size_t k = 0; k < count; ++k) {
        if (!pieces[k].error.empty()) return why = "zlib cannot compress the image data: " + pieces[k].error, 0;
        total += pieces[k].size;
        if (k > 0) adler = adler32_combine(adler, pieces[k].adler, z_off_t(start(k + 1) - start(k)));
    }
    out.clear();
    out.reserve(total);
    out.push_back(0x78); // deflate, 32 kB window
    out.push_back(0x9C); // level 6 (default), no dictionary; the header checksum
    for (const Piece& p : pieces) out.insert(out.end(), p.out.get(), p.out.get() + p.size);
    for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<unsigned char>(adler >> shift));
    return count;
}

// The signature, IHDR and oFFs chunks written by libpng, then the image data made beforehand
// (`idat`, a zlib stream) in IDAT chunks and the IEND chunk.
bool write_png(Context& c, WriteStruct& ws, const Image& img, int nc, const std::vector<unsigned char>& idat) {
    ws.sp = png_create_write_struct(PNG_LIBPNG_VER_STRING, &c, on_error, on_warning);
    if (!ws.sp) return c.error = "cannot make a PNG writer", false;
    ws.ip = png_create_info_struct(ws.sp);
    if (!ws.ip) return c.error = "cannot make a PNG writer", false;
    if (setjmp(png_jmpbuf(ws.sp))) return false;
    png_set_write_fn(ws.sp, &c, write_bytes, flush_bytes);
    static constexpr int kColour[] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                      PNG_COLOR_TYPE_RGB_ALPHA};
    png_set_IHDR(ws.sp, ws.ip, png_uint_32(img.width), png_uint_32(img.height), 8, kColour[nc - 1], PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_oFFs(ws.sp, ws.ip, 0, 0, PNG_OFFSET_PIXEL);
    png_write_info(ws.sp, ws.ip);
    for (std::size_t at = 0; at < idat.size(); at += kChunk)
        png_write_chunk(ws.sp, reinterpret_cast<png_const_bytep>("IDAT"), idat.data() + at,
                        std::min(kChunk, idat.size() - at));
    // Not png_write_end: libpng has not seen the image data go by and would refuse.
    png_write_chunk(ws.sp, reinterpret_cast<png_const_bytep>("IEND"), nullptr, 0);
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

bool write(const Image& img, int channels, const std::string& file, std::vector<unsigned char>* bytes, std::string& why,
           std::size_t* pieces) {
    if (img.width < 1 || img.height < 1 || channels < 1 || channels > 4 || channels > img.channels ||
        img.samples() < std::size_t(img.width) * img.height * img.channels)
        return why = "PNG takes 1 to 4 channels of a non-empty image", false;
    // The image data first, in parallel, then the file through libpng.
    std::vector<unsigned char> idat;
    try {
        const std::size_t size = (std::size_t(img.width) * std::size_t(channels) + 1) * std::size_t(img.height);
        const auto filtered = std::make_unique_for_overwrite<unsigned char[]>(size);
        filter_image(img, channels, filtered.get());
        const std::size_t count = deflate_stream(filtered.get(), size, idat, why);
        if (count == 0) return false;
        if (pieces) *pieces = count;
        if (bytes) // all the file: nothing allocated inside libpng's callback
            bytes->reserve(bytes->size() + 128 + idat.size() + 12 * (idat.size() / kChunk + 1));
    } catch (const std::bad_alloc&) {
        return why = "out of memory for the image data", false;
    } catch (const std::exception& e) {
        return why = e.what(), false;
    }
    Context c;
    c.bytes = bytes;
    if (!file.empty()) {
        c.file = std::fopen(file.c_str(), "wb");
        if (!c.file) return why = std::strerror(errno), false;
    }
    bool ok;
    {
        WriteStruct ws;
        ok = write_png(c, ws, img, channels, idat);
    }
    if (c.file && std::fclose(c.file) != 0 && ok) {
        c.error = std::strerror(errno);
        ok = false;
    }
    if (!ok) why = c.error;
    return ok;
}

} // namespace cm::png
