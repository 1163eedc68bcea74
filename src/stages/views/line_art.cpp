#include "line_art.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <tbb/parallel_for.h>

#include "components.h"
#include "geometry/distance_transform.h"

namespace cm {

namespace {

// The window (px each way) the local stroke width is averaged over.
constexpr int kWidthWindow = 10;

// The outline stroke's width where it was measured (-1 elsewhere): at the object's pixels
// beside the background with the object's blank inside behind the stroke, the distance to
// the background plus the distance to that blank, less a pixel (both from pixel centres).
std::vector<float> stroke_widths(const std::vector<float>& to_bg2, const std::vector<float>& to_blank2,
                                 const std::vector<char>& ink, int w, int h, std::vector<float>& samples) {
    std::vector<float> width(to_bg2.size(), -1.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            // Not ink on the outer edge, or no blank: 1 + the distance to the blank - 1.
            if (!ink[i] || to_bg2[i] != 1.0f || to_blank2[i] >= kEdtFar) continue;
            width[i] = std::sqrt(to_blank2[i]);
            samples.push_back(width[i]);
        }
    return width;
}

// Per pixel, half the mean of the width samples up to `cap` within kWidthWindow; `fallback`
// (half the median) where none lies near. Only where `wanted`.
std::vector<float> half_widths(const std::vector<float>& width, float cap, float fallback,
                               const std::vector<char>& wanted, int w, int h) {
    const std::size_t W = std::size_t(w) + 1;
    std::vector<double> sum(W * (std::size_t(h) + 1), 0.0), count(sum.size(), 0.0);
    for (int y = 0; y < h; ++y) {
        double rs = 0, rc = 0;
        for (int x = 0; x < w; ++x) {
            const float v = width[std::size_t(y) * w + x];
            if (v > 0 && v <= cap) {
                rs += v;
                rc += 1;
            }
            sum[(std::size_t(y) + 1) * W + x + 1] = sum[std::size_t(y) * W + x + 1] + rs;
            count[(std::size_t(y) + 1) * W + x + 1] = count[std::size_t(y) * W + x + 1] + rc;
        }
    }
    std::vector<float> half(width.size(), fallback);
    tbb::parallel_for(0, h, [&](int y) {
        const std::size_t y0 = std::size_t(std::max(0, y - kWidthWindow)),
                          y1 = std::size_t(std::min(h, y + kWidthWindow + 1));
        for (int x = 0; x < w; ++x) {
            if (!wanted[std::size_t(y) * w + x]) continue;
            const std::size_t x0 = std::size_t(std::max(0, x - kWidthWindow)),
                              x1 = std::size_t(std::min(w, x + kWidthWindow + 1));
            const double c = count[y1 * W + x1] - count[y0 * W + x1] - count[y1 * W + x0] + count[y0 * W + x0];
            if (c < 1) continue;
            const double s = sum[y1 * W + x1] - sum[y0 * W + x1] - sum[y1 * W + x0] + sum[y0 * W + x0];
            half[std::size_t(y) * w + x] = float(0.5 * s / c);
        }
    });
    return half;
}

// The medial pixels of the object where it is thin: those whose distance to the background
// (squared, `to_bg2`) is a ridge across some direction (at least the neighbour's on one side,
// more than the other's), with their half-thickness up to `reach`: the distance less half a
// pixel (the rim pixel's centre is half a pixel inside), half a pixel more between two of
// equal distance across the part (an even number of pixels thick).
std::vector<std::pair<std::size_t, float>> thin_ridge(const std::vector<float>& to_bg2, const std::vector<char>& bg,
                                                      float reach, int w, int h) {
    std::vector<std::pair<std::size_t, float>> ridge;
    const float reach2 = (reach + 0.5f) * (reach + 0.5f);
    auto d2 = [&](int x, int y) { return to_bg2[std::size_t(y) * w + x]; };
    const int dirs[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
    // The background within `len` px both ways along (dx, dy): the part is thin across there
    // (a ridge of the distance near a thick part's curved edge is not).
    auto thin_across = [&](int x, int y, int dx, int dy, float len) {
        const int steps = int(std::ceil(len / std::hypot(float(dx), float(dy))));
        for (const int sign : {1, -1}) {
            bool reached = false;
            for (int k = 1; k <= steps && !reached; ++k) {
                const int xx = x + sign * k * dx, yy = y + sign * k * dy;
                reached = xx < 0 || yy < 0 || xx >= w || yy >= h || bg[std::size_t(yy) * w + xx];
            }
            if (!reached) return false;
        }
        return true;
    };
    for (int y = 1; y + 1 < h; ++y)
        for (int x = 1; x + 1 < w; ++x) {
            const float c = d2(x, y);
            if (bg[std::size_t(y) * w + x] || c > reach2) continue;
            bool medial = false, even = false;
            for (const auto& d : dirs) {
                const float a = d2(x + d[0], y + d[1]), b = d2(x - d[0], y - d[1]);
                if (c >= a && c >= b && (c > a || c > b) && thin_across(x, y, d[0], d[1], std::sqrt(c) + 1.5f)) {
                    medial = true;
                    even = even || ((d[0] == 0 || d[1] == 0) && (a == c || b == c));
                }
            }
            if (medial) ridge.push_back({std::size_t(y) * w + x, std::sqrt(c) - (even ? 0.0f : 0.5f)});
        }
    return ridge;
}

// Cores the thin-part rule raised where the pull left nothing, in pieces (4-connected)
// under four strokes squared: the outer corner of a stroke turning a sharp convex corner,
// whose distance ridge starts thin at the tip, not a part (a box drawn in thick lines got a
// speck or a knob at each corner). A part thinner than two strokes is long against them.
// They go back to what the pull left, with the raised fringe around them. Returns how many.
std::size_t drop_stray_cores(std::vector<float>& out, const std::vector<float>& pulled, float stroke, int w, int h) {
    const std::size_t n = std::size_t(w) * h;
    std::vector<char> mask(n);
    for (std::size_t i = 0; i < n; ++i) mask[i] = out[i] >= 0.5f && pulled[i] < 0.5f;
    std::vector<int> lab;
    std::vector<std::size_t> sizes;
    const int nc = mask_components(mask, w, h, false, lab, sizes);
    std::vector<char> stray(std::size_t(nc), 0);
    std::size_t dropped = 0;
    for (int c = 0; c < nc; ++c) {
        stray[std::size_t(c)] = double(sizes[std::size_t(c)]) < 4.0 * stroke * stroke;
        dropped += stray[std::size_t(c)] != 0;
    }
    if (!dropped) return 0;
    std::vector<char> gone(n, 0);
    for (std::size_t i = 0; i < n; ++i) gone[i] = lab[i] >= 0 && stray[std::size_t(lab[i])];
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            if (out[i] <= pulled[i]) continue;
            bool near_gone = gone[i] != 0;
            for (int dy = -1; dy <= 1 && !near_gone; ++dy)
                for (int dx = -1; dx <= 1 && !near_gone; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    near_gone = xx >= 0 && yy >= 0 && xx < w && yy < h && gone[std::size_t(yy) * w + xx];
                }
            if (near_gone) out[i] = pulled[i];
        }
    return dropped;
}

// Pockets of blank paper outside the outline that gap closing shut (the wedge where two
// strokes meet at a concave corner): blank object pixels beside the background whose blank
// piece (4-connected) lies within `reach` of it everywhere and is no larger than a square
// two reaches wide. They become background.
std::size_t open_outside_pockets(std::vector<char>& bg, const std::vector<char>& ink, const std::vector<float>& to_bg2,
                                 float reach, int w, int h) {
    const std::size_t n = bg.size();
    std::vector<char> blank(n);
    for (std::size_t i = 0; i < n; ++i) blank[i] = !bg[i] && !ink[i];
    std::vector<int> lab;
    std::vector<std::size_t> sizes;
    const int count = mask_components(blank, w, h, false, lab, sizes);
    // Per piece: beside the background, and how far from it its deepest pixel lies.
    std::vector<char> beside(std::size_t(count), 0);
    std::vector<float> deepest(std::size_t(count), 0.0f);
    for (std::size_t i = 0; i < n; ++i) {
        if (lab[i] < 0) continue;
        const std::size_t k = std::size_t(lab[i]);
        beside[k] = beside[k] || to_bg2[i] <= 2.0f;
        deepest[k] = std::max(deepest[k], to_bg2[i]);
    }
    // Deep, or large (the paper between doubled strokes, reached through a break): inside.
    const float reach2 = reach * reach;
    std::size_t opened = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (lab[i] < 0) continue;
        const std::size_t k = std::size_t(lab[i]);
        if (!beside[k] || deepest[k] > reach2 || float(sizes[k]) > 4.0f * reach2) continue;
        bg[i] = 1;
        ++opened;
    }
    return opened;
}

// How deep pixel (x, y)'s centre lies inside the silhouette's anti-aliased edge (px): a
// pixel j of coverage c_j < 1 holds the edge c_j - 1/2 beyond its centre (a straight edge
// across it), so the depth is the least |p - j| + c_j - 1/2 over the pixels within `to_bg`
// (the distance to the nearest background pixel) and a pixel more.
float edge_depth(const std::vector<float>& coverage, int x, int y, float to_bg, int w, int h) {
    const int r = int(std::ceil(to_bg)) + 1;
    float best = to_bg - 0.5f;
    for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
            const int xx = x + dx, yy = y + dy;
            if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
            const float c = coverage[std::size_t(yy) * w + xx];
            if (c < 1.0f) best = std::min(best, std::hypot(float(dx), float(dy)) + c - 0.5f);
        }
    return best;
}

} // namespace

