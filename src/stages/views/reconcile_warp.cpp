// The bend of a reconciled view (reconcile.h): where other drawings' lines of sight must pass
// through a view that cuts them, its outline is moved out by a smooth, low-frequency warp
// (smooth_warp.h), and its silhouette and drawing are resampled through it, so that the
// model keeps what every drawing shows without steps on its outline.
#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include <tbb/parallel_for.h>

#include "geometry/distance_transform.h"
#include "reconcile_state.h"
#include "smooth_warp.h"

namespace cm::reconcile_detail {

namespace {

// The centre of the inside pixel nearest to pixel (x, y), searched within r pixels.
Vec2d nearest_inside(const std::vector<char>& in, int w, int h, int x, int y, int r) {
    Vec2d best{x + 0.5, y + 0.5};
    long best_d = -1;
    for (int j = std::max(0, y - r); j <= std::min(h - 1, y + r); ++j)
        for (int i = std::max(0, x - r); i <= std::min(w - 1, x + r); ++i) {
            if (!in[std::size_t(j) * std::size_t(w) + std::size_t(i)]) continue;
            const long d = long(i - x) * (i - x) + long(j - y) * (j - y);
            if (best_d < 0 || d < best_d) best_d = d, best = {i + 0.5, j + 0.5};
        }
    return best;
}

// The drawing's colour at continuous pixel coordinates, bilinear, clamped to the canvas.
std::array<float, 4> colour_at(const Image& img, int w, int h, double x, double y) {
    const double fx = std::clamp(x - 0.5, 0.0, w - 1.0), fy = std::clamp(y - 0.5, 0.0, h - 1.0);
    const int i = std::min(int(fx), w - 2 < 0 ? 0 : w - 2), j = std::min(int(fy), h - 2 < 0 ? 0 : h - 2);
    const int i1 = std::min(i + 1, w - 1), j1 = std::min(j + 1, h - 1);
    const float ax = float(fx - i), ay = float(fy - j);
    const auto a = img.rgba(std::size_t(j) * w + i), b = img.rgba(std::size_t(j) * w + i1);
    const auto c = img.rgba(std::size_t(j1) * w + i), d = img.rgba(std::size_t(j1) * w + i1);
    std::array<float, 4> out;
    for (std::size_t k = 0; k < 4; ++k)
        out[k] = (1 - ay) * ((1 - ax) * a[k] + ax * b[k]) + ay * ((1 - ax) * c[k] + ax * d[k]);
    return out;
}

// A pixel the bend must cover: where it is, the way out of the silhouette to it (a unit
// vector from the nearest inside pixel) and how far.
struct NeedPixel {
    int x = 0, y = 0;
    Vec2d dir{0, 0};
    double dist = 0;
};

Vec2d clamp_length(Vec2d v, double cap) {
    const double n = std::hypot(v.x, v.y);
    return n > cap ? Vec2d{v.x * cap / n, v.y * cap / n} : v;
}

// How far pixel p lies beyond the silhouette along -dir, up to the cap; 0 when not within it.
double depth_along(const Coverage& cov, const NeedPixel& p, const Vec2d& dir, double cap) {
    for (double t = 0.5; t <= cap; t += 0.5)
        if (sample(cov, p.x + 0.5 - t * dir.x, p.y + 0.5 - t * dir.y) >= 0.5f) return t;
    return 0.0;
}

// The pixels to cover, each with its way out: from the nearest inside pixel, unless a
// neighbour already found goes the opposite way (a gap between two parts, or a band across
// one, whose two sides are equally near): then the neighbour's way, so that a gap closes
// from one side and the field need not pull apart within a pixel.
std::vector<NeedPixel> need_pixels(const std::vector<char>& in, const std::vector<char>& need, const Coverage& cov,
                                   int W, int H, double cap) {
    const std::vector<float> to_in = squared_edt(in, W, H);
    std::vector<NeedPixel> needs;
    std::vector<int> at(in.size(), -1);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::size_t i = std::size_t(y) * W + x;
            if (!need[i] || !(to_in[i] < kEdtFar)) continue;
            const double d = std::sqrt(double(to_in[i]));
            const Vec2d b = nearest_inside(in, W, H, x, y, int(std::ceil(d)) + 1);
            const double dx = x + 0.5 - b.x, dy = y + 0.5 - b.y, n = std::max(1e-9, std::hypot(dx, dy));
            NeedPixel p{x, y, {dx / n, dy / n}, n};
            for (const auto& [ox, oy] : {std::pair{-1, 0}, std::pair{-1, -1}, std::pair{0, -1}, std::pair{1, -1}}) {
                if (x + ox < 0 || y + oy < 0 || x + ox >= W) continue;
                const int k = at[std::size_t(y + oy) * W + std::size_t(x + ox)];
                if (k < 0 || needs[std::size_t(k)].dir.x * p.dir.x + needs[std::size_t(k)].dir.y * p.dir.y >= 0)
                    continue;
                if (const double t = depth_along(cov, p, needs[std::size_t(k)].dir, cap); t > 0)
                    p.dir = needs[std::size_t(k)].dir, p.dist = t;
                break;
            }
            at[i] = int(needs.size());
            needs.push_back(p);
        }
    return needs;
}

// Pixels to cover that bend together: a connected group bends on a lattice of half its
// farthest pixel's distance, at least 5 px (a cubic B-spline spans four spacings, so the
// bend spreads over about twice the distance it moves the outline: no further than it must,
// and its slope along the outline stays under about one pixel per pixel), at most `widest`.
// Where two groups' bends overlap, their displacements add (a sum of smooth fields is smooth).
struct NeedGroup {
    std::vector<NeedPixel> needs;
    double far = 0, h = 0;
    std::array<double, 4> box{1e300, 1e300, -1e300, -1e300}; // where its bend reaches
    void settle(double widest) {
        far = 0;
        std::array<double, 4> b{1e300, 1e300, -1e300, -1e300};
        for (const NeedPixel& p : needs)
            far = std::max(far, p.dist), b = {std::min(b[0], p.x - p.dist), std::min(b[1], p.y - p.dist),
                                              std::max(b[2], p.x + 1 + p.dist), std::max(b[3], p.y + 1 + p.dist)};
        h = std::max(5.0, std::min(widest, 0.5 * (far + 1)));
        box = {b[0] - 3 * h, b[1] - 3 * h, b[2] + 3 * h, b[3] + 3 * h};
    }
};

std::vector<NeedGroup> group_needs(const std::vector<NeedPixel>& needs, int W, int H, double widest) {
    std::vector<int> at(std::size_t(W) * H, -1), group(needs.size(), -1);
    for (std::size_t i = 0; i < needs.size(); ++i) at[std::size_t(needs[i].y) * W + needs[i].x] = int(i);
    std::vector<NeedGroup> out;
    for (std::size_t s = 0; s < needs.size(); ++s) {
        if (group[s] >= 0) continue;
        NeedGroup g;
        std::vector<std::size_t> todo{s};
        group[s] = int(out.size());
        while (!todo.empty()) {
            const NeedPixel& p = needs[todo.back()];
            todo.pop_back();
            g.needs.push_back(p);
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int x = p.x + dx, y = p.y + dy;
                    if (x < 0 || y < 0 || x >= W || y >= H) continue;
                    const int k = at[std::size_t(y) * W + x];
                    if (k >= 0 && group[std::size_t(k)] < 0)
                        group[std::size_t(k)] = int(out.size()), todo.push_back(std::size_t(k));
                }
        }
        g.settle(widest);
        out.push_back(std::move(g));
    }
    return out;
}

