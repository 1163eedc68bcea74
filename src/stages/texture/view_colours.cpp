#include "view_colours.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "drawing/fill.h"
#include "drawing/ink.h"
#include "geometry/distance_transform.h"

namespace cm {

void CleanOptions::declare(ParamBinder& b) {
    b.add(strokes,
          ParamSpec::Enum("strokes", "strip", {"strip", "keep"},
                          "the drawing's strokes: strip leaves out ink (outlines, hatching: thin, dark, "
                          "high-contrast) and the paper between marker strokes, and fills them from the "
                          "neighbouring fill colour; keep takes the drawing's pixels as drawn, for a hand-drawn look "
                          "(was strip_lines: false)"),
          {Strokes::Strip, Strokes::Keep});
    b.add(line_width,
          ParamSpec::Float("line_width", 4, 1, 64, "px", "the widest stroke taken for ink (strokes: strip)"));
    b.add(line_contrast, ParamSpec::Float("line_contrast", 0.12, 0.01, 1, "",
                                          "how much darker (luminance, 0-1) than the fill around it a stroke is"));
    b.add(paper_slivers,
          ParamSpec::Bool("paper_slivers", true,
                          "with strokes: strip, also leave out the paper showing between marker or hatching strokes "
                          "(thin, lighter than around them by line_contrast, near the paper's colour) and the pale "
                          "streaks where a marker ran dry (thin, nearer the paper than both sides by 15 % of their "
                          "distance to it, towards it from the fill around, repeated, with no paper within 1.5 "
                          "line widths: hatching's pale gaps beside the paper stay as drawn), so the fill does "
                          "not come out paler than drawn or flecked"));
    b.add(ink_chroma, ParamSpec::Float("ink_chroma", 0.25, 0, 1, "",
                                       "strokes at least this saturated (largest minus smallest of R, G, B, 0-1) are "
                                       "coloured: marker or coloured hatching, part of the fill and smoothed with it, "
                                       "not ink (1: every thin dark stroke is ink)"));
    b.add(fill_smooth, ParamSpec::Float("fill_smooth", 5, 0, 64, "px",
                                        "radius of the low-pass of the fill across the stroke pattern: where strokes "
                                        "were left out around a pixel, its colour leans to the mean of the fill "
                                        "around it (0: the pixels' own colours)"));
    b.add(erode_px,
          ParamSpec::Float("erode", 2, 0, 64, "px", "silhouette border not sampled (the background bleeds in there)"));
    b.add(blend_px, ParamSpec::Float("blend", 3, 0.5, 64, "px",
                                     "width over which a view's say fades out towards the eroded border and the "
                                     "mesh's occlusion edges in it, so views blend across seams (under ink a view has "
                                     "no say; beside it, full say)"));
}

namespace {

// Leaves the strokes out of `valid` and `drawn`: ink (and its fringe) and, with
// paper_slivers, the paper between strokes and the pale streaks where a marker ran dry. With fill_smooth, `fill` gets each valid pixel's
// colour: its own, leaning to the fill's low-pass as much as strokes crowd around it (a
// flat drawing keeps its pixels, a marker drawing its fill's mean, not the stroke pattern).
void strip_strokes(const Image& img, const std::vector<char>& inside, const CleanOptions& opt, ViewColours& vc,
                   std::vector<char>& valid, std::vector<char>& drawn, std::vector<std::array<float, 3>>& fill) {
    const int w = img.width, h = img.height;
    const std::size_t n = std::size_t(w) * h;
    // The paper between strokes first: beside it the fill looks dark, and the ink finder
    // would take it all for ink. Its pixels take the fill around them before ink is looked for.
    std::vector<char> slivers(n, 0);
    const Image* searched = &img;
    Image patched;
    const std::array<float, 3> paper = paper_colour(img, inside);
    if (opt.paper_slivers) {
        slivers = find_paper_slivers(img, inside, paper, opt.line_width, opt.line_contrast);
        std::vector<char> keep(n);
        for (std::size_t i = 0; i < n; ++i) keep[i] = inside[i] && !slivers[i];
        std::vector<float> unused;
        const auto around = fill_under_strokes(img, keep, slivers, int(std::ceil(opt.line_width)), unused);
        patched.width = w;
        patched.height = h;
        patched.channels = 3;
        patched.pixels.resize(n * 3);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const std::size_t i = std::size_t(y) * w + x;
                for (int c = 0; c < 3; ++c) patched.pixels[i * 3 + c] = slivers[i] ? around[i][c] : img.at(x, y, c);
            }
        searched = &patched;
    }
    const std::vector<char> all_strokes = find_ink(*searched, inside, opt.line_width, opt.line_contrast, false);
    std::vector<char> ink = all_strokes;
    if (opt.ink_chroma < 1) keep_neutral_ink(*searched, ink, opt.ink_chroma);
    const std::vector<char> fringed = grow_ink(ink, inside, w, h);
    std::vector<char> strokes(n), loose(n);
    for (std::size_t i = 0; i < n; ++i) {
        vc.line_pixels += ink[i] && inside[i] ? 1 : 0;
        vc.sliver_pixels += slivers[i] && !fringed[i] ? 1 : 0;
        // Coloured strokes stay (their colour is the fill's) but count as the stroke pattern.
        strokes[i] = fringed[i] || slivers[i] || all_strokes[i];
        loose[i] = valid[i] && !ink[i] && !slivers[i]; // the fringe kept
        if (ink[i]) drawn[i] = 0;
        if (fringed[i] || slivers[i]) valid[i] = 0;
    }
    if (opt.paper_slivers) {
        // Where the marker ran dry: thin streaks paler, towards the paper, than the fill
        // around them. Left in, they come out as pale flecks in the texture. They often
        // run along a stroke, in its fringe: looked for among the fringe's pixels too (the
        // fill of strokes too dense for any pixel clear of their fringe is the fringe's).
        std::vector<float> unused;
        const auto around = fill_under_strokes(img, loose, strokes, int(std::ceil(2 * opt.line_width)), unused);
        const std::vector<char> pale = find_pale_streaks(img, inside, around, paper, opt.line_width);
        for (std::size_t i = 0; i < n; ++i)
            if (pale[i] && loose[i]) {
                vc.sliver_pixels += valid[i] ? 1 : 0;
                strokes[i] = 1;
                valid[i] = loose[i] = 0;
            }
    }
    if (opt.fill_smooth <= 0) return;
    const int r = int(opt.fill_smooth);
    std::vector<float> share, core;
    const std::vector<std::array<float, 3>> low = fill_under_strokes(img, valid, strokes, r, share);
    fill_under_strokes(img, valid, valid, r, core);
    // Strokes so dense that no pixel beside them is clear of their fringe: the fringe's own
    // mean (slightly darkened by the ink in it) rather than no colour from this view at all.
    bool crowded = false;
    for (std::size_t i = 0; i < n && !crowded; ++i) crowded = loose[i] && !valid[i] && core[i] == 0;
    std::vector<float> unused;
    const std::vector<std::array<float, 3>> low_loose =
        crowded ? fill_under_strokes(img, loose, strokes, r, unused) : std::vector<std::array<float, 3>>{};
    fill.resize(n);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            if (crowded && loose[i] && !valid[i] && core[i] == 0) {
                valid[i] = 1;
                fill[i] = low_loose[i];
                continue;
            }
            // A quarter of the window in strokes is a stroke pattern: the fill's mean all through.
            const float a = std::clamp(4.0f * share[i], 0.0f, 1.0f);
            for (int c = 0; c < 3; ++c)
                fill[i][std::size_t(c)] = (1 - a) * img.at(x, y, c) + a * low[i][std::size_t(c)];
        }
}

} // namespace

