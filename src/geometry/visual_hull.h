// The visual hull as a point set: the intersection of every view's silhouette cone
// (the sub-pixel model of silhouette_field.h) with a clip box. hull.carve decides
// grid points and whole boxes with it; hull.marching_intersections finds where
// lattice edges enter and leave it. Both use this one definition, so the crossings
// always lie between an inside and an outside grid point.
#pragma once
#include <cstdint>
#include <vector>

#include "geometry/silhouette_field.h"

namespace cm {

class VisualHull {
public:
    /// Builds the silhouette fields of every view; the hull is clipped to [clip_lo, clip_hi].
    VisualHull(const Views& views, Vec3d clip_lo, Vec3d clip_hi);

    using Class = SilhouetteField::Class;
    /// Bit i set: view i still needs testing. Views beyond 64 are always tested.
    using ViewMask = std::uint64_t;
    static constexpr ViewMask kAllViews = ~ViewMask(0);

    std::size_t size() const { return fields_.size(); }
    const SilhouetteField& field(std::size_t i) const { return fields_[i]; }
    const Vec3d& clip_lo() const { return clip_lo_; }
    const Vec3d& clip_hi() const { return clip_hi_; }

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

private:
    std::vector<SilhouetteField> fields_;
    Vec3d clip_lo_, clip_hi_;
};

} // namespace cm
