#include "render/raster.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "core/error.h"

namespace cm {

namespace {

// A vertex on screen: pixel coordinates and an attribute that is affine in screen
// space and grows towards the camera (orthographic: -depth; perspective: 1/w).
struct SV {
    double x, y, k;
};

// Homogeneous projection of every vertex (orthographic: w = 1 and k = -depth).
struct Projected {
    bool perspective = false;
    std::vector<double> x, y, w, k;
};

Projected project_vertices(const Mesh& mesh, const Camera& cam) {
    Projected p;
    p.perspective = !cam.orthographic();
    const std::size_t n = mesh.positions.size();
    p.x.resize(n);
    p.y.resize(n);
    p.w.resize(n);
    p.k.resize(n);
    // A matrix and its negation project alike; pick the sign that makes w > 0 in front.
    std::array<double, 12> P = cam.P;
    if (p.perspective) {
        const double det = P[0] * (P[5] * P[10] - P[6] * P[9]) - P[1] * (P[4] * P[10] - P[6] * P[8]) +
                           P[2] * (P[4] * P[9] - P[5] * P[8]);
        if (det < 0)
            for (double& v : P) v = -v;
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 8192), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            const Vec3d q(mesh.positions[i]);
            if (!p.perspective) {
                const Vec2d s = cam.project(q);
                p.x[i] = s.x;
                p.y[i] = s.y;
                p.w[i] = 1.0;
                p.k[i] = -dot(q, cam.d);
            } else {
                p.x[i] = P[0] * q.x + P[1] * q.y + P[2] * q.z + P[3];
                p.y[i] = P[4] * q.x + P[5] * q.y + P[6] * q.z + P[7];
                p.w[i] = P[8] * q.x + P[9] * q.y + P[10] * q.z + P[11];
                p.k[i] = 0;
            }
        }
    });
    return p;
}

// Calls f(a, b, c) for the screen triangles of face t: one triangle, none (behind the
// camera, or not finite), or up to two after clipping a perspective triangle at w = eps.
template <typename F>
void screen_triangles(const Mesh& mesh, const Projected& p, std::size_t t, F&& f) {
    const auto& tri = mesh.triangles[t];
    if (!p.perspective) {
        f(SV{p.x[tri[0]], p.y[tri[0]], p.k[tri[0]]}, SV{p.x[tri[1]], p.y[tri[1]], p.k[tri[1]]},
          SV{p.x[tri[2]], p.y[tri[2]], p.k[tri[2]]});
        return;
    }
    struct H {
        double x, y, w;
    };
    const H h[3] = {{p.x[tri[0]], p.y[tri[0]], p.w[tri[0]]},
                    {p.x[tri[1]], p.y[tri[1]], p.w[tri[1]]},
                    {p.x[tri[2]], p.y[tri[2]], p.w[tri[2]]}};
    const double wmax = std::max({h[0].w, h[1].w, h[2].w});
    if (!(wmax > 0)) return;
    const double eps = 1e-7 * wmax;
    auto to_sv = [](const H& v) { return SV{v.x / v.w, v.y / v.w, 1.0 / v.w}; };
    if (h[0].w >= eps && h[1].w >= eps && h[2].w >= eps) {
        f(to_sv(h[0]), to_sv(h[1]), to_sv(h[2]));
        return;
    }
    // Sutherland-Hodgman against w >= eps in homogeneous space.
    H poly[4];
    int n = 0;
    for (int i = 0; i < 3; ++i) {
        const H& a = h[i];
        const H& b = h[(i + 1) % 3];
        const bool ain = a.w >= eps, bin = b.w >= eps;
        if (ain) poly[n++] = a;
        if (ain != bin) {
            const double s = (eps - a.w) / (b.w - a.w);
            poly[n++] = {a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), eps};
        }
    }
    for (int i = 1; i + 1 < n; ++i) f(to_sv(poly[0]), to_sv(poly[i]), to_sv(poly[i + 1]));
}

// Edge function of the directed edge p->q at (x, y), computed from a canonical order of
// the two ends so that edge(p, q) == -edge(q, p) exactly: a pixel centre on an edge
// shared by two triangles is inside both (inclusive test), never inside neither.
inline double edge(const SV& p, const SV& q, double x, double y) {
    if (p.x < q.x || (p.x == q.x && p.y < q.y)) return (q.x - p.x) * (y - p.y) - (q.y - p.y) * (x - p.x);
    return -((p.x - q.x) * (y - q.y) - (p.y - q.y) * (x - q.x));
}

