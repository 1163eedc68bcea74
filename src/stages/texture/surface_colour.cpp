#include "surface_colour.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cm {

double facing(const Camera& cam, const Vec3d& p, const Vec3d& n) {
    const Vec3d to_cam = cam.orthographic() ? -cam.d : normalize(cam.center() - p);
    return dot(n, to_cam);
}

bool visible_in(const ViewSampler& v, const Vec3d& p, double c) {
    const Vec2d q = v.view->camera.project(p);
    const int ix = int(std::floor(q.x)), iy = int(std::floor(q.y));
    const DepthImage& d = v.depth;
    if (ix < 0 || iy < 0 || ix >= d.width || iy >= d.height) return false;
    // The nearest surface around the pixel: a point just beside an occluder's edge counts
    // as hidden rather than painted with the occluder's colour.
    float nearest = std::numeric_limits<float>::infinity();
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const int x = ix + dx, y = iy + dy;
            if (x < 0 || y < 0 || x >= d.width || y >= d.height || !d.covered(x, y)) continue;
            nearest = std::min(nearest, d.depth[std::size_t(y) * d.width + x]);
        }
    if (!std::isfinite(nearest)) return false;
    const double cc = std::clamp(c, 0.1, 1.0);
    const double tan_angle = std::sqrt(1 - cc * cc) / cc;
    const double tol = v.pixel_world * (2.0 + 1.5 * tan_angle);
    return v.view->camera.depth(p) <= double(nearest) + tol;
}

bool surface_colour(const std::vector<ViewSampler>& views, const Vec3d& p, const Vec3d& n,
                    const SurfaceColourOptions& opt, std::array<float, 3>& rgb) {
    double sum = 0, acc[3] = {0, 0, 0};
    for (const ViewSampler& v : views) {
        if (!v.colours.any_valid) continue;
        const double c = facing(v.view->camera, p, n);
        if (c <= 0.02 || !visible_in(v, p, c)) continue;
        const Vec2d q = v.view->camera.project(p);
        std::array<float, 3> col;
        float conf;
        v.colours.sample(q.x, q.y, col, conf);
        // A small floor keeps a view's filled colour where every view is unsure (a point
        // under an ink line seen by one view only).
        const double w = std::pow(c, opt.angle_power) * (0.02 + conf);
        sum += w;
        for (int k = 0; k < 3; ++k) acc[k] += w * col[k];
    }
    if (sum <= 0) return false;
    for (int k = 0; k < 3; ++k) rgb[k] = float(acc[k] / sum);
    return true;
}

} // namespace cm
