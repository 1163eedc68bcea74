#include "silhouette_holes.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "components.h"
#include "line_holes.h"

namespace cm {

namespace {

// Calls f(q) for each 8-neighbour q (row-major index) of (x, y) within the w x h image.
template <typename F>
void neighbours8(int x, int y, int w, int h, F&& f) {
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const int xx = x + dx, yy = y + dy;
            if ((dx || dy) && xx >= 0 && yy >= 0 && xx < w && yy < h) f(std::size_t(yy) * w + xx);
        }
}

// The pieces of object (8-connected, neither outside nor a blank region): labels and sizes.
int object_pieces(const RegionEvidence& e, std::vector<int>& lab, std::vector<std::size_t>& sizes) {
    const std::size_t n = std::size_t(e.w) * e.h;
    std::vector<char> object(n);
    for (std::size_t i = 0; i < n; ++i) object[i] = !(*e.outside)[i] && (*e.region)[i] < 0;
    return mask_components(object, e.w, e.h, true, lab, sizes);
}

// Multi-source breadth-first distances (8-connected steps) from the pixels where `dist` is 0
// through the pixels `open` allows, up to `limit`; unreached pixels keep `dist` as given.
template <typename Open>
void bfs8(std::vector<int>& dist, int w, int h, int limit, Open&& open) {
    std::vector<int> front, next;
    for (std::size_t i = 0; i < dist.size(); ++i)
        if (dist[i] == 0) front.push_back(int(i));
    for (int d = 1; d <= limit && !front.empty(); ++d) {
        next.clear();
        for (const int p : front)
            neighbours8(p % w, p / w, w, h, [&](std::size_t q) {
                if (dist[q] <= d || !open(int(q))) return;
                dist[q] = d;
                next.push_back(int(q));
            });
        front.swap(next);
    }
}

// Each region's centre and area, the starting record of its judgement.
std::vector<EnclosedRegion> region_records(const RegionEvidence& e) {
    std::vector<EnclosedRegion> out(std::size_t(e.count));
    std::vector<double> sx(out.size(), 0), sy(out.size(), 0);
    const std::vector<int>& region = *e.region;
    for (int y = 0; y < e.h; ++y)
        for (int x = 0; x < e.w; ++x) {
            const int r = region[std::size_t(y) * e.w + x];
            if (r < 0) continue;
            sx[std::size_t(r)] += x;
            sy[std::size_t(r)] += y;
        }
    for (std::size_t r = 0; r < out.size(); ++r) {
        out[r].area = (*e.sizes)[r];
        const double a = double(std::max<std::size_t>(1, out[r].area));
        out[r].x = int(std::lround(sx[r] / a));
        out[r].y = int(std::lround(sy[r] / a));
    }
    return out;
}

// The regions that come within `reach` steps of the outside through object pixels: with
// `share` 0 any pixel of the rim will do, else at least that share of the rim's pixels.
std::vector<char> near_outside(const RegionEvidence& e, int reach, double share) {
    const std::size_t n = std::size_t(e.w) * e.h;
    constexpr int kFar = 1 << 29;
    std::vector<int> dist(n, kFar);
    for (std::size_t i = 0; i < n; ++i)
        if ((*e.outside)[i]) dist[i] = 0;
    // Steps through object pixels (not outside, no blank region); the region pixel beside
    // the last of them is one step further.
    bfs8(dist, e.w, e.h, reach, [&](int q) { return (*e.region)[std::size_t(q)] < 0; });
    // A rim pixel of a region is near when an object pixel beside it is within reach.
    std::vector<std::size_t> rim(std::size_t(e.count), 0), close(std::size_t(e.count), 0);
    for (int y = 0; y < e.h; ++y)
        for (int x = 0; x < e.w; ++x) {
            const int r = (*e.region)[std::size_t(y) * e.w + x];
            if (r < 0) continue;
            bool on_rim = false, near = false;
            neighbours8(x, y, e.w, e.h, [&](std::size_t q) {
                if ((*e.region)[q] == r) return;
                on_rim = true;
                near = near || dist[q] < reach;
            });
            rim[std::size_t(r)] += on_rim;
            close[std::size_t(r)] += near;
        }
    std::vector<char> near(std::size_t(e.count), 0);
    for (std::size_t r = 0; r < near.size(); ++r) near[r] = close[r] > 0 && double(close[r]) >= share * double(rim[r]);
    return near;
}

// The regions that hold a mark of their own: a piece of object (8-connected, at least
// `min_mark` px) that touches no outside pixel, only blank regions.
std::vector<char> holding_marks(const RegionEvidence& e, std::size_t min_mark) {
    std::vector<int> lab;
    std::vector<std::size_t> sizes;
    const int count = object_pieces(e, lab, sizes);
    std::vector<char> touches_outside(std::size_t(count), 0);
    std::vector<std::vector<int>> beside(static_cast<std::size_t>(count));
    for (int y = 0; y < e.h; ++y)
        for (int x = 0; x < e.w; ++x) {
            const int c = lab[std::size_t(y) * e.w + x];
            if (c < 0) continue;
            if (x == 0 || y == 0 || x + 1 == e.w || y + 1 == e.h) touches_outside[std::size_t(c)] = 1;
            neighbours8(x, y, e.w, e.h, [&](std::size_t q) {
                if ((*e.outside)[q]) touches_outside[std::size_t(c)] = 1;
                const int r = (*e.region)[q];
                auto& b = beside[std::size_t(c)];
                if (r >= 0 && std::find(b.begin(), b.end(), r) == b.end()) b.push_back(r);
            });
        }
    std::vector<char> holds(std::size_t(e.count), 0);
    for (int c = 0; c < count; ++c) {
        if (touches_outside[std::size_t(c)] || sizes[std::size_t(c)] < min_mark) continue;
        // An island beside one region lies inside it; beside several it is a part between
        // them (a bar across a window), which says nothing of either.
        if (beside[std::size_t(c)].size() == 1) holds[std::size_t(beside[std::size_t(c)][0])] = 1;
    }
    return holds;
}

// The regions that lie within separate marks: every piece of object (8-connected, no blank
// region) they touch is under 5 % of the largest piece, the size below which
// keep_components drops a mark (the gaps between a label's letters, bridged by gap closing).
std::vector<char> inside_marks(const RegionEvidence& e) {
    std::vector<int> lab;
    std::vector<std::size_t> sizes;
    const int count = object_pieces(e, lab, sizes);
    std::vector<char> out(std::size_t(e.count), 1);
    if (count == 0) return out;
    const double largest = double(*std::max_element(sizes.begin(), sizes.end()));
    for (int y = 0; y < e.h; ++y)
        for (int x = 0; x < e.w; ++x) {
            const int c = lab[std::size_t(y) * e.w + x];
            if (c < 0 || double(sizes[std::size_t(c)]) < 0.05 * largest) continue;
            neighbours8(x, y, e.w, e.h, [&](std::size_t q) {
                if ((*e.region)[q] >= 0) out[std::size_t((*e.region)[q])] = 0;
            });
        }
    return out;
}

// The regions most of whose rim (the object pixels beside them) is ink joined (8-connected)
// to ink beside the outside: the outline's own network of lines.
std::vector<char> bounded_by_outline_ink(const RegionEvidence& e) {
    const std::size_t n = std::size_t(e.w) * e.h;
    std::vector<int> lab;
    std::vector<std::size_t> sizes;
    const int count = mask_components(*e.ink, e.w, e.h, true, lab, sizes);
    std::vector<char> network(std::size_t(count), 0);
    auto each_neighbour = [&](int x, int y, auto&& f) { neighbours8(x, y, e.w, e.h, f); };
    for (int y = 0; y < e.h; ++y)
        for (int x = 0; x < e.w; ++x) {
            const int c = lab[std::size_t(y) * e.w + x];
            if (c >= 0 && !network[std::size_t(c)])
                each_neighbour(x, y, [&](std::size_t q) { network[std::size_t(c)] |= (*e.outside)[q]; });
        }
    std::vector<std::size_t> rim(std::size_t(e.count), 0), inked(std::size_t(e.count), 0);
    std::vector<char> counted(n, 0);
    for (int y = 0; y < e.h; ++y)
        for (int x = 0; x < e.w; ++x) {
            const int r = (*e.region)[std::size_t(y) * e.w + x];
            if (r < 0) continue;
            each_neighbour(x, y, [&](std::size_t q) {
                if ((*e.region)[q] >= 0 || (*e.outside)[q] || counted[q] == char(1 + r % 100)) return;
                counted[q] = char(1 + r % 100);
                ++rim[std::size_t(r)];
                // The rim pixel or one beside it: thin lines reach the region by their fringe.
                bool on_line = false;
                each_neighbour(int(q % std::size_t(e.w)), int(q / std::size_t(e.w)), [&](std::size_t k) {
                    on_line = on_line || (lab[k] >= 0 && network[std::size_t(lab[k])]);
                });
                if (on_line || (lab[q] >= 0 && network[std::size_t(lab[q])])) ++inked[std::size_t(r)];
            });
        }
    std::vector<char> out(std::size_t(e.count), 0);
    for (std::size_t r = 0; r < out.size(); ++r) out[r] = rim[r] > 0 && 2 * inked[r] >= rim[r];
    return out;
}

// Mean colour distance of each region.
std::vector<double> region_tints(const RegionEvidence& e) {
    std::vector<double> sum(std::size_t(e.count), 0);
    const std::size_t n = std::size_t(e.w) * e.h;
    for (std::size_t i = 0; i < n; ++i)
        if ((*e.region)[i] >= 0) sum[std::size_t((*e.region)[i])] += (*e.distance)[i];
    for (std::size_t r = 0; r < sum.size(); ++r) sum[r] /= double(std::max<std::size_t>(1, (*e.sizes)[r]));
    return sum;
}

} // namespace

