// The visual hull as a point set: the intersection of every view's silhouette cone
// (the sub-pixel model of silhouette_field.h) with a clip box. hull.carve decides
// grid points and whole boxes with it; hull.marching_intersections finds where
// lattice edges enter and leave it. Both use this one definition, so the crossings
// always lie between an inside and an outside grid point.
#pragma once
#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include "geometry/silhouette_field.h"

namespace cm {

/// The summed-area tables of the silhouettes of one set of views (SilhouetteField::Table, one
/// per view), which every VisualHull of those views reads. Each is a pass over a whole image
/// and 4 bytes per pixel of its silhouette's box, so a run makes them once and hands them on
/// as data: hull.carve makes them for its hulls (the box estimate and the carving) and puts
/// them in its volume (Volume::silhouette_tables); the stages after it read them from there
/// and pass them on. They are freed with the last volume or hull that holds them.
struct SilhouetteTables {
    std::vector<SilhouetteField::Table> tables; ///< one per view, in the views' order
    /// Whether these are the tables of `views`: one per view, each of its view's image size
    /// (or empty, for a view without a usable silhouette).
    bool fit(const Views& views) const;
    /// The table of view i, sharing the ownership of these tables.
    static std::shared_ptr<const SilhouetteField::Table> of(const std::shared_ptr<const SilhouetteTables>& all,
                                                            std::size_t i) {
        return {all, &all->tables[i]};
    }
};

/// Makes the summed-area tables of `views` (the views side by side). Null for no views.
std::shared_ptr<const SilhouetteTables> silhouette_tables(const Views& views);

class VisualHull {
public:
    /// Builds the silhouette fields of every view; the hull is clipped to [clip_lo, clip_hi].
    /// `tables`: the views' silhouette tables (silhouette_tables(views)); null: made here.
    /// @throw cm::Error for no views, or tables that are not those of `views`.
    VisualHull(const Views& views, Vec3d clip_lo, Vec3d clip_hi,
               std::shared_ptr<const SilhouetteTables> tables = nullptr);

    using Class = SilhouetteField::Class;
    /// Bit i set: view i still needs testing. Views beyond 64 are always tested.
    using ViewMask = std::uint64_t;
    static constexpr ViewMask kAllViews = ~ViewMask(0);

    std::size_t size() const { return fields_.size(); }
    const SilhouetteField& field(std::size_t i) const { return fields_[i]; }
    const Vec3d& clip_lo() const { return clip_lo_; }
    const Vec3d& clip_hi() const { return clip_hi_; }
    /// The views' summed-area tables this hull reads.
    const std::shared_ptr<const SilhouetteTables>& tables() const { return tables_; }

    bool in_clip(const Vec3d& p) const {
        return p.x >= clip_lo_.x && p.y >= clip_lo_.y && p.z >= clip_lo_.z && p.x <= clip_hi_.x && p.y <= clip_hi_.y &&
               p.z <= clip_hi_.z;
    }
    /// Is the point inside the hull? Only the views in `mask` are tested.
    bool inside(const Vec3d& p, ViewMask mask = kAllViews) const {
        if (!in_clip(p)) return false;
        for (std::size_t i = 0; i < fields_.size(); ++i)
            if ((i >= 64 || (mask >> i) & 1u) && !fields_[i].inside(p)) return false;
        return true;
    }
    /// Conservative decision for the world box [lo, hi]. On return `mask` keeps only the
    /// views for which the box is Mixed (views that see it all inside need no more tests).
    Class classify(const Vec3d& lo, const Vec3d& hi, ViewMask& mask) const;

    /// Inside intervals of the segment a + t (b - a), t in [0, 1]: `start` is inside(a),
    /// `flips` the increasing t where the state toggles (at most `max_flips`). Views that
    /// see the segment all inside are skipped, and so are the views not in `mask` (the
    /// caller knows they see it all inside, e.g. from a box holding the segment).
    int transitions(const Vec3d& a, const Vec3d& b, bool& start, double* flips, int max_flips,
                    ViewMask mask = kAllViews) const;
    /// transitions() with each view's answers about the segment taken from `views`:
    /// views.classify(i) as field(i).classify_segment(a, b) and views.transitions(i, st,
    /// flips, max) as field(i).transitions(a, b, st, flips, max). A caller that knows a view's
    /// answers already (from another segment with the same projection in that view) gives them
    /// again without the view's work; the result is the same.
    template <typename Views>
    int transitions(const Vec3d& a, const Vec3d& b, bool& start, double* flips, int max_flips, ViewMask mask,
                    Views&& views) const;

private:
    std::vector<SilhouetteField> fields_;
    Vec3d clip_lo_, clip_hi_;
    std::shared_ptr<const SilhouetteTables> tables_;
};

namespace hull_detail {

constexpr int kMaxIntervals = 64;

struct Intervals {
    double s[kMaxIntervals], e[kMaxIntervals];
    int n = 0;
    void add(double a, double b) {
        if (n < kMaxIntervals) s[n] = a, e[n] = b, ++n;
    }
};

inline void from_flips(bool start, const double* flips, int n, Intervals& out) {
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

inline void intersect(const Intervals& a, const Intervals& b, Intervals& out) {
    out.n = 0;
    int i = 0, j = 0;
    while (i < a.n && j < b.n) {
        const double lo = std::max(a.s[i], b.s[j]), hi = std::min(a.e[i], b.e[j]);
        if (lo <= hi) out.add(lo, hi);
        if (a.e[i] < b.e[j]) ++i;
        else ++j;
    }
}

} // namespace hull_detail

template <typename Views>
int VisualHull::transitions(const Vec3d& a, const Vec3d& b, bool& start, double* flips, int max_flips, ViewMask mask,
                            Views&& views) const {
    using hull_detail::Intervals;
    // A view that sees the whole segment outside settles it before any exact work; views
    // that see it all inside (or are masked out) need none.
    constexpr std::size_t kCached = 256;
    signed char cls[kCached];
    const std::size_t nv = fields_.size();
    for (std::size_t i = 0; i < nv; ++i) {
        const bool skip = i < 64 && !((mask >> i) & 1u);
        const Class c = skip ? Class::Inside : views.classify(i);
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
        const Class c = i < kCached ? static_cast<Class>(cls[i]) : views.classify(i);
        if (c == Class::Inside) continue;
        bool st = false;
        const int m = views.transitions(i, st, local, 256);
        start = start && st;
        hull_detail::from_flips(st, local, m, view);
        hull_detail::intersect(cur, view, tmp);
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
