#include "surface_colour.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "render/colour.h"

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
    // The nearest surface at the pixel itself. (Near an occluder's edge the view's say is
    // small anyway, view_colours.h; a wider window would take from a view the pixels of
    // its own drawing just beside every occluder, which only it may see.)
    if (!d.covered(ix, iy)) return false;
    const float nearest = d.depth[std::size_t(iy) * d.width + ix];
    const double cc = std::clamp(c, 0.1, 1.0);
    const double tan_angle = std::sqrt(1 - cc * cc) / cc;
    const double tol = v.pixel_world * (2.0 + 1.5 * tan_angle);
    return v.view->camera.depth(p) <= double(nearest) + tol;
}

int view_samples(const std::vector<ViewSampler>& views, const Vec3d& p, const Vec3d& n, const SurfaceColourOptions& opt,
                 ViewSample* out, bool lab) {
    int count = 0;
    for (std::size_t i = 0; i < views.size() && count < kMaxViewSamples; ++i) {
        const ViewSampler& v = views[i];
        if (!v.colours.any_valid) continue;
        const double c = facing(v.view->camera, p, n);
        if (c <= 0.02 || !visible_in(v, p, c)) continue;
        const Vec2d q = v.view->camera.project(p);
        ViewSample& s = out[count++];
        float conf;
        v.colours.sample(q.x, q.y, s.rgb, conf);
        s.view = int(i);
        s.weight = v.weight;
        s.facing = c;
        s.drawn = v.colours.drawn_at(q.x, q.y);
        // A small floor keeps a view's filled colour where every view is unsure (a point
        // under an ink line seen by one view only).
        s.say = std::pow(c, opt.angle_power) * (0.02 + conf);
        if (lab || opt.conflict_de > 0) s.lab = srgb_to_lab(s.rgb);
    }
    return count;
}

std::array<float, 3> combine_samples(const ViewSample* s, int n, const SurfaceColourOptions& opt) {
    double w[kMaxViewSamples], sum = 0;
    for (int k = 0; k < n; ++k) {
        w[k] = s[k].say * s[k].weight;
        sum += w[k];
    }
    if (sum <= 0) return s[0].rgb;
    if (opt.conflict_de <= 0 || n == 1) {
        double acc[3] = {0, 0, 0};
        for (int k = 0; k < n; ++k)
            for (int ch = 0; ch < 3; ++ch) acc[ch] += w[k] * s[k].rgb[ch];
        return {float(acc[0] / sum), float(acc[1] / sum), float(acc[2] / sum)};
    }
    // The minimum over c of sum_k w_k sqrt(|c - lab_k|^2 + e^2): convex, so iteratively
    // reweighted means converge to it, started at the view colour of least cost.
    const double e2 = opt.conflict_de * opt.conflict_de;
    auto cost = [&](const std::array<double, 3>& c) {
        double t = 0;
        for (int k = 0; k < n; ++k) {
            const double d0 = c[0] - s[k].lab[0], d1 = c[1] - s[k].lab[1], d2 = c[2] - s[k].lab[2];
            t += w[k] * std::sqrt(d0 * d0 + d1 * d1 + d2 * d2 + e2);
        }
        return t;
    };
    std::array<double, 3> c = s[0].lab;
    double best = cost(c);
    for (int k = 1; k < n; ++k) {
        const double t = cost(s[k].lab);
        if (t < best) {
            best = t;
            c = s[k].lab;
        }
    }
    for (int it = 0; it < 24; ++it) {
        double acc[3] = {0, 0, 0}, den = 0;
        for (int k = 0; k < n; ++k) {
            const double d0 = c[0] - s[k].lab[0], d1 = c[1] - s[k].lab[1], d2 = c[2] - s[k].lab[2];
            const double a = w[k] / std::sqrt(d0 * d0 + d1 * d1 + d2 * d2 + e2);
            for (int ch = 0; ch < 3; ++ch) acc[ch] += a * s[k].lab[ch];
            den += a;
        }
        const std::array<double, 3> next{acc[0] / den, acc[1] / den, acc[2] / den};
        const double step = std::abs(next[0] - c[0]) + std::abs(next[1] - c[1]) + std::abs(next[2] - c[2]);
        c = next;
        if (step < 0.01) break;
    }
    return lab_to_srgb(c);
}

bool surface_colour(const std::vector<ViewSampler>& views, const Vec3d& p, const Vec3d& n,
                    const SurfaceColourOptions& opt, std::array<float, 3>& rgb) {
    ViewSample s[kMaxViewSamples];
    const int count = view_samples(views, p, n, opt, s);
    if (count == 0) return false;
    rgb = combine_samples(s, count, opt);
    return true;
}

} // namespace cm
