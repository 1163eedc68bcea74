// The outline guard of mesh.reduce (`constrain: silhouette`): a collapse may not move the
// mesh's outline in any view more than a tolerance away from the drawn silhouette.
//
// A half-edge collapse of v into w keeps every other vertex where it is, so what a view sees
// changes only around v: the region its old faces covered and its new faces (v replaced by
// w) do not cover is lost, and the new faces may reach beyond the old. Per view:
//  - recession: when v's projection is not covered by the new faces' projections, the
//    outline there moves to the nearest covered point q; refused when q lies more than the
//    tolerance inside the drawn silhouette and deeper than v does;
//  - growth: points along the new edges (w to each vertex of v's ring) must not lie more
//    than the tolerance outside the drawn silhouette, nor farther out than their ends.
// Distances are read from each view's signed distance field (src/geometry/hull_distance.h),
// in that view's pixels, against the drawing itself, so the steps do not add up.
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/views.h"
#include "geometry/hull_distance.h"

namespace cm {

namespace decimate {
class Collapser;

/// A point on a view's image, in pixels. Trivially constructible, unlike Vec2d: the guard holds
/// an array of them per collapse asked about, which would otherwise be zeroed every time.
struct ImagePoint {
    double x, y;
};

/// @brief Whether the faces around a vertex seen at `pv` on an image and the faces a collapse
/// puts in their place cover the same region of it, shown by their orientations alone: then
/// the collapse leaves what the view sees, and so its outline, as it is. Face i around the
/// vertex is (pv, ring[i], ring[next[i]]), the nr faces one cycle; the nt new faces are
/// `tris` (indices into `ring`; the faces at the ring vertex taken are gone). True when every
/// face, old and new, turns the same way on the image, by a margin (relative to `reach2`, the
/// ring's squared reach from pv); false otherwise (not necessarily a change).
bool same_cover(const ImagePoint& pv, const ImagePoint* ring, const int* next, int nr, const std::array<int, 3>* tris,
                int nt, double reach2);
} // namespace decimate

class OutlineGuard {
public:
    /// @throw cm::Error naming the view when a view has an empty silhouette.
    OutlineGuard(const Views& views, double tolerance_px);
    /// The views' distances at the vertices of one collapse run's mesh, kept as they are
    /// first asked: a collapse moves no vertex, so each vertex is sampled once per view.
    class Samples {
    public:
        Samples(std::size_t vertices, std::size_t views)
            : d_(vertices * views, std::numeric_limits<double>::quiet_NaN()), views_(views) {}
        template <typename Sample>
        double at(std::uint32_t v, std::size_t view, Sample&& sample) {
            double& d = d_[std::size_t(v) * views_ + view];
            if (std::isnan(d)) d = sample();
            return d;
        }

    private:
        std::vector<double> d_;
        std::size_t views_;
    };
    std::size_t view_count() const { return views_.size(); }
    /// Whether collapsing v into its neighbour w keeps every view's outline within the
    /// tolerance of the drawing (see above). `samples` (optional): the run's samples at the
    /// vertices (the same answers, each vertex's samples read once).
    bool keeps(const decimate::Collapser& c, std::uint32_t v, std::uint32_t w, Samples* samples = nullptr) const;

private:
    using Entry = ViewSdf;
    std::vector<Entry> views_;
    double tol_;
};

} // namespace cm