double outline_width(const RegionEvidence& e) {
    const std::size_t n = std::size_t(e.w) * e.h;
    double paper = 0;
    std::size_t np = 0;
    for (std::size_t i = 0; i < n; i += 7)
        if ((*e.outside)[i]) {
            paper += (*e.luminance)[i];
            ++np;
        }
    paper = np ? paper / double(np) : 1.0;
    const float dark = float(0.5 * paper);
    std::vector<int> runs;
    std::size_t crossings = 0;
    // An outline is a run of dark pixels that ends on a clearly lighter one (the fill), no
    // longer than 2 % of the larger side: a dark fill reaching deep is no outline.
    const int longest = std::max(3, int(0.02 * std::max(e.w, e.h)));
    // A crossing from the outside into the object at (x, y), walking by (dx, dy).
    auto walk = [&](int x, int y, int dx, int dy) {
        ++crossings;
        int run = 0;
        float darkest = 1;
        while (x >= 0 && y >= 0 && x < e.w && y < e.h && run <= longest) {
            const std::size_t i = std::size_t(y) * e.w + x;
            const float l = (*e.luminance)[i];
            if ((*e.outside)[i]) return;
            if (l >= dark && run < 2 && darkest == 1 && l < float(paper) - 0.1f) {
                ++run; // the stroke's anti-aliased fringe, lighter than its core
                x += dx;
                y += dy;
                continue;
            }
            if (l >= dark) {
                if (darkest < 1 && l >= darkest + 0.15f) runs.push_back(run);
                return;
            }
            darkest = std::min(darkest, l);
            ++run;
            x += dx;
            y += dy;
        }
    };
    for (int y = 0; y < e.h; ++y)
        for (int x = 1; x < e.w; ++x) {
            const std::size_t i = std::size_t(y) * e.w + x;
            if ((*e.outside)[i - 1] && !(*e.outside)[i]) walk(x, y, 1, 0);
            if (!(*e.outside)[i - 1] && (*e.outside)[i]) walk(x - 1, y, -1, 0);
        }
    for (int y = 1; y < e.h; ++y)
        for (int x = 0; x < e.w; ++x) {
            const std::size_t i = std::size_t(y) * e.w + x, up = i - std::size_t(e.w);
            if ((*e.outside)[up] && !(*e.outside)[i]) walk(x, y, 0, 1);
            if (!(*e.outside)[up] && (*e.outside)[i]) walk(x, y - 1, 0, -1);
        }
    if (runs.empty() || 2 * runs.size() < crossings) return 0;
    std::nth_element(runs.begin(), runs.begin() + long(runs.size() / 2), runs.end());
    return double(runs[runs.size() / 2]);
}

