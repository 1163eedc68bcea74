#include "preview_sheet.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

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
    void paste(const Image& src, int x0, int y0, int w, int h, const Progress& progress = {}) {
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
                progress);
            return;
        }
        paste_pixels(
            src.width, src.height, x0, y0, w, h,
            [&](std::size_t i, float rgb[3], float& a) {
                const std::size_t s = i * std::size_t(ch);
                a = ch == 4 ? std::clamp(src.value(s + 3), 0.0f, 1.0f) : 1.0f;
                for (int k = 0; k < 3; ++k) rgb[k] = src.value(ch == 1 ? s : s + std::size_t(k));
            },
            progress);
    }
    /// The same for a sw x sh picture given by pixel(i, rgb, alpha) (i = row-major index),
    /// which need not be stored as an image.
    template <typename Pixel>
    void paste_pixels(int sw, int sh, int x0, int y0, int w, int h, Pixel pixel, const Progress& progress = {}) {
        paste_runs(
            sw, sh, x0, y0, w, h,
            [&](std::size_t first, int n, double acc[3]) {
                for (int i = 0; i < n; ++i) {
                    float v[3], a;
                    pixel(first + std::size_t(i), v, a);
                    for (int k = 0; k < 3; ++k) acc[k] += std::clamp(v[k], 0.0f, 1.0f) * a + (1.0f - a);
                }
            },
            progress);
    }
    /// The resizing itself: `run(first, n, acc)` adds to acc the colours over white of the n
    /// source pixels from row-major index `first` on (a run of one row), in that order.
    template <typename Run>
    void paste_runs(int sw, int sh, int x0, int y0, int w, int h, Run run, const Progress& progress) {
        const double f = std::min(double(w) / sw, double(h) / sh);
        const int dw = std::max(1, int(std::lround(sw * f))), dh = std::max(1, int(std::lround(sh * f)));
        const int ox = x0 + (w - dw) / 2, oy = y0 + (h - dh) / 2;
        tbb::parallel_for(0, dh, [&](int y) {
            if (y % 64 == 0) progress.check();
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

// The grey a coloured mesh is shaded as: lit, at most 0.94 of the page's white, so a white
// model reads as a light grey with its shading and outlines.
constexpr float kLitGrey = 0.9f;

// `shaded` (the shading and lines of the mesh on white) times `colour` (the mesh's colours
// on white), channel by channel: the colours lit and outlined, the page left white.
void multiply_rgb(Image& shaded, const Image& colour) {
    for (int y = 0; y < shaded.height; ++y)
        for (int x = 0; x < shaded.width; ++x)
            for (int k = 0; k < 3; ++k) shaded.at(x, y, k) *= colour.at(x, y, k);
}

// Where the parts of a sheet go.
struct Layout {
    int P, gap, scale;
    int line; ///< a row of text
    int nviews, width, height;
    Layout(int panel, int views)
        : P(panel),
          gap(std::max(8, P / 32)),
          scale(std::max(1, P / 160)),
          line(7 * scale + 2 * gap),
          nviews(views),
          width(3 * P + 4 * gap),
          height(2 * line + nviews * (line + P + gap) + line + gap) {}
};

// The sheet of one mesh: the layout, then its steps (the mesh drawn from each view, a row per
// view, the header, the legend), each drawing into its own part of the canvas.
class Sheet {
public:
    Sheet(const Mesh& mesh, const Views& views, const PreviewOptions& opt, const Progress& progress)
        : mesh_(mesh),
          views_(views),
          opt_(opt),
          progress_(progress),
          lay_(opt.panel, int(views.views.size())),
          canvas_(lay_.width, lay_.height, 0.93f) {}

    /// Step 3: the title and the error of all views, above the rows (once they are measured).
    void header(const SilhouetteError& error) {
        std::string title = opt_.title.empty() ? std::string("preview") : opt_.title;
        const int max_chars = (lay_.width - 2 * lay_.gap) / (6 * lay_.scale);
        if (int(title.size()) > max_chars) title = "..." + title.substr(title.size() - std::size_t(max_chars - 3));
        canvas_.text(lay_.gap, lay_.gap, title, lay_.scale, kInk);
        canvas_.text(lay_.gap, lay_.line,
                     "all views: xor " + fixed(error.xor_pct, 3) + "%  mean iou " + fixed(error.mean_iou, 4),
                     lay_.scale, kInk);
    }

    /// Step 1: the mesh drawn from each view's camera, at the panel's size (its samples give
    /// the anti-aliasing; lines half as wide as in a full drawing, to read as in one shrunk):
    /// the views side by side, each drawing's serial passes (its distances to the outline)
    /// beside the others' instead of one after another. A coloured mesh shows its colours
    /// under the same shading and lines: its colours alone would leave a white or pale
    /// model white on the white page.
    std::vector<Image> draw_meshes() const {
        ArtOptions art;
        art.paper = {1.0f, 1.0f, 1.0f};
        art.grain = 0;
        art.vignette = 0;
        art.outline_px = 1.0f;
        art.crease_px = 0.6f;
        const bool coloured = has_colour(mesh_);
        // Lit, the shading of a grey under white stays below the page's white.
        if (coloured) art.fill = {kLitGrey, kLitGrey, kLitGrey};
        std::vector<Image> drawn(static_cast<std::size_t>(lay_.nviews));
        tbb::parallel_for(0, lay_.nviews, [&](int v) {
            const View& view = views_.views[std::size_t(v)];
            const double f = std::min(1.0, double(lay_.P) / std::max(view.width, view.height));
            const int sw = std::max(1, int(std::lround(view.width * f))),
                      sh = std::max(1, int(std::lround(view.height * f)));
            const Camera small = resized_camera(view.camera, double(sw) / view.width);
            Image shaded = render_art(mesh_, small, sw, sh, art, progress_);
            if (coloured) multiply_rgb(shaded, render_colour(mesh_, small, sw, sh, {1, 1, 1}, progress_));
            drawn[std::size_t(v)] = std::move(shaded);
        });
        return drawn;
    }

    /// Step 2, per view: the mesh's render through its camera and its error, and a row of
    /// the sheet: the view's name and error, then its three panels: the input drawing, the
    /// mesh drawn above, and the overlay of the silhouettes. One render at a time: each
    /// takes the memory of the one before.
    ViewError view_row(int v, const Image& drawn) {
        const View& view = views_.views[std::size_t(v)];
        const SilhouetteMask mask = silhouette_mask(mesh_, view, progress_);
        const ViewError e = view_error(view, mask);
        const int y0 = 2 * lay_.line + v * (lay_.line + lay_.P + lay_.gap);
        canvas_.text(lay_.gap, y0 + lay_.gap, view.name + ":  xor " + fixed(e.xor_pct, 3) + "%  iou " + fixed(e.iou, 4),
                     lay_.scale, kInk);
        const int py = y0 + lay_.line;
        if (!view.image.empty()) canvas_.paste(view.image, lay_.gap, py, lay_.P, lay_.P, progress_);
        canvas_.paste(drawn, 2 * lay_.gap + lay_.P, py, lay_.P, lay_.P, progress_);
        overlay(view, mask, 3 * lay_.gap + 2 * lay_.P, py);
        return e;
    }

    /// Step 4: what the overlay's colours mean; the sheet is done.
    Image legend() {
        const int ly = 2 * lay_.line + lay_.nviews * (lay_.line + lay_.P + lay_.gap) + lay_.gap / 2;
        const int box = 7 * lay_.scale;
        int x = lay_.gap;
        canvas_.text(x, ly, "input | mesh | overlay:", lay_.scale, kGrey);
        x += 24 * 6 * lay_.scale;
        canvas_.rect(x, ly, box, box, kInputOnly);
        x += box + 2 * lay_.scale;
        canvas_.text(x, ly, "input only", lay_.scale, kGrey);
        x += 11 * 6 * lay_.scale;
        canvas_.rect(x, ly, box, box, kMeshOnly);
        x += box + 2 * lay_.scale;
        canvas_.text(x, ly, "mesh only", lay_.scale, kGrey);
        return std::move(canvas_.img);
    }

private:
    // The overlay: both grey, input only and mesh only in their colours. Each pixel adds one
    // of four colours; a destination pixel's sum is counted per colour, which is the same
    // double as adding them one by one (every partial sum of these floats is exact).
    void overlay(const View& view, const SilhouetteMask& r, int left, int top) {
        const Coverage& cover = view.coverage;
        canvas_.paste_runs(
            view.width, view.height, left, top, lay_.P, lay_.P,
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
            progress_);
    }

    static constexpr float kInk[3] = {0.12f, 0.12f, 0.14f}, kGrey[3] = {0.45f, 0.45f, 0.48f};
    const Mesh& mesh_;
    const Views& views_;
    const PreviewOptions& opt_;
    const Progress& progress_;
    const Layout lay_;
    Canvas canvas_;
};

} // namespace

void PreviewOptions::declare(ParamBinder& b) {
    b.add(panel,
          ParamSpec::Int("panel", 320, 32, 4096, "px", "size of each panel (the sheet has three panels per view)"));
    b.add(title, ParamSpec::String("title", std::string(), "printed at the top of the sheet; empty: the file's name"));
}

void PreviewStats::report(Metrics& m) const {
    m.metric("xor_pct", error.xor_pct);
    m.metric("mean_iou", error.mean_iou);
}

Result<Image, PreviewStats> make_preview_sheet(const Mesh& mesh, const Views& views, const PreviewOptions& opt,
                                               Progress progress) {
    if (views.views.empty()) throw Error("there are no views to preview");
    if (opt.panel < 32) throw Error("the panel size must be at least 32 pixels");
    progress(0);
    Sheet sheet(mesh, views, opt, progress);
    const std::vector<Image> drawn = sheet.draw_meshes();
    progress(0.3);
    const int nviews = int(views.views.size());
    std::vector<ViewError> errors;
    for (int v = 0; v < nviews; ++v) {
        progress(0.3 + 0.7 * v / nviews);
        errors.push_back(sheet.view_row(v, drawn[std::size_t(v)]));
    }
    SilhouetteError error = combine_view_errors(std::move(errors));
    sheet.header(error);
    progress(1);
    return {sheet.legend(), {std::move(error)}};
}

} // namespace cm
