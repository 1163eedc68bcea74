#include "geometry/visual_hull.h"

#include <algorithm>

#include "core/error.h"

namespace cm {

VisualHull::VisualHull(const Views& views, Vec3d clip_lo, Vec3d clip_hi) : clip_lo_(clip_lo), clip_hi_(clip_hi) {
    if (views.views.empty()) throw Error("no views: the visual hull needs at least one view");
    fields_.reserve(views.views.size());
    for (const auto& v : views.views) fields_.emplace_back(v);
}

VisualHull::Class VisualHull::classify(const Vec3d& lo, const Vec3d& hi, ViewMask& mask) const {
    if (hi.x < clip_lo_.x || hi.y < clip_lo_.y || hi.z < clip_lo_.z || lo.x > clip_hi_.x || lo.y > clip_hi_.y ||
        lo.z > clip_hi_.z)
        return Class::Outside;
    const bool clipped = !(in_clip(lo) && in_clip(hi));
    bool mixed = clipped;
    for (std::size_t i = 0; i < fields_.size(); ++i) {
        if (i < 64 && !((mask >> i) & 1u)) continue;
        const Class c = fields_[i].classify_box(lo, hi);
        if (c == Class::Outside) return Class::Outside;
        if (c == Class::Inside) {
            if (i < 64) mask &= ~(ViewMask(1) << i);
        } else {
            mixed = true;
        }
    }
    return mixed ? Class::Mixed : Class::Inside;
}

namespace {

constexpr int kMaxIntervals = 64;

struct Intervals {
    double s[kMaxIntervals], e[kMaxIntervals];
    int n = 0;
    void add(double a, double b) {
        if (n < kMaxIntervals) s[n] = a, e[n] = b, ++n;
    }
};

void from_flips(bool start, const double* flips, int n, Intervals& out) {
    out.n = 0;
    bool cur = start;
    double pos = 0;
    for (int k = 0; k < n; ++k) {
        if (cur) out.add(pos, flips[k]);
        cur = !cur;
        pos = flips[k];
    }
    if (cur) out.add(pos, 1.0);
}

void intersect(const Intervals& a, const Intervals& b, Intervals& out) {
    out.n = 0;
    int i = 0, j = 0;
    while (i < a.n && j < b.n) {
        const double lo = std::max(a.s[i], b.s[j]), hi = std::min(a.e[i], b.e[j]);
        if (lo <= hi) out.add(lo, hi);
        if (a.e[i] < b.e[j]) ++i;
        else ++j;
    }
}

} // namespace

int VisualHull::transitions(const Vec3d& a, const Vec3d& b, bool& start, double* flips, int max_flips,
                            ViewMask mask) const {
    // A view that sees the whole segment outside settles it before any exact work; views
    // that see it all inside (or are masked out) need none.
    constexpr std::size_t kCached = 256;
    signed char cls[kCached];
    const std::size_t nv = fields_.size();
    for (std::size_t i = 0; i < nv; ++i) {
        const bool skip = i < 64 && !((mask >> i) & 1u);
        const Class c = skip ? Class::Inside : fields_[i].classify_segment(a, b);
        if (c == Class::Outside) {
            start = false;
            return 0;
        }
        if (i < kCached) cls[i] = static_cast<signed char>(c);
    }
    Intervals cur, view, tmp;
    // The clip box (slab test).
    double t0 = 0, t1 = 1;
    for (int k = 0; k < 3; ++k) {
        const double d = b[k] - a[k];
        if (d == 0) {
            if (a[k] < clip_lo_[k] || a[k] > clip_hi_[k]) t0 = 1, t1 = 0;
            continue;
        }
        double ta = (clip_lo_[k] - a[k]) / d, tb = (clip_hi_[k] - a[k]) / d;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta), t1 = std::min(t1, tb);
    }
    if (t0 <= t1) cur.add(t0, t1);
    start = in_clip(a);
    double local[256];
    for (std::size_t i = 0; i < nv && cur.n > 0; ++i) {
        const bool skip = i < 64 && !((mask >> i) & 1u);
        if (skip) continue;
        const Class c = i < kCached ? static_cast<Class>(cls[i]) : fields_[i].classify_segment(a, b);
        if (c == Class::Inside) continue;
        bool st = false;
        const int m = fields_[i].transitions(a, b, st, local, 256);
        start = start && st;
        from_flips(st, local, m, view);
        intersect(cur, view, tmp);
        cur = tmp;
    }
    if (cur.n == 0) {
        // Some view or the clip box leaves nothing inside; `start` must still say whether
        // a itself is inside (a point of zero length).
        start = start && inside(a, mask);
    }
    // Back to flips, consistent with `start`.
    int n = 0;
    auto emit = [&](double t) {
        if (n < max_flips) flips[n++] = t;
    };
    bool state = start;
    for (int k = 0; k < cur.n; ++k) {
        if (state && k == 0 && cur.s[0] > 0) emit(0.0), state = false;
        if (!state) emit(cur.s[k]), state = true;
        if (cur.e[k] < 1.0) emit(cur.e[k]), state = false;
    }
    if (cur.n == 0 && state) emit(0.0);
    return n;
}

} // namespace cm