std::vector<int> region_depths(const RegionEvidence& e) {
    const std::size_t n = std::size_t(e.w) * e.h;
    constexpr int kFar = 1 << 29;
    std::vector<int> dist(n, 0);
    for (std::size_t i = 0; i < n; ++i) dist[i] = (*e.region)[i] >= 0 ? kFar : 0;
    // Every other region's pixels are sources too: a region's depth is to its own rim.
    const std::vector<int>& region = *e.region;
    std::vector<int> front;
    for (int y = 0; y < e.h; ++y)
        for (int x = 0; x < e.w; ++x) {
            const std::size_t i = std::size_t(y) * e.w + x;
            if (region[i] < 0) continue;
            bool rim = x == 0 || y == 0 || x + 1 == e.w || y + 1 == e.h;
            for (int dy = -1; dy <= 1 && !rim; ++dy)
                for (int dx = -1; dx <= 1 && !rim; ++dx) rim = region[std::size_t(y + dy) * e.w + x + dx] != region[i];
            if (rim) dist[i] = 1;
        }
    for (std::size_t i = 0; i < n; ++i)
        if (dist[i] == 1) dist[i] = 0; // the rim seeds the search at depth 1 (added below)
    bfs8(dist, e.w, e.h, e.w + e.h, [&](int q) { return region[std::size_t(q)] >= 0; });
    std::vector<int> deepest(std::size_t(e.count), 0);
    for (std::size_t i = 0; i < n; ++i)
        if (region[i] >= 0) deepest[std::size_t(region[i])] = std::max(deepest[std::size_t(region[i])], dist[i] + 1);
    return deepest;
}

