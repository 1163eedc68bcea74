#include "preview_sheet.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>

#include <tbb/parallel_for.h>

#include "core/error.h"
#include "io/image_io.h"
#include "metrics/silhouette_error.h"
#include "render/shade.h"
#include "render/textured.h"

namespace cm {

namespace {

// 5x7 glyphs, one row per byte (low 5 bits, leftmost pixel in bit 4).
struct Glyph {
    char c;
    unsigned char rows[7];
};
constexpr Glyph kFont[] = {
    {'A', {14, 17, 17, 31, 17, 17, 17}}, {'B', {30, 17, 17, 30, 17, 17, 30}}, {'C', {14, 17, 16, 16, 16, 17, 14}},
    {'D', {28, 18, 17, 17, 17, 18, 28}}, {'E', {31, 16, 16, 30, 16, 16, 31}}, {'F', {31, 16, 16, 30, 16, 16, 16}},
    {'G', {14, 17, 16, 23, 17, 17, 15}}, {'H', {17, 17, 17, 31, 17, 17, 17}}, {'I', {14, 4, 4, 4, 4, 4, 14}},
    {'J', {7, 2, 2, 2, 2, 18, 12}},      {'K', {17, 18, 20, 24, 20, 18, 17}}, {'L', {16, 16, 16, 16, 16, 16, 31}},
    {'M', {17, 27, 21, 21, 17, 17, 17}}, {'N', {17, 17, 25, 21, 19, 17, 17}}, {'O', {14, 17, 17, 17, 17, 17, 14}},
    {'P', {30, 17, 17, 30, 16, 16, 16}}, {'Q', {14, 17, 17, 17, 21, 18, 13}}, {'R', {30, 17, 17, 30, 20, 18, 17}},
    {'S', {15, 16, 16, 14, 1, 1, 30}},   {'T', {31, 4, 4, 4, 4, 4, 4}},       {'U', {17, 17, 17, 17, 17, 17, 14}},
    {'V', {17, 17, 17, 17, 17, 10, 4}},  {'W', {17, 17, 17, 21, 21, 21, 10}}, {'X', {17, 17, 10, 4, 10, 17, 17}},
    {'Y', {17, 17, 17, 10, 4, 4, 4}},    {'Z', {31, 1, 2, 4, 8, 16, 31}},     {'0', {14, 17, 19, 21, 25, 17, 14}},
    {'1', {4, 12, 4, 4, 4, 4, 14}},      {'2', {14, 17, 1, 2, 4, 8, 31}},     {'3', {31, 2, 4, 2, 1, 17, 14}},
    {'4', {2, 6, 10, 18, 31, 2, 2}},     {'5', {31, 16, 30, 1, 1, 17, 14}},   {'6', {6, 8, 16, 30, 17, 17, 14}},
    {'7', {31, 1, 2, 4, 8, 8, 8}},       {'8', {14, 17, 17, 14, 17, 17, 14}}, {'9', {14, 17, 17, 15, 1, 2, 12}},
    {'.', {0, 0, 0, 0, 0, 12, 12}},      {'%', {24, 25, 2, 4, 8, 19, 3}},     {'-', {0, 0, 0, 31, 0, 0, 0}},
    {'_', {0, 0, 0, 0, 0, 0, 31}},       {':', {0, 12, 12, 0, 12, 12, 0}},    {'=', {0, 0, 31, 0, 31, 0, 0}},
    {'/', {0, 1, 2, 4, 8, 16, 0}},       {'(', {2, 4, 8, 8, 8, 4, 2}},        {')', {8, 4, 2, 2, 2, 4, 8}},
    {',', {0, 0, 0, 0, 12, 4, 8}},       {'+', {0, 4, 4, 31, 4, 4, 0}},       {'|', {4, 4, 4, 4, 4, 4, 4}},
};

// The sheet, in the bytes its PNG holds: each colour as the PNG writer would store it (a
// quarter of the memory of float RGB, and no conversion when it is written).
struct Canvas {
    Image img;
    std::size_t tail_from; ///< a row's samples from here on are its last n % 4 (see png_byte)
    Canvas(int w, int h, float grey) {
        img.width = w;
        img.height = h;
        img.channels = 3;
        const std::size_t row = std::size_t(w) * 3;
        tail_from = row - row % 4;
        img.bytes.resize(row * std::size_t(h));
        const float c[3] = {grey, grey, grey};
        tbb::parallel_for(0, h, [&](int y) {
            for (int x = 0; x < w; ++x) put(x, y, c);
        });
    }
    void put(int x, int y, const float* c) {
        if (x < 0 || y < 0 || x >= img.width || y >= img.height) return;
        const std::size_t k = std::size_t(x) * 3;
        std::uint8_t* p = &img.bytes[std::size_t(y) * std::size_t(img.width) * 3 + k];
        for (std::size_t i = 0; i < 3; ++i) p[i] = png_byte(c[i], k + i >= tail_from);
    }
    void rect(int x0, int y0, int w, int h, const float* c) {
        for (int y = y0; y < y0 + h; ++y)
            for (int x = x0; x < x0 + w; ++x) put(x, y, c);
    }
    /// Upper-case text with its top-left at (x, y), each font pixel drawn as scale x scale.
    void text(int x, int y, const std::string& s, int scale, const float* c) {
        for (char ch : s) {
            const char u = char(std::toupper(static_cast<unsigned char>(ch)));
            for (const Glyph& g : kFont)
                if (g.c == u)
                    for (int r = 0; r < 7; ++r)
                        for (int k = 0; k < 5; ++k)
                            if (g.rows[r] & (16 >> k)) rect(x + k * scale, y + r * scale, scale, scale, c);
            x += 6 * scale;
        }
    }
    /// Pastes `src` (RGB or RGBA over white), resized by area averaging to fit box w x h, centred.
    void paste(const Image& src, int x0, int y0, int w, int h, const RenderCheck& check = {}) {
        const int ch = src.channels;
        if (src.eight_bit()) {
            // Each byte's value as Image::value gives it, looked up. An opaque pixel adds its
            // colour as it is (v * 1 + 0, exactly).
            std::array<double, 256> lut;
            for (int b = 0; b < 256; ++b) lut[std::size_t(b)] = double(float(b) * (1.0f / 255.0f));
            const std::uint8_t* bytes = src.bytes.data();
            paste_runs(
                src.width, src.height, x0, y0, w, h,
                [&, ch](std::size_t first, int n, double acc[3]) {
                    const std::uint8_t* p = bytes + first * std::size_t(ch);
                    for (int i = 0; i < n; ++i, p += ch) {
                        if (ch != 4 || p[3] == 255) {
                            for (int k = 0; k < 3; ++k) acc[k] += lut[p[ch == 1 ? 0 : k]];
                            continue;
                        }
                        const float a = std::clamp(float(p[3]) * (1.0f / 255.0f), 0.0f, 1.0f);
                        for (int k = 0; k < 3; ++k) acc[k] += float(lut[p[k]]) * a + (1.0f - a);
                    }
                },
                check);
            return;
        }
        paste_pixels(
            src.width, src.height, x0, y0, w, h,
            [&](std::size_t i, float rgb[3], float& a) {
                const std::size_t s = i * std::size_t(ch);
                a = ch == 4 ? std::clamp(src.value(s + 3), 0.0f, 1.0f) : 1.0f;
                for (int k = 0; k < 3; ++k) rgb[k] = src.value(ch == 1 ? s : s + std::size_t(k));
            },
            check);
    }
    /// The same for a sw x sh picture given by pixel(i, rgb, alpha) (i = row-major index),
    /// which need not be stored as an image.
    template <typename Pixel>
    void paste_pixels(int sw, int sh, int x0, int y0, int w, int h, Pixel pixel, const RenderCheck& check = {}) {
        paste_runs(
            sw, sh, x0, y0, w, h,
            [&](std::size_t first, int n, double acc[3]) {
                for (int i = 0; i < n; ++i) {
                    float v[3], a;
                    pixel(first + std::size_t(i), v, a);
                    for (int k = 0; k < 3; ++k) acc[k] += std::clamp(v[k], 0.0f, 1.0f) * a + (1.0f - a);
                }
            },
            check);
    }
    /// The resizing itself: `run(first, n, acc)` adds to acc the colours over white of the n
    /// source pixels from row-major index `first` on (a run of one row), in that order.
    template <typename Run>
    void paste_runs(int sw, int sh, int x0, int y0, int w, int h, Run run, const RenderCheck& check) {
        const double f = std::min(double(w) / sw, double(h) / sh);
        const int dw = std::max(1, int(std::lround(sw * f))), dh = std::max(1, int(std::lround(sh * f)));
        const int ox = x0 + (w - dw) / 2, oy = y0 + (h - dh) / 2;
        tbb::parallel_for(0, dh, [&](int y) {
            if (check && y % 64 == 0) check();
            for (int x = 0; x < dw; ++x) {
                // Source pixels whose centres fall in the destination pixel; the nearest when none.
                const double sx0 = x / f, sx1 = (x + 1) / f, sy0 = y / f, sy1 = (y + 1) / f;
                int i0 = int(std::ceil(sx0 - 0.5)), i1 = int(std::ceil(sx1 - 0.5)) - 1;
                int j0 = int(std::ceil(sy0 - 0.5)), j1 = int(std::ceil(sy1 - 0.5)) - 1;
                if (i1 < i0) i0 = i1 = std::min(sw - 1, int((sx0 + sx1) / 2));
                if (j1 < j0) j0 = j1 = std::min(sh - 1, int((sy0 + sy1) / 2));
                i1 = std::min(i1, sw - 1);
                j1 = std::min(j1, sh - 1);
                const int ni = std::max(0, i1 - i0 + 1), nj = std::max(0, j1 - j0 + 1);
                double acc[3] = {0, 0, 0};
                if (ni > 0)
                    for (int j = j0; j <= j1; ++j) run(std::size_t(j) * std::size_t(sw) + std::size_t(i0), ni, acc);
                const int cnt = ni * nj;
                float c[3];
                for (int k = 0; k < 3; ++k) c[k] = float(acc[k] / std::max(cnt, 1));
                put(ox + x, oy + y, c);
            }
        });
    }
};

std::string fixed(double v, int digits) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    return buf;
}

} // namespace

