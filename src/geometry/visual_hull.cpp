#include "geometry/visual_hull.h"

#include <algorithm>

#include <memory>
#include <mutex>

#include <tbb/collaborative_call_once.h>
#include <tbb/parallel_for.h>

#include "core/error.h"

namespace cm {

namespace {

using Tables = std::vector<std::shared_ptr<const SilhouetteField::Table>>;

// The views' summed-area tables are made side by side by the first hull that asks and shared
// by every hull of the same views while something holds them (a run builds several: carving's
// box estimate, the carving, the crossings, and each table is a pass over a whole image).
// The views hold them only weakly (Views::derived): once the last holder goes, their 4 bytes
// per pixel of each silhouette's box are freed (up to 50 MB for three 2048 px views, kept
// through smoothing and reduction before). A generation is one making of them; a new one
// starts when the last has been let go.
struct TableGeneration {
    tbb::collaborative_once_flag once;
    std::weak_ptr<const Tables> tables;
};
struct TableCache { // shared as const by Views::derived; used only under its mutex
    mutable std::mutex mutex;
    mutable std::shared_ptr<TableGeneration> current;
};

std::shared_ptr<const Tables> summed_areas(const Views& views) {
    const auto cache = std::static_pointer_cast<const TableCache>(views.derived.get(
        "silhouette_sat", [] { return std::shared_ptr<const void>(std::make_shared<TableCache>()); }));
    const TableCache& c = *cache;
    for (;;) {
        std::shared_ptr<TableGeneration> gen;
        {
            std::lock_guard<std::mutex> lock(c.mutex);
            if (!c.current) c.current = std::make_shared<TableGeneration>();
            gen = c.current;
        }
        std::shared_ptr<const Tables> made;
        tbb::collaborative_call_once(gen->once, [&] {
            auto tables = std::make_shared<Tables>(views.views.size());
            tbb::parallel_for(std::size_t(0), views.views.size(), [&](std::size_t i) {
                (*tables)[i] =
                    std::make_shared<const SilhouetteField::Table>(SilhouetteField::summed_area(views.views[i]));
            });
            made = std::move(tables);
            gen->tables = made;
        });
        if (made) return made;
        if (auto held = gen->tables.lock()) return held;
        // Let go since: the next asker of this generation starts the next.
        std::lock_guard<std::mutex> lock(c.mutex);
        if (c.current == gen) c.current.reset();
    }
}

} // namespace

std::shared_ptr<const void> silhouette_tables(const Views& views) {
    if (views.views.empty()) return nullptr;
    return summed_areas(views);
}

VisualHull::VisualHull(const Views& views, Vec3d clip_lo, Vec3d clip_hi) : clip_lo_(clip_lo), clip_hi_(clip_hi) {
    if (views.views.empty()) throw Error("no views: the visual hull needs at least one view");
    const auto tables = summed_areas(views);
    tables_ = tables;
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
