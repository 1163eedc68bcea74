// Hard-surface detection (`hard_surface` of hull.plausible, mesh.laplacian_smooth and
// mesh.reduce): a machined part is drawn with long straight edges meeting at corners, a
// creature with curves. Where every drawing's outline runs mostly along straight lines the
// visual hull is the shape a modeller would build from the drawings (extrusions cut by one
// another): hull.plausible keeps it, and the mesh stages treat it as pipelines/paper.yaml
// treats the hull.
#pragma once
#include <vector>

#include "core/views.h"

namespace cm {

/// @brief The share in [0, 1] of a silhouette's outline that lies on a straight stretch: the
/// outline is sampled on a raster whose longest side spans the silhouette's box in
/// kStraightCells cells (or its pixels when fewer); an outline cell is on a straight stretch when the outline cells
/// within a tenth of that side lie within half a cell (rms) of one line. Curves of any
/// radius the silhouette's own size allows (a disc, an ellipse, a body's back) are not
/// straight at that reach; the edges of a box, a wedge or a machined part are. 0 for an
/// empty silhouette.
double outline_straightness(const View& view);

/// Cells along the silhouette box's longest side of outline_straightness()'s raster.
constexpr int kStraightCells = 460;

/// Whether a view is orthographic along one of the world's axes (front, right, top, ... or an
/// azimuth and elevation that are multiples of 90 degrees).
bool along_axis(const View& view);

/// @brief How hard-surfaced the views say the object is, in [0, 1]: a smooth step of the
/// least straight deciding view's share (from 0 at 0.06 to 1 at 0.12; a curved view rounds
/// the shape). The views along the world's axes decide when there are any (a machined
/// part's faces and edges are seen edge-on along its axes; seen obliquely, its outline
/// crowds more corners and shows its curved faces' contours: fandisk's oblique view at
/// azimuth 45, elevation 30 keeps 10.9 % of its outline straight, its top view 22.6 %);
/// otherwise every view does. `shares` gets each deciding view's outline_straightness().
double hard_surface(const Views& views, std::vector<double>& shares);

/// hard_surface() without the shares.
inline double hard_surface(const Views& views) {
    std::vector<double> shares;
    return hard_surface(views, shares);
}

} // namespace cm
