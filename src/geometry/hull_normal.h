// The exact surface normal of the visual hull at a point of its boundary. The hull's
// boundary near a point is the boundary of one view's silhouette cone (or a face of the
// clip box): for an orthographic view, the outline's 2D normal lifted into 3D
// (perpendicular to the view direction); for a perspective view, the normal of the plane
// through the camera centre and the outline's tangent. Both are the gradient of the view's
// coverage pulled back through its projection, which is what is computed here.
#pragma once
#include <memory>

#include "geometry/visual_hull.h"

namespace cm {

struct HullNormal {
    Vec3d normal;    ///< outward unit normal; zero when no view has an outline near the point
    int view = -1;   ///< the view whose cone bounds the hull at the point; -1 for the clip box
    double distance; ///< first-order distance (world units) from the point to that boundary
};

/// @brief The outward normal of the hull's boundary nearest to `p` (a crossing found by
/// hull.marching_intersections lies on it): of all views' outlines (the 0.5 iso-line of
/// the bilinear coverage, as in silhouette_field.h) and the clip box's faces, the one
/// nearest to `p` in world units.
/// @param smooth_px 0: the outline's normal at the point (exact for the silhouette model:
/// of a binary mask, a pixel staircase). > 0: the outline's direction averaged over a disc
/// of that radius in pixels (the first moment of the coverage), which follows the drawn
/// shape rather than its pixels; symmetric, so straight edges and circles keep their
/// exact normals.
HullNormal hull_normal(const VisualHull& hull, const Vec3d& p, double smooth_px = 0);

} // namespace cm
