#include "geometry/visual_hull.h"

#include <algorithm>
#include <memory>

#include <tbb/parallel_for.h>

#include "core/error.h"

namespace cm {

bool SilhouetteTables::fit(const Views& views) const {
    if (tables.size() != views.views.size()) return false;
    // An empty table (no size) is what summed_area() gives a view without a usable silhouette,
    // which the view's field then refuses with the reason.
    for (std::size_t i = 0; i < tables.size(); ++i) {
        const SilhouetteField::Table& t = tables[i];
        if (t.width != 0 && !(t.width == views.views[i].width && t.height == views.views[i].height)) return false;
    }
    return true;
}

std::shared_ptr<const SilhouetteTables> silhouette_tables(const Views& views) {
    if (views.views.empty()) return nullptr;
    auto made = std::make_shared<SilhouetteTables>();
    made->tables.resize(views.views.size());
    tbb::parallel_for(std::size_t(0), views.views.size(),
                      [&](std::size_t i) { made->tables[i] = SilhouetteField::summed_area(views.views[i]); });
    return made;
}

VisualHull::VisualHull(const Views& views, Vec3d clip_lo, Vec3d clip_hi, std::shared_ptr<const SilhouetteTables> tables)
    : clip_lo_(clip_lo), clip_hi_(clip_hi), tables_(std::move(tables)) {
    if (views.views.empty()) throw Error("no views: the visual hull needs at least one view");
    if (!tables_) tables_ = silhouette_tables(views);
    else if (!tables_->fit(views))
        throw Error("the silhouette tables given to the visual hull are not those of its views");
    fields_.reserve(views.views.size());
    for (std::size_t i = 0; i < views.views.size(); ++i)
        fields_.emplace_back(views.views[i], SilhouetteTables::of(tables_, i));
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
