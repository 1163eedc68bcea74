// HullDistance (hull_distance.h): the largest of the views' signed distances at a point.
#include "geometry/hull_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace cm {

HullDistance::HullDistance(const Views& views) {
    if (views.views.empty()) throw Error("the hull constraint needs at least one view");
    finest_pixel_ = views.finest_pixel();
    fields_ = view_sdfs(views);
}

double HullDistance::perspective_distance(const Entry& e, const Vec3d& p) const {
    const Vec2d q = e.camera.project(p);
    const double px = e.sdf.sample(q.x, q.y);
    // Local scale of the projection (world units per pixel at p), from finite differences
    // along the axes.
    const double h = 1e-3 * (1.0 + std::fabs(e.camera.depth(p)));
    double s = 0;
    for (int a = 0; a < 3; ++a) {
        Vec3d o = p;
        o[a] += h;
        const Vec2d qa = e.camera.project(o);
        s = std::max(s, std::hypot(qa.x - q.x, qa.y - q.y) / h);
    }
    const double pixel_size = s > 0 ? 1.0 / s : finest_pixel_;
    return px * pixel_size;
}

void HullDistance::prefetch(const Vec3d& p) const { prefetch(p, all_views()); }

void HullDistance::prefetch(const Vec3d& p, ViewMask views) const {
    for (std::size_t i = 0; i < fields().size(); ++i) {
        if (i < 32 && !(views >> i & 1u)) continue;
        const Entry& e = fields()[i];
        const Vec2d q = e.camera.project(p);
        const double x = q.x - e.sdf.ox, y = q.y - e.sdf.oy; // in the window
        if (!(x >= 1.5 && y >= 1.5 && x < e.sdf.stride - 2.5 && y < e.sdf.rows - 2.5)) continue;
        const std::size_t at = std::size_t(y - 0.5) * std::size_t(e.sdf.stride) + std::size_t(x - 0.5);
        const float* row = e.sdf.sdf.data() + at;
        __builtin_prefetch(row - e.sdf.stride);
        __builtin_prefetch(row);
        __builtin_prefetch(row + e.sdf.stride);
        __builtin_prefetch(row + 2 * e.sdf.stride);
    }
}

double HullDistance::operator()(const Vec3d& p) const {
    double best = -std::numeric_limits<double>::infinity();
    for (const auto& e : fields()) best = std::max(best, view_distance(e, p));
    return best;
}

double HullDistance::distance(const Vec3d& p, ViewMask views) const {
    double best = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < fields().size(); ++i)
        if (i >= 32 || views >> i & 1u) best = std::max(best, view_distance(fields()[i], p));
    return best;
}

bool HullDistance::within(const Vec3d& p, double bound, std::size_t& first, ViewMask views, double& largest) const {
    const std::size_t n = fields().size();
    if (first >= n) first = 0;
    largest = -std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t i = (first + k) % n;
        if (i < 32 && !(views >> i & 1u)) continue;
        const double d = view_distance(fields()[i], p);
        if (d > bound) {
            first = i;
            largest = d;
            return false;
        }
        largest = std::max(largest, d);
    }
    return std::fabs(largest) <= bound;
}

bool HullDistance::within(const Vec3d& p, double bound, std::size_t& first) const {
    const std::size_t n = fields().size();
    if (first >= n) first = 0;
    double best = -std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t i = (first + k) % n;
        const double d = view_distance(fields()[i], p);
        if (d > bound) { // the largest is farther still
            first = i;
            return false;
        }
        best = std::max(best, d);
    }
    return std::fabs(best) <= bound;
}

} // namespace cm
