// The box of reconciled views (reconcile.h): the fitted box is the views' agreed size, but a
// drawing that draws an axis longer than the others, once they are bent to let it through,
// reaches beyond it; the hull's box is what the views themselves span.
#include <algorithm>
#include <cmath>
#include <tuple>

#include "reconcile_state.h"

namespace cm::reconcile_detail {

std::pair<Vec3d, Vec3d> Reconciler::silhouette_span(bool all) const {
    Vec3d lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    if (!all) lo = {-1e300, -1e300, -1e300}, hi = {1e300, 1e300, 1e300};
    for (const Member& m : members_) {
        const View& v = views_.views[m.index];
        const Coverage::Box& b = v.coverage.inside_box();
        if (b.empty()) continue;
        const Camera& c = v.camera;
        // Image x = cx + s p.r, y = cy - s p.u, with r and u along (or against) a world axis.
        const double xa = (b.x0 - c.cx) / c.scale * c.r[m.ar], xb = (b.x1 + 1 - c.cx) / c.scale * c.r[m.ar];
        const double ya = (c.cy - b.y0) / c.scale * c.u[m.au], yb = (c.cy - b.y1 - 1) / c.scale * c.u[m.au];
        for (const auto& [axis, a, z] : {std::tuple{m.ar, xa, xb}, std::tuple{m.au, ya, yb}}) {
            const double l = std::min(a, z), h = std::max(a, z);
            if (all) lo[axis] = std::min(lo[axis], l), hi[axis] = std::max(hi[axis], h);
            else lo[axis] = std::max(lo[axis], l), hi[axis] = std::min(hi[axis], h);
        }
    }
    // An axis no member measures keeps the fitted box's.
    const Vec3d flo{-size_[0] / 2, 0, -size_[2] / 2}, fhi{size_[0] / 2, size_[1], size_[2] / 2};
    for (int a = 0; a < 3; ++a)
        if (!(lo[a] < hi[a]) || std::abs(lo[a]) > 1e299 || std::abs(hi[a]) > 1e299) lo[a] = flo[a], hi[a] = fhi[a];
    return {lo, hi};
}

void Reconciler::settle_box() {
    auto [lo, hi] = silhouette_span(false);
    // Where the views span the fitted box to within half a pixel, the box stays as fitted:
    // views that agree keep the alignment's frame to the bit.
    double px = 0;
    for (const Member& m : members_) px = std::max(px, 0.5 / views_.views[m.index].camera.scale);
    const Vec3d flo{-size_[0] / 2, 0, -size_[2] / 2}, fhi{size_[0] / 2, size_[1], size_[2] / 2};
    for (int a = 0; a < 3; ++a)
        if (std::abs(lo[a] - flo[a]) <= px && std::abs(hi[a] - fhi[a]) <= px) lo[a] = flo[a], hi[a] = fhi[a];
    // The output frame's pivot: the box's bottom centre at the origin.
    const Vec3d d{-0.5 * (lo.x + hi.x), -lo.y, -0.5 * (lo.z + hi.z)};
    for (View& v : views_.views) {
        if (!v.camera.orthographic()) continue;
        v.camera.cx -= v.camera.scale * dot(d, v.camera.r);
        v.camera.cy += v.camera.scale * dot(d, v.camera.u);
    }
    for (Member& m : members_) m.cam = views_.views[m.index].camera;
    views_.bounds_min = lo + d, views_.bounds_max = hi + d;
    span_.first = span_.first + d, span_.second = span_.second + d;
}

void Reconciler::grow_canvas(Member& m, int left, int top, int right, int bottom) {
    left = std::max(0, left), top = std::max(0, top), right = std::max(0, right), bottom = std::max(0, bottom);
    if (left + top + right + bottom == 0) return;
    View& v = views_.views[m.index];
    const int W = v.width + left + right, H = v.height + top + bottom;
    std::vector<float> cov(std::size_t(W) * H, 0.0f);
    Image img{W, H, 4, std::vector<float>(std::size_t(W) * H * 4, 0.0f), {}};
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const int sx = x - left, sy = y - top;
            if (sx >= 0 && sy >= 0 && sx < v.width && sy < v.height)
                cov[std::size_t(y) * W + x] = v.coverage.at(sx, sy);
            const int ix = std::clamp(sx, 0, v.width - 1), iy = std::clamp(sy, 0, v.height - 1);
            const auto px = v.image.rgba(std::size_t(iy) * v.width + ix);
            for (int c = 0; c < 4; ++c) img.pixels[(std::size_t(y) * W + x) * 4 + c] = px[std::size_t(c)];
        }
    v.coverage = Coverage(cov, W, H);
    v.image = std::move(img);
    v.width = W, v.height = H;
    v.camera.cx += left, v.camera.cy += top;
    m.cam = v.camera;
}

} // namespace cm::reconcile_detail
