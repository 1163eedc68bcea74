#include "thin_outline.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cm {

namespace {

// Strokes up to this wide by their ink (px) are placed from it.
constexpr float kThinWidth = 1.3f;
// Ink below the threshold outside the first object pixel taken into a crossing (px).
constexpr int kFringe = 2;
// The longest crossing of a single thin stroke (px, its fringe included).
constexpr int kLongest = 5;
// A crossing holding more ink than this many of the drawing's strokes runs over the outline
// and lines beside it run together (no valley between them): the outline is its outermost
// stroke, placed by one stroke's ink.
constexpr float kMerged = 2.0f;
// Blank pixels after a stroke whose coverage the crossing sets (pull_to_stroke_centre may
// have pulled them in by half a stroke measured too wide).
constexpr int kAfter = 2;

// Differences of ink under this are rounding, not ink (px): one step of a byte is 1/255 of
// full scale, more of the full ink.
constexpr float kTie = 1e-5f;
// Ink fractions within this of each other are the same ink: each is read from bytes, a
// pixel's colour to within half a step (0.002) on each channel, its fraction of the full ink
// (at least 0.3 from the paper for the faintest pencil) to within 0.007, differently in each
// ink colour. Comparisons of two pixels' ink (a valley against the stroke's peak) take
// near-equal as equal, so that a valley of exactly half the peak (the renderer's 1/3 beside
// 2/3, or 1/9 beside 2/9) is read alike in every ink.
constexpr float kInkStep = 0.01f;

// How far the pixel's centre lies past the half-ink point of its crossing, in ink (px): the
// ink `passed` before the pixel, half its own `a`, less half the stroke's `placed`. Summed
// before the half pixel of coverage is added (0.5 + passed + a / 2 - placed / 2 rounds
// 0.5 + a / 2 first, and gave a stroke on one pixel 0.5 less one float step in some inks,
// 0.5 in others: a whole row of pixels in or out by the colour), and within kTie of the
// point taken as on it.
float beyond_half_ink(float passed, float a, float placed) {
    const float off = passed + 0.5f * a - 0.5f * placed;
    return std::abs(off) < kTie ? 0.0f : off;
}

// Per pixel, the crossing that passes its stroke most squarely: its ink and the coverage it
// gives the pixel.
struct Best {
    std::vector<float> ink, cov;
};

// Where the outline stroke entered at k ends when another line runs into it from inside:
// `e` becomes the first valley of the ink after k, within kLongest (a pixel under half the
// stroke's peak by more than kInkStep, and no more than the next pixel's give or take it),
// and `shared` its ink. False when there is none, or the background lies within kAfter + 1
// beyond it (a thin part).
template <typename At>
bool first_stroke(int count, At at, const std::vector<char>& bg, const std::vector<float>& ink, int k, int& e,
                  float& shared) {
    float peak = ink[at(k)];
    for (int j = k + 1; j + 1 < count && j <= k + kLongest; ++j) {
        const float a = ink[at(j)];
        if (bg[at(j)] || a <= 0) return false; // the blank inside: a single stroke
        if (a < 0.5f * peak - kInkStep && a <= ink[at(j + 1)] + kInkStep) {
            for (int m = j + 1; m <= j + kAfter + 1; ++m)
                if (m >= count || bg[at(m)]) return false;
            e = j;
            shared = a;
            return true;
        }
        peak = std::max(peak, a);
    }
    return false;
}

// The crossings of one line of pixels (a row or a column, either way): `at(k)` is the index
// of its k-th pixel. A crossing enters from the background into the object at k and runs
// over ink (fraction `ink`) to the object's blank inside. `stroke`: one stroke's ink (px;
// infinite while it is being measured).
template <typename At>
void cross_line(int count, At at, const std::vector<char>& bg, const std::vector<float>& ink, float stroke, Best& best,
                std::vector<float>& widths) {
    for (int k = 1; k < count; ++k) {
        if (!bg[at(k - 1)] || bg[at(k)]) continue;
        int s = k;
        while (s > 0 && k - s < kFringe && bg[at(s - 1)] && ink[at(s - 1)] > 0) --s;
        int e = k;
        while (e < count && !bg[at(e)] && ink[at(e)] > 0 && e - s < kLongest) ++e;
        if (e == k || e >= count || bg[at(e)]) continue;
        // A single stroke between the background and the blank inside: no more ink after it.
        // Or the outline stroke run together with a line just inside it: it ends at the first
        // valley of the ink, whose ink is shared half and half.
        float shared = 0;
        if (!first_stroke(count, at, bg, ink, k, e, shared) && ink[at(e)] > 0) continue;
        float total = 0.5f * shared;
        for (int j = s; j < e; ++j) total += ink[at(j)];
        widths.push_back(total);
        const float placed = total > kMerged * stroke ? stroke : total; // the outermost stroke's
        float passed = 0;
        for (int j = s; j < std::min(count, e + kAfter); ++j) {
            const std::size_t i = at(j);
            if (j >= e && bg[i]) break;
            const float a = j < e ? ink[i] : j == e ? 0.5f * shared : 0.0f;
            // The ink up to the pixel's centre against half the stroke's (the pixel's side of
            // the half-ink point, px). At the half-ink point itself (a 1 px stroke on one pixel,
            // the outline through its middle) the pixel is half inside, exactly, in any ink.
            const float c = std::clamp(0.5f + beyond_half_ink(passed, a, placed), 0.0f, 1.0f);
            passed += a;
            if (total < best.ink[i]) {
                best.ink[i] = total;
                best.cov[i] = c;
            }
        }
    }
}

// Each pixel's ink fraction: its distance to the paper over the full ink's (the 95th
// percentile over the object's ink), 0 under half the threshold (the paper's own grain).
std::vector<float> ink_fraction(const std::vector<char>& bg, const std::vector<double>& dist, double t) {
    std::vector<double> strong;
    for (std::size_t i = 0; i < dist.size(); ++i)
        if (!bg[i] && dist[i] >= t) strong.push_back(dist[i]);
    std::vector<float> ink(dist.size(), 0.0f);
    if (strong.empty()) return ink;
    const auto q = strong.begin() + std::ptrdiff_t(0.95 * double(strong.size() - 1));
    std::nth_element(strong.begin(), q, strong.end());
    const double full = *q;
    for (std::size_t i = 0; i < dist.size(); ++i)
        if (dist[i] >= 0.5 * t) ink[i] = float(std::min(1.0, dist[i] / full));
    return ink;
}

} // namespace