// Where a raster writes: the columns [x0, x0 + width) and rows [y0, ...) of the image, pixel
// (i, j) of the image at index (j - y0) * width + (i - x0). The whole image: x0 = y0 = 0.
struct Frame {
    int width = 0, x0 = 0, y0 = 0;
};

// Visits the pixels of `frame` whose centre lies inside triangle abc, rows [row0, row1) (of
// the image). f(index, k) with k interpolated in screen space (affine there for both camera
// kinds). With `Spans`, f(rowbase, first, last) instead, once per row, for the pixels
// first..last of the row (frame columns) starting at rowbase: each edge function, computed
// in one fixed order per edge, is monotone along a row (a difference in x times a constant,
// from a constant), so the pixels inside all three are one run, found by testing from its
// two ends inwards. The tests are made at the image's pixel centres, whatever the frame.
template <bool Spans = false, typename F>
void raster_triangle(SV a, SV b, SV c, const Frame& frame, int row0, int row1, F&& f) {
    double area = edge(a, b, c.x, c.y);
    if (!(std::abs(area) > 0)) return; // degenerate or not finite
    if (area < 0) {
        std::swap(b, c);
        area = -area;
    }
    const double xmin = std::min({a.x, b.x, c.x}), xmax = std::max({a.x, b.x, c.x});
    const double ymin = std::min({a.y, b.y, c.y}), ymax = std::max({a.y, b.y, c.y});
    if (!std::isfinite(xmin) || !std::isfinite(xmax) || !std::isfinite(ymin) || !std::isfinite(ymax)) return;
    const int i0 = int(std::max(double(frame.x0), std::ceil(xmin - 0.5)));
    const int i1 = int(std::min(double(frame.x0 + frame.width - 1), std::floor(xmax - 0.5)));
    const int j0 = int(std::max(double(row0), std::ceil(ymin - 0.5)));
    const int j1 = int(std::min(double(row1 - 1), std::floor(ymax - 0.5)));
    const double inv = 1.0 / area;
    // The exact test over pixels [s0, s1] of row j.
    auto row = [&](int j, int s0, int s1) {
        const double y = j + 0.5;
        // Pixel i of this row is at rowbase + i (i a column of the image, at least frame.x0).
        const std::size_t rowbase = std::size_t(j - frame.y0) * std::size_t(frame.width) - std::size_t(frame.x0);
        if constexpr (Spans) {
            auto inside = [&](int i) {
                const double x = i + 0.5;
                return edge(b, c, x, y) >= 0 && edge(c, a, x, y) >= 0 && edge(a, b, x, y) >= 0;
            };
            while (s0 <= s1 && !inside(s0)) ++s0;
            while (s1 >= s0 && !inside(s1)) --s1;
            if (s0 <= s1) f(rowbase, s0, s1);
        } else {
            for (int i = s0; i <= s1; ++i) {
                const double x = i + 0.5;
                const double e0 = edge(b, c, x, y);
                if (e0 < 0) continue;
                const double e1 = edge(c, a, x, y);
                if (e1 < 0) continue;
                const double e2 = edge(a, b, x, y);
                if (e2 < 0) continue;
                f(rowbase + i, (e0 * a.k + e1 * b.k + e2 * c.k) * inv);
            }
        }
    };
    // A box a few pixels wide is tested whole.
    if (i1 - i0 < 8) {
        for (int j = j0; j <= j1; ++j) row(j, i0, i1);
        return;
    }
    // Wider: each edge function is affine along a row; where its slope is not zero, the
    // pixel centres it keeps lie on one side of where it crosses zero. That span, widened
    // by a pixel on each side for rounding, bounds the row's pixels, and the exact test
    // decides each of them: the same pixels as testing the whole box, without visiting
    // the box of a long thin triangle (what a reduction makes along straight parts).
    struct Bound {
        bool lower;       ///< the edge keeps the pixels right of its crossing (else left)
        double at0, step; ///< its crossing's column index on row j0, and per row
    };
    Bound bounds[3];
    int nb = 0;
    const SV* ends[3][2] = {{&b, &c}, {&c, &a}, {&a, &b}};
    for (const auto& e : ends) {
        const SV &p = *e[0], &q = *e[1];
        const double slope = -(q.y - p.y); // d edge(p, q, x, y) / dx, either end order
        // A (nearly) horizontal edge bounds nothing here: along the row its rounding may
        // outweigh its slope over many pixels, so the exact test alone decides.
        if (!(std::fabs(slope) >= 1e-6 * std::fabs(q.x - p.x))) continue;
        const double step = (q.x - p.x) / (q.y - p.y);
        const double at0 = p.x + step * (j0 + 0.5 - p.y) - 0.5;
        if (std::isfinite(at0) && std::isfinite(step)) bounds[nb++] = {slope > 0, at0, step};
    }
    for (int j = j0; j <= j1; ++j) {
        double lo = double(i0), hi = double(i1);
        for (int k = 0; k < nb; ++k) {
            const double cross = bounds[k].at0 + bounds[k].step * double(j - j0);
            if (bounds[k].lower) lo = std::max(lo, std::floor(cross) - 1);
            else hi = std::min(hi, std::ceil(cross) + 1);
        }
        row(j, int(std::min(lo, double(i1) + 1)), int(std::max(hi, double(i0) - 1))); // in int range
    }
}

