#include "geometry/hull_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/collaborative_call_once.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "core/error.h"
#include "geometry/distance_transform.h"

namespace cm {

// The field beyond a silhouette's window: every pixel there is outside, farther than the
// margin from the silhouette, so its value is its distance to the nearest inside pixel less
// half a pixel. Built on first use from the window's inside pixels (all the inside pixels
// there are), once: threads that ask meanwhile help build it.
class SdfBeyondWindow {
public:
    SdfBeyondWindow(std::vector<char> inside, int ox, int oy, int stride, int rows, int w, int h)
        : inside_(std::move(inside)), ox_(ox), oy_(oy), stride_(stride), rows_(rows), w_(w), h_(h) {}
    float at(int i, int j) const {
        tbb::collaborative_call_once(once_, [&] {
            std::vector<char> seed(std::size_t(w_) * h_, 0);
            for (int y = 0; y < rows_; ++y)
                std::copy_n(inside_.data() + std::size_t(y) * stride_, stride_,
                            seed.data() + std::size_t(y + oy_) * w_ + ox_);
            to_in_ = squared_edt(seed, w_, h_);
        });
        return std::sqrt(to_in_[std::size_t(j) * w_ + i]) - 0.5f;
    }

private:
    std::vector<char> inside_; // the window's inside pixels
    int ox_, oy_, stride_, rows_, w_, h_;
    mutable tbb::collaborative_once_flag once_;
    mutable std::vector<float> to_in_;
};

SilhouetteSdf silhouette_sdf(const std::vector<float>& coverage, int w, int h, const std::string& view_name) {
    if (w <= 0 || h <= 0 || coverage.size() != std::size_t(w) * h)
        throw Error("view \"" + view_name + "\": the silhouette does not match the image size");
    return silhouette_sdf(Coverage(coverage, w, h), view_name);
}

SilhouetteSdf silhouette_sdf(const Coverage& coverage, const std::string& view_name) {
    const int w = coverage.width(), h = coverage.height();
    if (w <= 0 || h <= 0) throw Error("view \"" + view_name + "\" has no silhouette");
    const Coverage::Box box = coverage.inside_box();
    if (box.empty()) throw Error("view \"" + view_name + "\" has an empty silhouette");
    SilhouetteSdf s;
    s.width = w;
    s.height = h;
    constexpr int m = SilhouetteSdf::kSdfMargin;
    s.ox = std::max(0, box.x0 - m);
    s.oy = std::max(0, box.y0 - m);
    s.stride = std::min(w, box.x1 + m + 1) - s.ox;
    s.rows = std::min(h, box.y1 + m + 1) - s.oy;
    const int sw = s.stride, sh = s.rows;
    const std::size_t n = std::size_t(sw) * sh;
    std::vector<char> inside(n), outside(n);
    const std::size_t n_in = tbb::parallel_reduce(
        tbb::blocked_range<int>(0, sh, 16), std::size_t(0),
        [&](const tbb::blocked_range<int>& r, std::size_t k) {
            for (int y = r.begin(); y != r.end(); ++y) {
                char* in = inside.data() + std::size_t(y) * sw;
                char* out = outside.data() + std::size_t(y) * sw;
                for (int x = 0; x < sw; ++x) {
                    in[x] = coverage.at(x + s.ox, y + s.oy) >= 0.5f;
                    out[x] = !in[x];
                    k += std::size_t(in[x]);
                }
            }
            return k;
        },
        [](std::size_t x, std::size_t y) { return x + y; });
    const auto to_in = squared_edt(inside, sw, sh);
    // No outside pixel in the window: then none in the image (the window is the image).
    const std::vector<float> to_out = n_in == n ? std::vector<float>(n, kEdtFar) : squared_edt(outside, sw, sh);
    s.sdf.resize(n);
    tbb::parallel_for(tbb::blocked_range<int>(0, sh, 16), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y != r.end(); ++y)
            for (int x = 0; x < sw; ++x) {
                const std::size_t i = std::size_t(y) * sw + x;
                // The binary border lies half-way between an inside and an outside pixel centre.
                float d = inside[i] ? -(std::sqrt(to_out[i]) - 0.5f) : (std::sqrt(to_in[i]) - 0.5f);
                const float c = coverage.at(x + s.ox, y + s.oy);
                if (c > 0.0f && c < 1.0f && std::fabs(d) <= 0.5f) d = 0.5f - c;
                s.sdf[i] = d;
            }
    });
    if (sw != w || sh != h)
        s.beyond = std::make_shared<const SdfBeyondWindow>(std::move(inside), s.ox, s.oy, sw, sh, w, h);
    return s;
}

float SilhouetteSdf::at(int i, int j) const {
    const int x = i - ox, y = j - oy;
    if (x >= 0 && y >= 0 && x < stride && y < rows) return sdf[std::size_t(y) * stride + x];
    return beyond->at(i, j);
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
    auto v_at = [&](int i, int j) { return double(at(i, j)); };
    const double v =
        (1 - ty) * ((1 - tx) * v_at(x0, y0) + tx * v_at(x1, y0)) + ty * ((1 - tx) * v_at(x0, y1) + tx * v_at(x1, y1));
    if (in_frame) return v;
    // Beyond the image: at least as far as the border sample plus the way out.
    const double beyond_image = std::hypot(fx - cx, fy - cy);
    return beyond_image > 0 ? std::max(v, 0.0) + beyond_image : v;
}

std::vector<ViewSdf> view_sdfs(const Views& views) {
    // The views' fields are independent: built side by side. The first failing view in
    // order is reported, whichever thread found it first.
    std::vector<ViewSdf> out(views.views.size());
    std::vector<std::string> errors(views.views.size());
    tbb::parallel_for(std::size_t(0), views.views.size(), [&](std::size_t i) {
        const View& v = views.views[i];
        try {
            out[i] = {v.camera, silhouette_sdf(v.coverage, v.name)};
        } catch (const std::exception& e) {
            errors[i] = e.what();
        }
    });
    for (const auto& e : errors)
        if (!e.empty()) throw Error(e);
    return out;
}

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
