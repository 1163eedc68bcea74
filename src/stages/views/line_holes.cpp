#include "line_holes.h"
#include "pixel_flood.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

namespace cm {

namespace {

// Calls f(q) for each 8-neighbour q (row-major index) of pixel p within the w x h image.
template <typename F>
void each8(int p, int w, int h, F&& f) {
    const int x = p % w, y = p / w;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const int xx = x + dx, yy = y + dy;
            if ((dx || dy) && xx >= 0 && yy >= 0 && xx < w && yy < h) f(yy * w + xx);
        }
}

// Steps (8-connected) from the pixels in `front` through the strokes (barrier, not
// background), up to `limit`: `dist` gets each reached stroke pixel's count (kept where
// already smaller).
void steps_through_strokes(std::vector<int> front, std::vector<int>& dist, const std::vector<char>& barrier,
                           const std::vector<char>& bg, int w, int h, int limit) {
    std::vector<int> next;
    for (int d = 1; d <= limit && !front.empty(); ++d) {
        next.clear();
        for (const int p : front)
            each8(p, w, h, [&](int q) {
                const std::size_t i = std::size_t(q);
                if (!barrier[i] || bg[i] || dist[i] <= d) return;
                dist[i] = d;
                next.push_back(q);
            });
        front.swap(next);
    }
}

// The strokes' mean width: twice their area over the length of their edges.
double stroke_width(const std::vector<char>& barrier, const std::vector<char>& bg, int w, int h) {
    std::size_t area = 0, edge = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            if (!barrier[i] || bg[i]) continue;
            ++area;
            const bool inner = x > 0 && y > 0 && x + 1 < w && y + 1 < h && barrier[i - 1] && barrier[i + 1] &&
                               barrier[i - std::size_t(w)] && barrier[i + std::size_t(w)];
            edge += !inner;
        }
    return edge ? 2.0 * double(area) / double(edge) : 0.0;
}

} // namespace

RegionLinks link_regions(const std::vector<int>& region, int count, const std::vector<char>& barrier,
                         const std::vector<char>& bg, int w, int h) {
    const std::size_t n = std::size_t(w) * h;
    constexpr int kOutside = -2, kNone = -1;
    // Each stroke pixel takes the label of the nearest region or of the outside: a
    // breadth-first growth from both through the strokes, 8-connected.
    std::vector<int> owner(n, kNone), front, next;
    for (std::size_t i = 0; i < n; ++i) {
        if (bg[i]) owner[i] = kOutside;
        else if (region[i] >= 0) owner[i] = region[i];
        if (owner[i] != kNone) front.push_back(int(i));
    }
    while (!front.empty()) {
        next.clear();
        for (const int p : front)
            each8(p, w, h, [&](int q) {
                if (owner[std::size_t(q)] != kNone || !barrier[std::size_t(q)]) return;
                owner[std::size_t(q)] = owner[std::size_t(p)];
                next.push_back(q);
            });
        front.swap(next);
    }
    RegionLinks links;
    links.outside.assign(std::size_t(count), 0);
    links.beside.resize(std::size_t(count));
    // Where two owners meet inside a stroke: each stroke pixel counts once towards each
    // other owner among its neighbours.
    std::vector<int> met;
    for (std::size_t i = 0; i < n; ++i) {
        if (!barrier[i] || bg[i] || owner[i] < 0) continue;
        const int a = owner[i];
        met.clear();
        each8(int(i), w, h, [&](int q) {
            const int b = owner[std::size_t(q)];
            if (b != kNone && b != a && std::find(met.begin(), met.end(), b) == met.end()) met.push_back(b);
        });
        for (const int b : met) {
            if (b == kOutside) {
                ++links.outside[std::size_t(a)];
                continue;
            }
            auto& list = links.beside[std::size_t(a)];
            auto it = std::find_if(list.begin(), list.end(), [&](const auto& c) { return c.first == b; });
            if (it == list.end()) list.emplace_back(b, 1);
            else ++it->second;
        }
    }
    return links;
}