// The field that covers the pixels to cover (Reconciler::warp), on a lattice of spacing h.
WarpField fit_bend(const std::vector<NeedPixel>& needs, const std::vector<char>& in, const std::vector<float>& to_need,
                   const Coverage& cov, double h, double cap) {
    const int W = cov.width(), H = cov.height();
    double bx0 = 1e300, by0 = 1e300, bx1 = -1e300, by1 = -1e300;
    for (const NeedPixel& p : needs)
        bx0 = std::min(bx0, p.x - p.dist), by0 = std::min(by0, p.y - p.dist), bx1 = std::max(bx1, p.x + 1 + p.dist),
        by1 = std::max(by1, p.y + 1 + p.dist);
    WarpField field(bx0, by0, bx1, by1, h);
    const int stride = std::max(1, int(h / 6));
    auto bucket = [&](int x, int y) { return std::pair{x / stride, y / stride}; };
    // One wish per occupied bucket of stride x stride pixels: its farthest pixel.
    std::map<std::pair<int, int>, std::size_t> wish_of;
    std::vector<WarpTarget> wishes;
    std::vector<std::size_t> wish_need;
    for (std::size_t i = 0; i < needs.size(); ++i) {
        const NeedPixel& p = needs[i];
        auto [it, fresh] = wish_of.try_emplace(bucket(p.x, p.y), wishes.size());
        const Vec2d at{p.x + 0.5, p.y + 0.5}, want{p.dir.x * (p.dist + 1), p.dir.y * (p.dist + 1)};
        if (fresh) wishes.push_back({at, clamp_length(want, cap), 1.0}), wish_need.push_back(i);
        else if (p.dist > needs[wish_need[it->second]].dist)
            wishes[it->second] = {at, clamp_length(want, cap), 1.0}, wish_need[it->second] = i;
    }
    // The outline away from the pixels to cover (beyond one spacing) stays where it is: the
    // bulge is held to the stretch of outline that must move.
    const auto sup = field.support();
    std::map<std::pair<int, int>, bool> anchored;
    for (int y = std::max(1, int(sup[1])); y < std::min(H - 1, int(sup[3]) + 1); ++y)
        for (int x = std::max(1, int(sup[0])); x < std::min(W - 1, int(sup[2]) + 1); ++x) {
            const std::size_t i = std::size_t(y) * W + x;
            if (!in[i] || (in[i - 1] && in[i + 1] && in[i - std::size_t(W)] && in[i + std::size_t(W)])) continue;
            if (to_need[i] <= h * h || !anchored.try_emplace(bucket(x, y), true).second) continue;
            wishes.push_back({{x + 0.5, y + 0.5}, {0, 0}, 0.5});
        }
    auto shown = [&](double x, double y, const WarpField& f) {
        const Vec2d d = clamp_length(f(x, y), cap);
        return sample(cov, x - d.x, y - d.y) >= 0.5f;
    };
    // The membrane weighs as half of the wishes to cover, spread over the lattice: enough to
    // keep the field smooth where wishes are sparse, and fixed as the wishes press harder.
    const double membrane = 0.5 * double(wish_need.size()) / std::max(1, field.free_points());
    for (int round = 0; round < 10; ++round) {
        field.fit(wishes, membrane);
        // Every pixel still uncovered presses its bucket's wish harder, along the wish's way
        // out (one way per bucket: a gap between two parts closes from one side), by what the
        // field still lacks there: the wishes grow no more than the fit needs.
        std::map<std::size_t, double> lack; // wish -> the most it lacks
        for (const NeedPixel& p : needs) {
            if (shown(p.x + 0.5, p.y + 0.5, field)) continue;
            const std::size_t w = wish_of.at(bucket(p.x, p.y));
            const Vec2d dir = needs[wish_need[w]].dir;
            const double t = depth_along(cov, p, dir, cap);
            if (t <= 0) continue;
            const Vec2d f = clamp_length(field(p.x + 0.5, p.y + 0.5), cap);
            lack[w] = std::max(lack[w], std::max(0.5, t + 1 - (f.x * dir.x + f.y * dir.y)));
        }
        if (lack.empty()) break;
        for (const auto& [w, l] : lack) {
            WarpTarget& t = wishes[w];
            const Vec2d dir = needs[wish_need[w]].dir;
            // At most twice the farthest pixel's need (one it cannot meet must not swell it).
            const double most = std::min(cap, 2 * (needs[wish_need[w]].dist + 1));
            t.v = clamp_length({t.v.x + dir.x * l, t.v.y + dir.y * l}, most);
            t.weight *= 1.5;
        }
    }
    return field;
}

} // namespace