void check_size(int width, int height) {
    if (width <= 0 || height <= 0 || width > 65536 || height > 65536)
        throw Error("cannot render a " + std::to_string(width) + "x" + std::to_string(height) +
                    " image: width and height must be in [1, 65536]");
}

} // namespace

std::vector<std::uint8_t> render_mask(const Mesh& mesh, const Camera& cam, int width, int height, Progress progress) {
    check_size(width, height);
    std::vector<std::uint8_t> mask(std::size_t(width) * height, 0);
    const Projected p = project_vertices(mesh, cam);
    std::uint8_t* out = mask.data();
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, mesh.triangles.size(), 4096), [&](const tbb::blocked_range<std::size_t>& r) {
            progress.check();
            for (std::size_t t = r.begin(); t != r.end(); ++t)
                screen_triangles(mesh, p, t, [&](const SV& a, const SV& b, const SV& c) {
                    raster_triangle<true>(a, b, c, Frame{width}, 0, height, [&](std::size_t row, int first, int last) {
                        // Several triangles may set one pixel at once; all write 1.
                        for (int i = first; i <= last; ++i)
                            std::atomic_ref<std::uint8_t>(out[row + std::size_t(i)])
                                .store(1, std::memory_order_relaxed);
                    });
                });
        });
    return mask;
}

PixelWindow covered_window(const Mesh& mesh, const Camera& cam, int width, int height, int rim) {
    check_size(width, height);
    const PixelWindow all{0, 0, width, height};
    if (!cam.orthographic() || mesh.positions.empty()) return all;
    struct Box {
        double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL;
    };
    const Box b = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, mesh.positions.size(), 8192), Box{},
        [&](const tbb::blocked_range<std::size_t>& r, Box x) {
            for (std::size_t v = r.begin(); v != r.end(); ++v) {
                const Vec2d q = cam.project(Vec3d(mesh.positions[v]));
                x = {std::min(x.x0, q.x), std::min(x.y0, q.y), std::max(x.x1, q.x), std::max(x.y1, q.y)};
            }
            return x;
        },
        [](const Box& a, const Box& c) {
            return Box{std::min(a.x0, c.x0), std::min(a.y0, c.y0), std::max(a.x1, c.x1), std::max(a.y1, c.y1)};
        });
    if (!std::isfinite(b.x0 + b.y0 + b.x1 + b.y1)) return all;
    // Pixel i's centre i + 0.5 lies in [lo, hi] for i in [ceil(lo - 0.5), floor(hi - 0.5)], as
    // raster_triangle bounds its pixels.
    const double i0 = std::max(0.0, std::ceil(b.x0 - 0.5) - rim),
                 i1 = std::min(width - 1.0, std::floor(b.x1 - 0.5) + rim);
    const double j0 = std::max(0.0, std::ceil(b.y0 - 0.5) - rim),
                 j1 = std::min(height - 1.0, std::floor(b.y1 - 0.5) + rim);
    if (i0 > i1 || j0 > j1) return all; // nothing in the image
    return {int(i0), int(j0), int(i1 - i0) + 1, int(j1 - j0) + 1};
}

DepthImage render_depth(const Mesh& mesh, const Camera& cam, int width, int height, Progress progress) {
    return render_depth(mesh, cam, width, height, {0, 0, width, height}, std::move(progress));
}