void place_thin_outline(std::vector<float>& coverage, const std::vector<char>& bg, const std::vector<double>& dist,
                        double t, int w, int h, StrokeCentre& stroke) {
    const std::size_t n = std::size_t(w) * h;
    const std::vector<float> ink = ink_fraction(bg, dist, t);
    Best best;
    std::vector<float> widths;
    // Every row and column crossed both ways; the first time to measure the strokes.
    auto cross_all = [&](float one) {
        best = {std::vector<float>(n, std::numeric_limits<float>::infinity()), std::vector<float>(n, 0.0f)};
        for (int y = 0; y < h; ++y) {
            const std::size_t row = std::size_t(y) * w;
            cross_line(
                w, [&](int k) { return row + std::size_t(k); }, bg, ink, one, best, widths);
            cross_line(
                w, [&](int k) { return row + std::size_t(w - 1 - k); }, bg, ink, one, best, widths);
        }
        for (int x = 0; x < w; ++x) {
            cross_line(
                h, [&](int k) { return std::size_t(k) * w + x; }, bg, ink, one, best, widths);
            cross_line(
                h, [&](int k) { return std::size_t(h - 1 - k) * w + x; }, bg, ink, one, best, widths);
        }
    };
    cross_all(std::numeric_limits<float>::infinity());
    if (widths.empty()) return;
    const auto m = widths.begin() + std::ptrdiff_t(widths.size() / 2);
    std::nth_element(widths.begin(), m, widths.end());
    const float median = *m;
    const auto q = widths.begin() + std::ptrdiff_t(widths.size() / 4);
    std::nth_element(widths.begin(), q, m);
    stroke.ink_width = *q;
    if (stroke.ink_width > kThinWidth) return;
    // Bands of lines run together only where at least half the crossings are single strokes
    // (a wide stroke drawn with thin ones about it is not a band of thin ones).
    if (median <= kMerged * stroke.ink_width) cross_all(float(stroke.ink_width));
    for (std::size_t i = 0; i < n; ++i)
        if (best.ink[i] < std::numeric_limits<float>::infinity()) {
            coverage[i] = best.cov[i];
            ++stroke.ink_placed;
        }
}

} // namespace cm
