#include "geometry/hull_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "core/error.h"
#include "geometry/distance_transform.h"

namespace cm {

SilhouetteSdf silhouette_sdf(const std::vector<float>& coverage, int w, int h, const std::string& view_name) {
    if (w <= 0 || h <= 0 || coverage.size() != std::size_t(w) * h)
        throw Error("view \"" + view_name + "\": the silhouette does not match the image size");
    std::vector<char> inside(coverage.size()), outside(coverage.size());
    const std::size_t n_in = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, coverage.size(), 1 << 16), std::size_t(0),
        [&](const tbb::blocked_range<std::size_t>& r, std::size_t n) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                inside[i] = coverage[i] >= 0.5f;
                outside[i] = !inside[i];
                n += std::size_t(inside[i]);
            }
            return n;
        },
        [](std::size_t x, std::size_t y) { return x + y; });
    if (n_in == 0) throw Error("view \"" + view_name + "\" has an empty silhouette");
    const auto to_in = squared_edt(inside, w, h);
    const std::vector<float> to_out =
        n_in == coverage.size() ? std::vector<float>(coverage.size(), kEdtFar) : squared_edt(outside, w, h);
    SilhouetteSdf s;
    s.width = w;
    s.height = h;
    s.sdf.resize(coverage.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, coverage.size(), 1 << 14), [&](const auto& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            // The binary border lies half-way between an inside and an outside pixel centre.
            float d = inside[i] ? -(std::sqrt(to_out[i]) - 0.5f) : (std::sqrt(to_in[i]) - 0.5f);
            const float c = coverage[i];
            if (c > 0.0f && c < 1.0f && std::fabs(d) <= 0.5f) d = 0.5f - c;
            s.sdf[i] = d;
        }
    });
    return s;
}

double SilhouetteSdf::sample_edge(double x, double y) const {
    // A point that projects nowhere (a coordinate overflowed) is outside every silhouette.
    if (!std::isfinite(x) || !std::isfinite(y)) return std::numeric_limits<double>::infinity();
    // Pixel-centre lattice coordinates.
    double fx = x - 0.5, fy = y - 0.5;
    const double cx = std::clamp(fx, 0.0, double(width - 1));
    const double cy = std::clamp(fy, 0.0, double(height - 1));
    const bool in_frame = fx == cx && fy == cy;
    const int x0 = std::min(int(cx), width - 1), y0 = std::min(int(cy), height - 1);
    const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
    const double tx = cx - x0, ty = cy - y0;
    auto at = [&](int i, int j) { return double(sdf[std::size_t(j) * width + i]); };
    const double v =
        (1 - ty) * ((1 - tx) * at(x0, y0) + tx * at(x1, y0)) + ty * ((1 - tx) * at(x0, y1) + tx * at(x1, y1));
    if (in_frame) return v;
    // Beyond the image: at least as far as the border sample plus the way out.
    const double beyond = std::hypot(fx - cx, fy - cy);
    return beyond > 0 ? std::max(v, 0.0) + beyond : v;
}

namespace {

std::vector<ViewSdf> build_view_sdfs(const Views& views) {
    // The views' fields are independent: built side by side. The first failing view in
    // order is reported, whichever thread found it first.
    std::vector<ViewSdf> out(views.views.size());
    std::vector<std::string> errors(views.views.size());
    tbb::parallel_for(std::size_t(0), views.views.size(), [&](std::size_t i) {
        const View& v = views.views[i];
        try {
            out[i] = {v.camera, silhouette_sdf(v.coverage, v.width, v.height, v.name)};
        } catch (const std::exception& e) {
            errors[i] = e.what();
        }
    });
    for (const auto& e : errors)
        if (!e.empty()) throw Error(e);
    return out;
}

} // namespace

std::shared_ptr<const std::vector<ViewSdf>> view_sdfs(const Views& views) {
    return std::static_pointer_cast<const std::vector<ViewSdf>>(views.derived.get(
        "silhouette_sdf", [&] { return std::make_shared<const std::vector<ViewSdf>>(build_view_sdfs(views)); }));
}

HullDistance::HullDistance(const Views& views) {
    if (views.views.empty()) throw Error("the hull constraint needs at least one view");
    finest_pixel_ = views.finest_pixel();
    fields_ = view_sdfs(views);
}

double HullDistance::view_distance(const Entry& e, const Vec3d& p) const {
    const Vec2d q = e.camera.project(p);
    const double px = e.sdf.sample(q.x, q.y);
    double pixel_size; // world units per pixel at p
    if (e.camera.orthographic()) {
        pixel_size = 1.0 / e.camera.scale;
    } else {
        // Local scale of the projection, from finite differences along the axes.
        const double h = 1e-3 * (1.0 + std::fabs(e.camera.depth(p)));
        double s = 0;
        for (int a = 0; a < 3; ++a) {
            Vec3d o = p;
            o[a] += h;
            const Vec2d qa = e.camera.project(o);
            s = std::max(s, std::hypot(qa.x - q.x, qa.y - q.y) / h);
        }
        pixel_size = s > 0 ? 1.0 / s : finest_pixel_;
    }
    return px * pixel_size;
}

void HullDistance::prefetch(const Vec3d& p) const { prefetch(p, all_views()); }

void HullDistance::prefetch(const Vec3d& p, ViewMask views) const {
    for (std::size_t i = 0; i < fields().size(); ++i) {
        if (i < 32 && !(views >> i & 1u)) continue;
        const Entry& e = fields()[i];
        const Vec2d q = e.camera.project(p);
        if (!(q.x >= 1.5 && q.y >= 1.5 && q.x < e.sdf.width - 2.5 && q.y < e.sdf.height - 2.5)) continue;
        const std::size_t at = std::size_t(q.y - 0.5) * std::size_t(e.sdf.width) + std::size_t(q.x - 0.5);
        const float* row = e.sdf.sdf.data() + at;
        __builtin_prefetch(row - e.sdf.width);
        __builtin_prefetch(row);
        __builtin_prefetch(row + e.sdf.width);
        __builtin_prefetch(row + 2 * e.sdf.width);
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
