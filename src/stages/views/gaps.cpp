#include "gaps.h"

#include <algorithm>
#include <cmath>

#include "components.h"
#include "geometry/distance_transform.h"
#include "pixel_flood.h"

namespace cm {

namespace {

// The disc that bridges a break `gap` px wide: half the gap and one pixel more, so a break
// of that many pixels along a diagonal stroke (sqrt 2 farther apart) is bridged too.
double gap_radius(double gap) { return 0.5 * gap + 1.0; }

} // namespace

double default_close_gaps(int w, int h) { return std::max(3.0, 0.004 * double(std::max(w, h))); }

std::vector<char> close_ink(const std::vector<char>& ink, int w, int h, double gap) {
    if (gap <= 0) return ink;
    const double radius = gap_radius(gap);
    const float r2 = float(radius * radius) + 1e-4f;
    // The frame is padded by more than the radius, so the image border behaves as blank
    // paper; the transforms run on the part of it around the ink only. The part reaches
    // 2 radii + 3 px beyond the ink's box: a pixel within the dilation lies within a radius
    // of the box, so what lies beyond the part (blank, outside the dilation) is farther
    // from it than the erosion's reach, and the result is the same as over the whole frame.
    const int pad = int(std::ceil(radius)) + 1;
    const int pw = w + 2 * pad, ph = h + 2 * pad;
    int x0 = w, x1 = -1, y0 = h, y1 = -1;
    for (int y = 0; y < h; ++y) {
        const char* row = ink.data() + std::size_t(y) * w;
        const char* first = std::find_if(row, row + w, [](char c) { return c != 0; });
        if (first == row + w) continue;
        int last = w - 1;
        while (!row[last]) --last;
        x0 = std::min(x0, int(first - row));
        x1 = std::max(x1, last);
        y0 = std::min(y0, y);
        y1 = y;
    }
    std::vector<char> closed(ink);
    if (x1 < 0) return closed; // no ink: nothing to close
    const int margin = 2 * pad + 3;
    const int cx0 = std::max(0, x0 + pad - margin), cx1 = std::min(pw - 1, x1 + pad + margin);
    const int cy0 = std::max(0, y0 + pad - margin), cy1 = std::min(ph - 1, y1 + pad + margin);
    const int cw = cx1 - cx0 + 1, ch = cy1 - cy0 + 1;
    std::vector<char> seed(std::size_t(cw) * ch, 0);
    for (int y = 0; y < ch; ++y)
        for (int x = 0; x < cw; ++x) {
            const int ix = cx0 + x - pad, iy = cy0 + y - pad; // image pixel
            if (ix >= 0 && iy >= 0 && ix < w && iy < h) seed[std::size_t(y) * cw + x] = ink[std::size_t(iy) * w + ix];
        }
    // Dilation: within the radius of the ink (its distances let go before the next ones).
    {
        const std::vector<float> to_ink = squared_edt(seed, cw, ch);
        for (std::size_t i = 0; i < seed.size(); ++i) seed[i] = to_ink[i] > r2; // outside the dilation
    }
    // Erosion of the dilation, by one pixel less than the radius: a disc's tip is one pixel,
    // and on the grid the full radius would let it reach through a break in a thin stroke.
    // The barrier is so up to one pixel thicker than the ink; the caller gives that back.
    const float e2 = float((radius - 1.0) * (radius - 1.0)) + 1e-4f;
    const std::vector<float> to_outside = squared_edt(seed, cw, ch);
    for (int y = std::max(0, cy0 - pad); y <= std::min(h - 1, cy1 - pad); ++y)
        for (int x = std::max(0, cx0 - pad); x <= std::min(w - 1, cx1 - pad); ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            closed[i] = ink[i] || to_outside[std::size_t(y + pad - cy0) * cw + x + pad - cx0] > e2;
        }
    return closed;
}

} // namespace cm

