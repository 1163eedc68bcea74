#include "geometry/hull_normal.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cm {

namespace {

// Pixel position of a world point in a view (after the perspective division).
Vec2d pixel(const SilhouetteField& f, const Vec3d& p) {
    const auto h = f.project_h(p);
    return {h[0] / h[2], h[1] / h[2]};
}

// An image-plane gradient (gx, gy) at the pixel of p, pulled back to world space through the
// projection's Jacobian (central differences; linear for orthographic views).
Vec3d pulled_back(const SilhouetteField& f, const Vec3d& p, double gx, double gy) {
    const double d = 1e-3 * f.pixel_size_at(p);
    Vec3d g{};
    for (int a = 0; a < 3; ++a) {
        Vec3d lo = p, hi = p;
        lo[a] -= d;
        hi[a] += d;
        const Vec2d ql = pixel(f, lo), qh = pixel(f, hi);
        g[a] = (gx * (qh.x - ql.x) + gy * (qh.y - ql.y)) / (2 * d);
    }
    return g;
}

// The outward normal of the view's outline near p, its direction averaged over a disc of
// radius r pixels: the first moment of the coverage over the disc, pulled back.
Vec3d smoothed(const SilhouetteField& f, const Vec3d& p, double r) {
    const Vec2d q = pixel(f, p);
    // Half a pixel apart: the bilinear coverage varies within a pixel cell.
    const double step = std::clamp(r / 6, 0.25, 0.5);
    const int n = int(std::ceil(r / step));
    double mx = 0, my = 0;
    for (int j = -n; j <= n; ++j)
        for (int k = -n; k <= n; ++k) {
            const double sx = k * step, sy = j * step;
            if (sx * sx + sy * sy > r * r) continue;
            const double w = f.coverage(q.x + sx, q.y + sy);
            mx += w * sx, my += w * sy;
        }
    const Vec3d g = pulled_back(f, p, mx, my);
    const double gl = length(g);
    return gl > 0 ? g * (-1.0 / gl) : Vec3d{0, 0, 0};
}

} // namespace

HullNormal hull_normal(const VisualHull& hull, const Vec3d& p, double smooth_px) {
    HullNormal best{{0, 0, 0}, -1, std::numeric_limits<double>::infinity()};
    for (std::size_t i = 0; i < hull.size(); ++i) {
        const SilhouetteField& f = hull.field(i);
        if (f.project_h(p)[2] <= SilhouetteField::kMinDepth) continue;
        const Vec2d q = pixel(f, p);
        // Gradient of the bilinear coverage in pixels (exact within a cell of pixel centres).
        constexpr double e = 1e-3;
        const double c = f.coverage(q.x, q.y);
        const double gx = (f.coverage(q.x + e, q.y) - f.coverage(q.x - e, q.y)) / (2 * e);
        const double gy = (f.coverage(q.x, q.y + e) - f.coverage(q.x, q.y - e)) / (2 * e);
        if (gx == 0 && gy == 0) continue; // no outline through this pixel cell
        const Vec3d g = pulled_back(f, p, gx, gy);
        const double gl = length(g);
        if (!(gl > 0)) continue;
        const double dist = std::abs(c - 0.5) / gl;
        if (dist < best.distance) best = {g * (-1.0 / gl), int(i), dist};
    }
    if (smooth_px > 0 && best.view >= 0) best.normal = smoothed(hull.field(std::size_t(best.view)), p, smooth_px);
    // A face of the clip box nearer than every outline bounds the hull there.
    for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side) {
            const double plane = side ? hull.clip_hi()[a] : hull.clip_lo()[a];
            if (!std::isfinite(plane) || std::abs(plane) > 1e200) continue;
            const double dist = std::abs(p[a] - plane);
            if (dist < best.distance) {
                Vec3d n{0, 0, 0};
                n[a] = side ? 1.0 : -1.0;
                best = {n, -1, dist};
            }
        }
    return best;
}

} // namespace cm