namespace {

// Whether each listed region comes to the outside through strokes alone: some stroke pixel
// within `limit` steps of both through strokes (where two parts touch or nearly touch, the
// joined strokes are all that lies between the gap above and the outside below).
std::vector<char> touch_outside(const std::vector<int>& region, const std::vector<int>& which,
                                const std::vector<char>& barrier, const std::vector<char>& bg, int w, int h,
                                int limit) {
    const std::size_t n = std::size_t(w) * h;
    constexpr int kFar = 1 << 29;
    std::vector<int> from_outside(n, kFar), seeds;
    for (std::size_t i = 0; i < n; ++i)
        if (bg[i]) seeds.push_back(int(i));
    steps_through_strokes(seeds, from_outside, barrier, bg, w, h, limit);
    std::vector<std::vector<int>> pixels(which.size());
    std::vector<int> slot(n ? std::size_t(*std::max_element(region.begin(), region.end()) + 1) : 0, -1);
    for (std::size_t k = 0; k < which.size(); ++k) slot[std::size_t(which[k])] = int(k);
    for (std::size_t i = 0; i < n; ++i)
        if (region[i] >= 0 && slot[std::size_t(region[i])] >= 0)
            pixels[std::size_t(slot[std::size_t(region[i])])].push_back(int(i));
    std::vector<char> touches(which.size(), 0);
    for (std::size_t k = 0; k < which.size(); ++k) {
        std::vector<int> dist(n, kFar);
        steps_through_strokes(pixels[k], dist, barrier, bg, w, h, limit);
        for (std::size_t i = 0; i < n && !touches[k]; ++i) touches[k] = dist[i] + from_outside[i] <= limit;
    }
    return touches;
}

// The gaps between parts (see nested_holes): regions behind one stroke, at least 0.25 % of
// the drawing (smaller ones are cells between crossing lines of detail, and no opening that
// small would survive the hull's resolution), whose strokes face the outside along at most a
// tenth of their length (see link_regions), and which either come to the outside through
// strokes alone within four strokes' width and 4 px (where two parts touch or nearly touch:
// the hand at the hip) or lie between two or more regions of some size (a twentieth of their
// own area, 9 px at least: the paper where two strokes cross is no part), as between a
// camel's legs closed by the belly above and the crossing knees below. The sizes compared
// are to the strokes' centre lines (a region's blank area and half a stroke along its rim),
// as the drawing means them: wide strokes take the same width from every region's edge,
// and a narrow part (a leg seen through the gap) would lose most of its area to them. A closed loop of
// detail lies within one region, which keeps it from the outside even when a line joins it
// to the outline; the inside of a part faces the outside along its outline.
void mark_gaps_between_parts(const std::vector<int>& region, int count, const std::vector<char>& barrier,
                             const std::vector<char>& bg, int w, int h, const std::vector<int>& depth,
                             std::vector<char>& kind) {
    std::vector<std::size_t> area(std::size_t(count), 0);
    for (const int r : region)
        if (r >= 0) ++area[std::size_t(r)];
    std::size_t body = 0; // the drawing's area: what the outside does not reach
    for (const char b : bg) body += !b;
    const RegionLinks links = link_regions(region, count, barrier, bg, w, h);
    const double stroke = stroke_width(barrier, bg, w, h);
    std::vector<std::size_t> rims(std::size_t(count), 0); // each region's rim: outside and beside others
    std::vector<double> centred(std::size_t(count), 0.0); // the area to the strokes' centre lines
    for (std::size_t r = 0; r < std::size_t(count); ++r) {
        rims[r] = links.outside[r];
        for (const auto& [b, length] : links.beside[r]) rims[r] += length;
        centred[r] = double(area[r]) + 0.5 * stroke * double(rims[r]);
    }
    std::vector<int> unsure; // bounded so, beside one part: do they come to the outside?
    for (std::size_t r = 0; r < std::size_t(count); ++r) {
        if (depth[r] != 1 || 400 * area[r] < body) continue;
        const double least = std::max(9.0, centred[r] / 20);
        int parts = 0;
        for (const auto& link : links.beside[r]) parts += centred[std::size_t(link.first)] >= least;
        const std::size_t rim = rims[r];
        if (rim == 0 || 10 * links.outside[r] > rim) continue;
        if (links.outside[r] > 0 || parts >= 2) kind[r] = kBetweenParts;
        else unsure.push_back(int(r));
    }
    if (unsure.empty()) return;
    const int limit = int(std::lround(4 * stroke)) + 4;
    const std::vector<char> touches = touch_outside(region, unsure, barrier, bg, w, h, limit);
    for (std::size_t k = 0; k < unsure.size(); ++k)
        if (touches[k]) kind[std::size_t(unsure[k])] = kBetweenParts;
}

} // namespace

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
    std::vector<char> kind(std::size_t(count), kNestedInside);
    for (int r = 0; r < count; ++r)
        if (region_depth[std::size_t(r)] < kFar && region_depth[std::size_t(r)] % 2 == 0)
            kind[std::size_t(r)] = kNestedHole;
    mark_gaps_between_parts(region, count, barrier, bg, w, h, region_depth, kind);
    return kind;
}

} // namespace cm