namespace cm {

std::size_t remove_thin_spurs(std::vector<char>& bg, const std::vector<char>& ink, int w, int h, double gap) {
    if (gap <= 0) return 0;
    const double radius = 0.5 * gap + 0.5; // strokes up to about the gap wide
    const float r2 = float(radius * radius) + 1e-4f;
    const std::size_t n = std::size_t(w) * h;
    // Opening of the object: erode (farther than the radius from the background, the
    // image's outside counting as background), then dilate back.
    const int pad = int(std::ceil(radius)) + 1;
    const int pw = w + 2 * pad, ph = h + 2 * pad;
    std::vector<char> seed = padded(bg, w, h, pad, 1);
    {
        const std::vector<float> to_bg = squared_edt(seed, pw, ph);
        for (std::size_t i = 0; i < seed.size(); ++i) seed[i] = to_bg[i] > r2; // the eroded object
    }
    const std::vector<float> to_core = squared_edt(seed, pw, ph);
    std::vector<char> residue(n, 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            residue[i] = !bg[i] && to_core[std::size_t(y + pad) * pw + x + pad] > r2;
        }
    // Pieces (8-connected) larger than what the disc takes off a sharp corner (about 1.5 r^2).
    const std::size_t corner = std::size_t(std::ceil(1.5 * radius * radius));
    std::vector<char> seen(n, 0);
    std::vector<int> piece;
    std::size_t removed = 0;
    for (std::size_t s = 0; s < n; ++s) {
        if (!residue[s] || seen[s]) continue;
        piece.clear();
        seen[s] = 1;
        grow_piece_8(
            int(s), w, h,
            [&](int q) {
                if (!residue[std::size_t(q)] || seen[std::size_t(q)]) return false;
                seen[std::size_t(q)] = 1;
                return true;
            },
            [&](int p) { piece.push_back(p); });
        if (piece.size() <= corner) continue;
        for (int p : piece) bg[std::size_t(p)] = 1;
        removed += piece.size();
    }
    return removed;
}

namespace {

// Of the strokes along a slit, the share that has the object's paper behind it (nearer
// than the background) for the slit to be drawn between two parts: the strokes of doubled
// lines have the background behind the outer one, about half of them.
constexpr double kSlitBacked = 0.75;

} // namespace

std::size_t open_drawn_slits(std::vector<char>& bg, const std::vector<char>& ink, const std::vector<char>& closed,
                             int w, int h) {
    const std::size_t n = std::size_t(w) * h;
    std::vector<char> bridged(n);
    for (std::size_t i = 0; i < n; ++i) bridged[i] = !bg[i] && !ink[i] && closed[i];
    std::vector<int> lab;
    std::vector<std::size_t> sizes;
    const int count = mask_components(bridged, w, h, false, lab, sizes);
    if (count == 0) return 0;
    // Per piece of bridged paper: beside the background (8-connected), beside paper the
    // closing left open (4-connected: the border's flood would reach it through the piece).
    std::vector<char> beside_bg(std::size_t(count), 0), beside_open(std::size_t(count), 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            if (lab[i] < 0) continue;
            const std::size_t k = std::size_t(lab[i]);
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if ((dx == 0 && dy == 0) || xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                    const std::size_t j = std::size_t(yy) * w + xx;
                    beside_bg[k] = beside_bg[k] || bg[j];
                    if (dx == 0 || dy == 0) beside_open[k] = beside_open[k] || (!bg[j] && !ink[j] && !closed[j]);
                }
        }
    std::vector<char> slit(std::size_t(count), 0);
    bool any = false;
    for (std::size_t k = 0; k < slit.size(); ++k) {
        slit[k] = beside_bg[k] && !beside_open[k];
        any = any || slit[k];
    }
    if (!any) return 0;
    // What lies behind the strokes along each slit: the object's paper (other than the
    // slits) or the background, whichever is nearer.
    std::vector<char> paper(n);
    for (std::size_t i = 0; i < n; ++i) paper[i] = !bg[i] && !ink[i] && !(lab[i] >= 0 && slit[std::size_t(lab[i])]);
    const std::vector<float> to_paper2 = squared_edt(paper, w, h);
    const std::vector<float> to_bg2 = squared_edt(bg, w, h);
    std::vector<std::size_t> along(slit.size(), 0), backed(slit.size(), 0);
    std::vector<int> seen(n, -1); // the last piece each stroke pixel was counted for
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            if (lab[i] < 0 || !slit[std::size_t(lab[i])]) continue;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                    const std::size_t j = std::size_t(yy) * w + xx;
                    if (!ink[j] || seen[j] == lab[i]) continue;
                    seen[j] = lab[i];
                    ++along[std::size_t(lab[i])];
                    backed[std::size_t(lab[i])] += to_paper2[j] < to_bg2[j];
                }
        }
    std::size_t opened = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (lab[i] < 0) continue;
        const std::size_t k = std::size_t(lab[i]);
        if (!slit[k] || along[k] == 0 || double(backed[k]) < kSlitBacked * double(along[k])) continue;
        bg[i] = 1;
        ++opened;
    }
    return opened;
}

} // namespace cm