// The pixels to cover are those of the rects outside the silhouette. The field is the
// inverse map (the reconciled pixel q shows the drawing at q - f(q)); each pixel to cover
// wishes f to reach from it to a pixel inside the silhouette, one pixel deep, along the way
// out (the outline's outward normal there), and the outline far from them (beyond one
// lattice spacing) wishes f to be zero. The fit is least squares: wishes it leaves unmet
// are pressed harder (longer, heavier) over a few rounds. The silhouette takes the union of
// itself and its warp (the bend only grows it: a thin part the field drags along keeps its
// far side), and the drawing follows the warp wherever the warped silhouette is the one
// shown.
double Reconciler::warp(Member& m, const std::vector<std::array<double, 4>>& rects, double cap) {
    if (rects.empty()) return 0.0;
    View& v = views_.views[m.index];
    double x0 = 0, y0 = 0, x1 = v.width, y1 = v.height;
    for (const auto& r : rects)
        x0 = std::min(x0, r[0] - 2), y0 = std::min(y0, r[1] - 2), x1 = std::max(x1, r[2] + 2),
        y1 = std::max(y1, r[3] + 2);
    // Rects were projected by the camera before the canvas grew: they move with it.
    const int left = int(std::ceil(-x0)), top = int(std::ceil(-y0));
    grow_canvas(m, left, top, int(std::ceil(x1)) - v.width, int(std::ceil(y1)) - v.height);
    const int W = v.width, H = v.height;
    const std::vector<float> cov = v.coverage.full();
    std::vector<char> in(cov.size()), need(cov.size(), 0);
    for (std::size_t i = 0; i < cov.size(); ++i) in[i] = cov[i] >= 0.5f;
    for (const auto& r : rects)
        for (int y = std::max(0, int(std::floor(r[1])) + top); y < std::min(H, int(std::ceil(r[3])) + top); ++y)
            for (int x = std::max(0, int(std::floor(r[0])) + left); x < std::min(W, int(std::ceil(r[2])) + left); ++x)
                need[std::size_t(y) * W + x] = !in[std::size_t(y) * W + x];
    const std::vector<NeedPixel> needs = need_pixels(in, need, v.coverage, W, H, cap);
    if (needs.empty()) return 0.0;
    // Each group of them bends on a lattice of half its farthest distance, at most a
    // twenty-fourth of the silhouette's longest side (a cubic B-spline spans four spacings:
    // a bend spreads over at most a sixth of the silhouette).
    const Coverage::Box& ib = v.coverage.inside_box();
    const double widest = std::max(4.0, std::max(ib.x1 - ib.x0 + 1, ib.y1 - ib.y0 + 1) / 24.0);
    const std::vector<float> to_need = squared_edt(need, W, H);
    std::vector<WarpField> fields;
    for (const NeedGroup& g : group_needs(needs, W, H, widest))
        fields.push_back(fit_bend(g.needs, in, to_need, v.coverage, g.h, cap));
    // Resampled through the field where it is not zero.
    std::vector<float> out = cov;
    const bool colour = v.image.width == W && v.image.height == H;
    Image img{W, H, 4, std::vector<float>(colour ? std::size_t(W) * H * 4 : 0), {}};
    if (colour)
        for (std::size_t i = 0; i < cov.size(); ++i) {
            const auto c = v.image.rgba(i);
            std::copy(c.begin(), c.end(), img.pixels.begin() + std::ptrdiff_t(i * 4));
        }
    // The sum of the groups' fields, over the box they reach.
    std::array<double, 4> reach{1e300, 1e300, -1e300, -1e300};
    for (const WarpField& f : fields) {
        const auto b = f.support();
        reach = {std::min(reach[0], b[0]), std::min(reach[1], b[1]), std::max(reach[2], b[2]),
                 std::max(reach[3], b[3])};
    }
    std::vector<double> row_max(std::size_t(H), 0.0);
    const int ya = std::max(0, int(reach[1])), yb = std::min(H, int(std::ceil(reach[3])) + 1);
    const int xa = std::max(0, int(reach[0])), xb = std::min(W, int(std::ceil(reach[2])) + 1);
    tbb::parallel_for(ya, std::max(ya, yb), [&](int y) {
        std::vector<const WarpField*> here;
        for (const WarpField& f : fields)
            if (const auto b = f.support(); b[1] <= y + 0.5 && y + 0.5 <= b[3]) here.push_back(&f);
        for (int x = xa; x < xb; ++x) {
            Vec2d d{0, 0};
            for (const WarpField* f : here) {
                const Vec2d e = (*f)(x + 0.5, y + 0.5);
                d.x += e.x, d.y += e.y;
            }
            d = clamp_length(d, cap);
            const double n = std::hypot(d.x, d.y);
            row_max[std::size_t(y)] = std::max(row_max[std::size_t(y)], n);
            if (n < 1e-3) continue;
            const std::size_t i = std::size_t(y) * W + x;
            const float s = sample(v.coverage, x + 0.5 - d.x, y + 0.5 - d.y);
            if (s < cov[i]) continue;
            out[i] = s;
            if (!colour) continue;
            const auto c = colour_at(v.image, W, H, x + 0.5 - d.x, y + 0.5 - d.y);
            for (std::size_t k = 0; k < 4; ++k) img.pixels[i * 4 + k] = c[k];
        }
    });
    const double most = *std::max_element(row_max.begin(), row_max.end());
    v.coverage = Coverage(out, W, H);
    if (colour) v.image = std::move(img);
    return most;
}

} // namespace cm::reconcile_detail
