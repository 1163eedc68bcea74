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

int VisualHull::transitions(const Vec3d& a, const Vec3d& b, bool& start, double* flips, int max_flips,
                            ViewMask mask) const {
    // Every answer asked of the view itself.
    struct Direct {
        const VisualHull& hull;
        const Vec3d &a, &b;
        Class classify(std::size_t i) const { return hull.fields_[i].classify_segment(a, b); }
        int transitions(std::size_t i, bool& st, double* out, int max) const {
            return hull.fields_[i].transitions(a, b, st, out, max);
        }
    };
    return transitions(a, b, start, flips, max_flips, mask, Direct{*this, a, b});
}

} // namespace cm