void give_back_barrier_rim(std::vector<char>& bg, const std::vector<char>& ink, const std::vector<char>& closed,
                           const std::vector<char>& from, int w, int h) {
    std::vector<char> rim(bg.size(), 0); // found first, set after: `from` may be `bg` itself
    tbb::parallel_for(0, h, [&](int y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            if (bg[i] || ink[i] || !closed[i]) continue;
            bool near = false;
            for (int dy = -1; dy <= 1 && !near; ++dy)
                for (int dx = -1; dx <= 1 && !near; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    near = xx >= 0 && yy >= 0 && xx < w && yy < h && from[std::size_t(yy) * w + xx];
                }
            rim[i] = near;
        }
    });
    for (std::size_t i = 0; i < bg.size(); ++i)
        if (rim[i]) bg[i] = 1;
}

StrokeCentre pull_to_stroke_centre(std::vector<float>& coverage, const std::vector<char>& bg_in,
                                   const std::vector<char>& ink, double close_gaps, int w, int h) {
    StrokeCentre res;
    const std::size_t n = std::size_t(w) * h;
    std::vector<char> bg = bg_in;
    std::vector<char> blank(n);
    for (std::size_t i = 0; i < n; ++i) blank[i] = !bg[i] && !ink[i];
    std::vector<float> to_bg2 = squared_edt(bg, w, h);
    const std::vector<float> to_blank2 = squared_edt(blank, w, h);
    std::vector<float> samples;
    const std::vector<float> width = stroke_widths(to_bg2, to_blank2, ink, w, h, samples);
    if (samples.empty()) return res;
    std::nth_element(samples.begin(), samples.begin() + std::ptrdiff_t(samples.size() / 2), samples.end());
    const float median = samples[samples.size() / 2];
    res.stroke_width = median;
    res.samples = samples.size();
    // Pockets the closing shut reach at most its disc and a stroke from the background.
    res.pockets_opened = open_outside_pockets(bg, ink, to_bg2, float(0.5 * close_gaps + 1.0) + median, w, h);
    if (res.pockets_opened) to_bg2 = squared_edt(bg, w, h);
    // Over twice the median: merged strokes, not one stroke.
    const float cap = 1.5f * median;
    const float reach = cap + 1.0f;
    std::vector<char> near(n, 0);
    for (std::size_t i = 0; i < n; ++i) near[i] = to_bg2[i] <= (reach + 1) * (reach + 1);
    const std::vector<float> half = half_widths(width, cap, 0.5f * median, near, w, h);
    const std::vector<float> coverage_in = coverage;
    for (std::size_t i = 0; i < n; ++i)
        if (!bg_in[i] && bg[i]) coverage[i] = 0; // the pockets opened
    std::vector<float> out(coverage);
    std::vector<float> depth(n, 0.0f);
    tbb::parallel_for(0, h, [&](int y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            if (coverage[i] > 0 && near[i]) depth[i] = edge_depth(coverage, x, y, std::sqrt(to_bg2[i]), w, h);
        }
    });
    // The widths are measured on the ink as thresholded, which its anti-aliased fringe widens
    // on both sides alike: the fringe's mean depth on the outer edge (pixel centres half a
    // pixel deep as thresholded) is taken off each half-width.
    double fringe = 0;
    std::size_t edge = 0;
    for (std::size_t i = 0; i < n; ++i)
        if (to_bg2[i] == 1.0f && coverage[i] > 0) {
            fringe += 0.5 - double(depth[i]);
            ++edge;
        }
    const float shift = edge ? float(fringe / double(edge)) : 0.0f;
    for (std::size_t i = 0; i < n; ++i)
        if (coverage[i] > 0 && near[i])
            out[i] = std::min(coverage[i], std::clamp(depth[i] + shift - half[i] + 0.5f, 0.0f, 1.0f));
    // A part thinner than two strokes keeps a core of a quarter stroke each side of its
    // middle (all of it when thinner still): at least half a stroke thick, never cut away.
    const std::vector<float> pulled = out;
    for (const auto& [q, r] : thin_ridge(to_bg2, bg, reach, w, h)) {
        const float hq = half[q], m = std::min(0.5f * hq, r);
        if (r >= hq + 0.5f * hq) continue; // the pull leaves more than the core
        const int qx = int(q % std::size_t(w)), qy = int(q / std::size_t(w)), rr = int(std::ceil(m + 0.5f));
        for (int dy = -rr; dy <= rr; ++dy)
            for (int dx = -rr; dx <= rr; ++dx) {
                const int x = qx + dx, y = qy + dy;
                if (x < 0 || y < 0 || x >= w || y >= h) continue;
                const std::size_t i = std::size_t(y) * w + x;
                const float c =
                    std::min(coverage[i], std::clamp(m + 0.5f - std::hypot(float(dx), float(dy)), 0.0f, 1.0f));
                if (c > out[i]) {
                    res.thin_held += out[i] < 0.5f && c >= 0.5f;
                    out[i] = c;
                }
            }
    }
    res.corners_dropped = drop_stray_cores(out, pulled, median, w, h);
    for (std::size_t i = 0; i < n; ++i) res.pulled_px += coverage_in[i] - out[i];
    coverage = std::move(out);
    return res;
}

std::size_t give_back_enclosed_paper(std::vector<float>& coverage, const std::vector<float>& before,
                                     const std::vector<char>& bg, int w, int h) {
    const std::size_t n = std::size_t(w) * h;
    std::vector<char> under(n);
    for (std::size_t i = 0; i < n; ++i) under[i] = coverage[i] < 0.5f;
    std::vector<int> lab;
    std::vector<std::size_t> sizes;
    const int count = mask_components(under, w, h, true, lab, sizes);
    std::vector<char> outside(std::size_t(count), 0);
    for (std::size_t i = 0; i < n; ++i)
        if (lab[i] >= 0 && bg[i]) outside[std::size_t(lab[i])] = 1;
    std::size_t given = 0;
    for (std::size_t i = 0; i < n; ++i)
        if (lab[i] >= 0 && !outside[std::size_t(lab[i])] && before[i] > coverage[i]) {
            coverage[i] = before[i];
            ++given;
        }
    return given;
}

} // namespace cm