DepthImage render_depth(const Mesh& mesh, const Camera& cam, int full_width, int full_height, const PixelWindow& window,
                        Progress progress) {
    check_size(full_width, full_height);
    if (window.x0 < 0 || window.y0 < 0 || window.width <= 0 || window.height <= 0 ||
        window.x0 + window.width > full_width || window.y0 + window.height > full_height)
        throw Error("the window to render does not lie within the " + std::to_string(full_width) + "x" +
                    std::to_string(full_height) + " image");
    const int width = window.width, height = window.height, y0 = window.y0;
    const Frame frame{width, window.x0, window.y0};
    DepthImage img;
    img.width = width;
    img.height = height;
    img.x0 = window.x0;
    img.y0 = window.y0;
    const std::size_t npx = std::size_t(width) * height;
    img.depth.assign(npx, std::numeric_limits<float>::infinity());
    img.face.assign(npx, DepthImage::kNoFace);
    const Projected p = project_vertices(mesh, cam);
    const std::size_t nt = mesh.triangles.size();

    // Bin faces into bands of rows so each band owns its pixels (no locks).
    constexpr int kBand = 8;
    const int nbands = (height + kBand - 1) / kBand;
    std::vector<std::int32_t> band_lo(nt, 0), band_hi(nt, -1);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nt, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t t = r.begin(); t != r.end(); ++t) {
            double ymin = std::numeric_limits<double>::infinity(), ymax = -ymin;
            screen_triangles(mesh, p, t, [&](const SV& a, const SV& b, const SV& c) {
                ymin = std::min({ymin, a.y, b.y, c.y});
                ymax = std::max({ymax, a.y, b.y, c.y});
            });
            if (!(ymin <= ymax) || !std::isfinite(ymin) || !std::isfinite(ymax)) continue;
            const double j0 = std::max(double(y0), std::ceil(ymin - 0.5));
            const double j1 = std::min(double(y0 + height - 1), std::floor(ymax - 0.5));
            if (j0 > j1) continue;
            band_lo[t] = (std::int32_t(j0) - y0) / kBand;
            band_hi[t] = (std::int32_t(j1) - y0) / kBand;
        }
    });
    std::vector<std::size_t> start(std::size_t(nbands) + 1, 0);
    for (std::size_t t = 0; t < nt; ++t)
        for (int b = band_lo[t]; b <= band_hi[t]; ++b) ++start[std::size_t(b) + 1];
    for (int b = 0; b < nbands; ++b) start[std::size_t(b) + 1] += start[std::size_t(b)];
    std::vector<std::uint32_t> faces(start.back());
    {
        std::vector<std::size_t> fill(start.begin(), start.end() - 1);
        for (std::size_t t = 0; t < nt; ++t)
            for (int b = band_lo[t]; b <= band_hi[t]; ++b) faces[fill[std::size_t(b)]++] = std::uint32_t(t);
    }

    progress.check();
    std::vector<double> nearness(npx, -std::numeric_limits<double>::infinity());
    tbb::parallel_for(0, nbands, [&](int b) {
        if (b % 16 == 0) progress.check();
        const int row0 = y0 + b * kBand, row1 = std::min(y0 + height, row0 + kBand);
        for (std::size_t k = start[std::size_t(b)]; k < start[std::size_t(b) + 1]; ++k) {
            const std::uint32_t t = faces[k];
            screen_triangles(mesh, p, t, [&](const SV& a, const SV& bb, const SV& c) {
                raster_triangle(a, bb, c, frame, row0, row1, [&](std::size_t i, double near) {
                    if (near > nearness[i] || img.face[i] == DepthImage::kNoFace) {
                        nearness[i] = near;
                        img.face[i] = t;
                    }
                });
            });
        }
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, npx, 65536), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i)
            if (img.face[i] != DepthImage::kNoFace)
                img.depth[i] = float(p.perspective ? 1.0 / nearness[i] : -nearness[i]);
    });
    return img;
}

Camera resized_camera(const Camera& cam, double factor) {
    if (!(factor > 0) || !std::isfinite(factor)) throw Error("an image can only be resized by a positive factor");
    if (cam.orthographic()) {
        Camera c = cam;
        c.scale *= factor;
        c.cx *= factor;
        c.cy *= factor;
        return c;
    }
    std::array<double, 12> P = cam.P;
    for (int i = 0; i < 8; ++i) P[std::size_t(i)] *= factor;
    return Camera::perspective(P);
}

Camera framed_camera(const Camera& direction, Vec3d bbox_min, Vec3d bbox_max, int width, int height) {
    if (!direction.orthographic()) throw Error("a framed view must be orthographic");
    check_size(width, height);
    const Vec3d ext = bbox_max - bbox_min;
    const double e = std::max({ext.x, ext.y, ext.z});
    if (!(e > 0) || !std::isfinite(e)) throw Error("cannot frame an empty or degenerate bounding box");
    Camera c = direction;
    c.scale = 0.9 * std::min(width, height) / e;
    const Vec3d mid = (bbox_min + bbox_max) * 0.5;
    c.cx = 0.5 * width - c.scale * dot(mid, c.r);
    c.cy = 0.5 * height + c.scale * dot(mid, c.u);
    return c;
}

} // namespace cm