Image make_preview_sheet(const Mesh& mesh, const Views& views, const PreviewOptions& opt, SilhouetteError& error) {
    if (views.views.empty()) throw Error("there are no views to preview");
    if (opt.panel < 32) throw Error("the panel size must be at least 32 pixels");
    if (opt.progress) opt.progress(0);
    // The error's renders are the overlays' too.
    SilhouetteRenders renders;
    renders.error = silhouette_error(mesh, views, &renders.masks, opt.check);
    error = renders.error;
    return make_preview_sheet(mesh, views, opt, renders);
}

Image make_preview_sheet(const Mesh& mesh, const Views& views, const PreviewOptions& opt,
                         const SilhouetteRenders& renders) {
    if (views.views.empty()) throw Error("there are no views to preview");
    if (opt.panel < 32) throw Error("the panel size must be at least 32 pixels");
    if (renders.masks.size() != views.views.size() || renders.error.views.size() != views.views.size())
        throw Error("the silhouette renders are not of these views");
    auto step = [&](double f) {
        if (opt.progress) opt.progress(f);
    };
    const SilhouetteError& error = renders.error;
    const auto& masks = renders.masks;
    step(0.3);
    const int P = opt.panel, gap = std::max(8, P / 32), scale = std::max(1, P / 160);
    const int line = 7 * scale + 2 * gap; // a row of text
    const int nviews = int(views.views.size());
    const int width = 3 * P + 4 * gap;
    const int height = 2 * line + nviews * (line + P + gap) + line + gap;
    Canvas sheet(width, height, 0.93f);
    const float ink[3] = {0.12f, 0.12f, 0.14f}, grey[3] = {0.45f, 0.45f, 0.48f};

    std::string title = opt.title.empty() ? std::string("preview") : opt.title;
    const int max_chars = (width - 2 * gap) / (6 * scale);
    if (int(title.size()) > max_chars) title = "..." + title.substr(title.size() - std::size_t(max_chars - 3));
    sheet.text(gap, gap, title, scale, ink);
    sheet.text(gap, line, "all views: xor " + fixed(error.xor_pct, 3) + "%  mean iou " + fixed(error.mean_iou, 4),
               scale, ink);

    ArtOptions art;
    art.paper = {1.0f, 1.0f, 1.0f};
    art.grain = 0;
    art.vignette = 0;
    art.outline_px = 1.0f;
    art.crease_px = 0.6f;
    art.check = opt.check;
    // 2. the mesh drawn from each view's camera, at the panel's size (its samples give the
    // anti-aliasing; lines half as wide as in a full drawing, to read as in one shrunk): the
    // views side by side, each drawing's serial passes (its distances to the outline) beside
    // the others' instead of one after another.
    std::vector<Image> drawn(static_cast<std::size_t>(nviews));
    tbb::parallel_for(0, nviews, [&](int v) {
        const View& view = views.views[std::size_t(v)];
        const double f = std::min(1.0, double(P) / std::max(view.width, view.height));
        const int sw = std::max(1, int(std::lround(view.width * f))),
                  sh = std::max(1, int(std::lround(view.height * f)));
        // (a coloured mesh in its own colours, unlit, to hold beside the drawing)
        const Camera small = resized_camera(view.camera, double(sw) / view.width);
        drawn[std::size_t(v)] = has_colour(mesh) ? render_colour(mesh, small, sw, sh, {1, 1, 1}, opt.check)
                                                 : render_art(mesh, small, sw, sh, art);
    });
    for (int v = 0; v < nviews; ++v) {
        step(0.3 + 0.7 * v / nviews);
        const View& view = views.views[std::size_t(v)];
        const ViewError& e = error.views[std::size_t(v)];
        const int y0 = 2 * line + v * (line + P + gap);
        sheet.text(gap, y0 + gap, view.name + ":  xor " + fixed(e.xor_pct, 3) + "%  iou " + fixed(e.iou, 4), scale,
                   ink);
        const int py = y0 + line;
        // 1. the input drawing
        if (!view.image.empty()) sheet.paste(view.image, gap, py, P, P, opt.check);
        // 2. the mesh, drawn above
        sheet.paste(drawn[std::size_t(v)], 2 * gap + P, py, P, P, opt.check);
        // 3. overlay: both grey, input only and mesh only in their colours. Each pixel adds
        // one of four colours; a destination pixel's sum is counted per colour, which is the
        // same double as adding them one by one (every partial sum of these floats is exact).
        const std::vector<std::uint8_t>& r = masks[std::size_t(v)];
        const Coverage& cover = view.coverage;
        sheet.paste_runs(
            view.width, view.height, 3 * gap + 2 * P, py, P, P,
            [&](std::size_t first, int n, double acc[3]) {
                int count[4] = {0, 0, 0, 0}; // none, mesh only, input only, both
                const int y = int(first / std::size_t(view.width)), x0 = int(first % std::size_t(view.width));
                // The run's pixels in the coverage's window [a, b) read its row; the others are
                // outside the drawing.
                const float* row = cover.window_row(y);
                const int a = row ? std::clamp(cover.x0() - x0, 0, n) : n;
                const int b = row ? std::clamp(cover.x0() + cover.window_width() - x0, a, n) : n;
                const std::uint8_t* mask = r.data() + first;
                int mesh = 0, inside = 0, both = 0;
                for (int k = 0; k < a; ++k) mesh += mask[k] != 0;
                for (int k = b; k < n; ++k) mesh += mask[k] != 0;
                const float* in = row ? row + (x0 + a - cover.x0()) : nullptr;
                for (int k = a; k < b; ++k) {
                    const int i = in[k - a] >= 0.5f, m = mask[k] != 0;
                    mesh += m;
                    inside += i;
                    both += i & m;
                }
                count[1] = mesh - both;
                count[2] = inside - both;
                count[3] = both;
                count[0] = n - count[1] - count[2] - count[3];
                static constexpr float kBoth[3] = {0.62f, 0.62f, 0.64f}, kNone[3] = {1.0f, 1.0f, 1.0f};
                static constexpr const float* kColours[4] = {kNone, kMeshOnly, kInputOnly, kBoth};
                for (int c = 0; c < 4; ++c)
                    for (int k = 0; k < 3; ++k) acc[k] += double(count[c]) * double(kColours[c][k]);
            },
            opt.check);
    }
    step(1);
    // Legend.
    const int ly = 2 * line + nviews * (line + P + gap) + gap / 2;
    const int box = 7 * scale;
    int x = gap;
    sheet.text(x, ly, "input | mesh | overlay:", scale, grey);
    x += 24 * 6 * scale;
    sheet.rect(x, ly, box, box, kInputOnly);
    x += box + 2 * scale;
    sheet.text(x, ly, "input only", scale, grey);
    x += 11 * 6 * scale;
    sheet.rect(x, ly, box, box, kMeshOnly);
    x += box + 2 * scale;
    sheet.text(x, ly, "mesh only", scale, grey);
    return sheet.img;
}

} // namespace cm
