#include "geometry/visual_hull.h"

#include <algorithm>

#include <memory>

#include <tbb/parallel_for.h>

#include "core/error.h"

namespace cm {

namespace {

using Tables = std::vector<std::shared_ptr<const SilhouetteField::Table>>;

// The views' summed-area tables, made side by side by the first hull of a run and kept with
// the views (Views::derived) for the next: a run builds several hulls of the same views
// (carving's box estimate, the carving, the crossings), and each table is a serial pass
// over a whole image.
std::shared_ptr<const Tables> summed_areas(const Views& views) {
    return std::static_pointer_cast<const Tables>(views.derived.get("silhouette_sat", [&] {
        auto tables = std::make_shared<Tables>(views.views.size());
        tbb::parallel_for(std::size_t(0), views.views.size(), [&](std::size_t i) {
            (*tables)[i] = std::make_shared<const SilhouetteField::Table>(SilhouetteField::summed_area(views.views[i]));
        });
        return std::shared_ptr<const void>(std::move(tables));
    }));
}

} // namespace

VisualHull::VisualHull(const Views& views, Vec3d clip_lo, Vec3d clip_hi) : clip_lo_(clip_lo), clip_hi_(clip_hi) {
    if (views.views.empty()) throw Error("no views: the visual hull needs at least one view");
    const auto tables = summed_areas(views);
    fields_.reserve(views.views.size());
    for (std::size_t i = 0; i < views.views.size(); ++i) fields_.emplace_back(views.views[i], (*tables)[i]);
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