ViewColours clean_view_colours(const View& view, const DepthImage* depth, double depth_jump, const CleanOptions& opt) {
    const Image& img = view.image;
    const int w = img.width, h = img.height;
    const std::size_t n = std::size_t(w) * h;
    ViewColours vc;
    vc.width = w;
    vc.height = h;
    vc.rgb.resize(n);
    vc.confidence.assign(n, 0.0f);
    std::vector<char> inside(n), outside(n);
    const bool given = view.coverage.size() == n;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
            inside[i] = given ? view.coverage.at(x, y) >= 0.5f : 1;
            outside[i] = !inside[i];
        }
    const std::vector<float> d_out = squared_edt(outside, w, h);
    // valid: the pixel's own colour is taken. drawn: the drawing gives a colour there, the
    // pixel's own or, on the one-pixel fringe of an ink stroke (anti-aliased, part ink), the
    // fill's beside it. Ink proper gives none; the view's say there is 0, and near it full
    // (the fill beside a stroke is as sure as any), so a view keeps its colours up to its
    // own lines and other views fill in only under them.
    std::vector<char> valid(n), weak(n);
    for (std::size_t i = 0; i < n; ++i) valid[i] = inside[i] && d_out[i] > opt.erode_px * opt.erode_px;
    std::vector<char> drawn = valid;
    std::vector<std::array<float, 3>> fill;
    if (opt.strokes == CleanOptions::Strokes::Strip) strip_strokes(img, inside, opt, vc, valid, drawn, fill);
    // The say ramps up from the eroded border and from occlusion edges.
    for (std::size_t i = 0; i < n; ++i) weak[i] = !inside[i] || d_out[i] <= opt.erode_px * opt.erode_px;
    // Occlusion edges of the mesh in this view: a surface behind another one ends there,
    // so the view's say fades out before it.
    if (depth && depth->width == w && depth->height == h)
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const std::size_t i = std::size_t(y) * w + x;
                if (!depth->covered(x, y)) continue;
                const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
                for (int k = 0; k < 4; ++k) {
                    if (nx[k] < 0 || ny[k] < 0 || nx[k] >= w || ny[k] >= h) continue;
                    const std::size_t j = std::size_t(ny[k]) * w + nx[k];
                    if (!depth->covered(nx[k], ny[k]) || std::abs(depth->depth[j] - depth->depth[i]) > depth_jump) {
                        weak[i] = 1;
                        break;
                    }
                }
            }
    const std::vector<float> d_weak = squared_edt(weak, w, h);
    for (std::size_t i = 0; i < n; ++i)
        vc.confidence[i] =
            drawn[i] ? std::clamp((std::sqrt(d_weak[i]) - 0.5f) / std::max(opt.blend_px, 0.5f), 0.0f, 1.0f) : 0.0f;
    vc.drawn = std::move(drawn);
    vc.border_px.resize(n);
    for (std::size_t i = 0; i < n; ++i) vc.border_px[i] = std::sqrt(d_out[i]);
    // Every other pixel takes the colour of the nearest valid one (breadth first, 8-connected).
    std::vector<std::uint32_t> queue;
    queue.reserve(n);
    std::vector<char> done(n, 0);
    for (std::size_t i = 0; i < n; ++i)
        if (valid[i]) {
            const int x = int(i % std::size_t(w)), y = int(i / std::size_t(w));
            vc.rgb[i] = fill.empty()
                            ? std::array<float, 3>{img.at(x, y, 0), img.at(x, y, std::min(1, img.channels - 1)),
                                                   img.at(x, y, std::min(2, img.channels - 1))}
                            : fill[i];
            done[i] = 1;
            queue.push_back(std::uint32_t(i));
        }
    vc.any_valid = !queue.empty();
    if (!vc.any_valid) {
        for (std::size_t i = 0; i < n; ++i) {
            const int x = int(i % std::size_t(w)), y = int(i / std::size_t(w));
            vc.rgb[i] = {img.at(x, y, 0), img.at(x, y, std::min(1, img.channels - 1)),
                         img.at(x, y, std::min(2, img.channels - 1))};
        }
        return vc;
    }
    for (std::size_t q = 0; q < queue.size(); ++q) {
        const std::uint32_t i = queue[q];
        const int x = int(i % std::uint32_t(w)), y = int(i / std::uint32_t(w));
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int xx = x + dx, yy = y + dy;
                if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                const std::size_t j = std::size_t(yy) * w + xx;
                if (done[j]) continue;
                done[j] = 1;
                vc.rgb[j] = vc.rgb[i];
                queue.push_back(std::uint32_t(j));
            }
    }
    return vc;
}

void ViewColours::sample(double x, double y, std::array<float, 3>& c, float& conf) const {
    const double fx = std::clamp(x - 0.5, 0.0, double(width - 1)), fy = std::clamp(y - 0.5, 0.0, double(height - 1));
    const int x0 = int(fx), y0 = int(fy);
    const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
    const float ax = float(fx - x0), ay = float(fy - y0);
    const float wts[4] = {(1 - ax) * (1 - ay), ax * (1 - ay), (1 - ax) * ay, ax * ay};
    const std::size_t idx[4] = {std::size_t(y0) * width + x0, std::size_t(y0) * width + x1,
                                std::size_t(y1) * width + x0, std::size_t(y1) * width + x1};
    c = {0, 0, 0};
    conf = 0;
    for (int k = 0; k < 4; ++k) {
        for (int ch = 0; ch < 3; ++ch) c[ch] += wts[k] * rgb[idx[k]][ch];
        conf += wts[k] * confidence[idx[k]];
    }
}

} // namespace cm