std::vector<EnclosedRegion> judge_filled_regions(const RegionEvidence& e, std::size_t min_area) {
    std::vector<EnclosedRegion> out = region_records(e);
    if (out.empty()) return out;
    const double stroke = outline_width(e);
    const int sliver = std::max(2, int(std::lround(stroke)));
    const std::vector<int> depth = region_depths(e);
    // A region meeting an ink outline that also bounds the outside is a part (an eye on the
    // edge of a head, paper between hatch strokes running into the outline). Without an
    // outline (a flat fill, a mask) the fill bounds a region: it is a part only when a long
    // stretch of its rim lies on the outside, not where a hand touching the hip closes the
    // gap between an arm and the body with a bridge a pixel thick.
    const std::vector<char> edge = near_outside(e, int(std::lround(stroke)) + 2, stroke > 0 ? 0.0 : 0.15);
    const std::vector<char> marks = holding_marks(e, min_area);
    const std::vector<double> tint = region_tints(e);
    const std::vector<char> in_mark = inside_marks(e);
    const std::vector<char> inked = bounded_by_outline_ink(e);
    std::size_t body = 0;
    for (std::size_t i = 0; i < e.outside->size(); ++i) body += !(*e.outside)[i];
    // Hatching leaves many slivers of paper between its strokes; a few narrow regions in a
    // drawing without hatching are gaps between close parts (an ear beside a head).
    std::size_t slivers = 0;
    for (std::size_t r = 0; r < out.size(); ++r)
        slivers += out[r].area >= min_area && depth[r] <= sliver && !in_mark[r];
    const bool hatched = slivers >= 20;
    for (std::size_t r = 0; r < out.size(); ++r) {
        EnclosedRegion& g = out[r];
        if (g.area < min_area) g.why = "a gap between strokes";
        else if (in_mark[r]) {
            g.hole = true; // a small separate mark (a letter) keeps its counters
            g.why = "inside a separate mark";
        } else if (depth[r] <= sliver && hatched) g.why = "paper between strokes";
        else if (depth[r] <= sliver) {
            g.hole = true;
            g.why = "a narrow gap between parts";
        } else if (tint[r] > 0.5 * e.threshold) g.why = "tinted, not the paper";
        else if (edge[r]) g.why = "outlined with the body";
        else if (marks[r]) g.why = "holds a mark of its own";
        else if (inked[r]) g.why = "bounded by the outline's lines";
        else if (double(g.area) < 0.0025 * double(body)) g.why = "too small for an opening";
        else {
            g.hole = true;
            g.why = "the background through the fill";
        }
    }
    return out;
}

