#include "line_holes.h"
#include "pixel_flood.h"

#include <algorithm>
#include <set>
#include <utility>

namespace cm {

std::vector<char> nested_holes(const std::vector<int>& region, int count, const std::vector<char>& barrier,
                               const std::vector<char>& bg, int w, int h) {
    const std::size_t n = std::size_t(w) * h;
    // Strokes: 8-connected pieces of the barrier not taken by the background.
    std::vector<int> stroke(n, -1);
    int nstrokes = 0;
    for (std::size_t s = 0; s < n; ++s) {
        if (!barrier[s] || bg[s] || stroke[s] >= 0) continue;
        stroke[s] = nstrokes;
        grow_piece_8(
            int(s), w, h,
            [&](int q) {
                const std::size_t i = std::size_t(q);
                if (!barrier[i] || bg[i] || stroke[i] >= 0) return false;
                stroke[i] = nstrokes;
                return true;
            },
            [](int) {});
        ++nstrokes;
    }
    // What touches what (8-neighbours): strokes and the background, strokes and regions.
    constexpr int kFar = 1 << 29;
    std::vector<int> stroke_depth(std::size_t(nstrokes), kFar), region_depth(std::size_t(count), kFar);
    std::set<std::pair<int, int>> touch; // (stroke, region)
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            if (stroke[i] < 0) continue;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx < 0 || yy < 0 || xx >= w || yy >= h) {
                        stroke_depth[std::size_t(stroke[i])] = 0;
                        continue;
                    }
                    const std::size_t q = std::size_t(yy) * w + xx;
                    if (bg[q]) stroke_depth[std::size_t(stroke[i])] = 0;
                    else if (region[q] >= 0) touch.insert({stroke[i], region[q]});
                }
        }
    // Depths outwards in: a region lies one stroke deeper than the shallowest stroke it
    // touches, a stroke as deep as the shallowest region it touches.
    for (bool changed = true; changed;) {
        changed = false;
        for (const auto& [s, r] : touch) {
            int& ds = stroke_depth[std::size_t(s)];
            int& dr = region_depth[std::size_t(r)];
            if (ds + 1 < dr) {
                dr = ds + 1;
                changed = true;
            }
            if (dr < ds) {
                ds = dr;
                changed = true;
            }
        }
    }
    std::vector<char> hole(std::size_t(count), 0);
    for (int r = 0; r < count; ++r)
        hole[std::size_t(r)] = region_depth[std::size_t(r)] < kFar && region_depth[std::size_t(r)] % 2 == 0;
    return hole;
}

} // namespace cm