std::vector<EnclosedRegion> judge_line_regions(const RegionEvidence& e, const std::vector<char>& nested,
                                               std::size_t min_area, bool open_candidates) {
    std::vector<EnclosedRegion> out = region_records(e);
    if (out.empty()) return out;
    const std::vector<int> depth = region_depths(e);
    std::size_t body = 0;
    for (const char o : *e.outside) body += !o;
    for (std::size_t r = 0; r < out.size(); ++r) {
        EnclosedRegion& g = out[r];
        const bool inside = nested[r] == kNestedInside;
        if (g.area < min_area) g.why = inside ? "the inside" : "a gap between strokes";
        else if (depth[r] <= 2) g.why = inside ? "the inside" : "paper between strokes";
        else if (!open_candidates && double(g.area) < 0.0025 * double(body))
            g.why = inside ? "the inside" : "too small for an opening";
        else if (inside) {
            // Seen from one side, a through-opening may lie within one part's outline (the
            // camel's hind legs from behind, with the tail hanging between them): the view
            // from the other side, which sees it between parts, is the evidence.
            g.why = "the inside";
            g.witness = !open_candidates;
        } else {
            const bool between = nested[r] == kBetweenParts;
            g.candidate = true;
            g.between_parts = between;
            g.hole = open_candidates;
            g.why = open_candidates ? "line art, holes: keep"
                    : between       ? "line art, a gap between parts: opened if the opposite view shows it"
                                    : "line art: detail unless another view shows it";
        }
    }
    return out;
}

void open_regions_at(std::vector<EnclosedRegion>& regions, const std::vector<int>& lab, int w, int h, int ox, int oy,
                     const std::vector<std::pair<int, int>>& at) {
    for (const auto& [x, y] : at) {
        const int lx = x - ox, ly = y - oy;
        if (lx < 0 || ly < 0 || lx >= w || ly >= h) continue;
        const int r = lab[std::size_t(ly) * w + lx];
        if (r < 0) continue;
        regions[std::size_t(r)].hole = true;
        regions[std::size_t(r)].why = "line art, shown by the opposite view";
    }
}

std::vector<EnclosedRegion> judge_all_regions(const RegionEvidence& e, bool hole, const std::string& why) {
    std::vector<EnclosedRegion> out = region_records(e);
    for (EnclosedRegion& g : out) {
        g.hole = hole;
        g.why = why;
    }
    return out;
}

std::string describe_regions(const std::vector<EnclosedRegion>& regions) {
    std::string opened;
    std::map<std::string, std::size_t> parts;
    int n_open = 0;
    for (const EnclosedRegion& g : regions) {
        if (g.hole) {
            if (n_open < 8)
                opened += std::string(n_open ? ", " : "") + std::to_string(g.area) + " px at (" + std::to_string(g.x) +
                          ", " + std::to_string(g.y) + ")";
            ++n_open;
        } else if (g.area >= 9) { // smaller: gaps between strokes, not worth a word
            ++parts[g.why];
        }
    }
    if (n_open == 0 && parts.empty()) return "";
    std::string s = std::to_string(n_open) + " hole(s)";
    if (n_open) s += ": " + opened + (n_open > 8 ? ", ..." : "");
    for (const auto& [why, k] : parts) s += "; " + std::to_string(k) + " region(s) filled: " + why;
    return s;
}

} // namespace cm
