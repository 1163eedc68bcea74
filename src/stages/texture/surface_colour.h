// The colour of a surface point from the views that see it: each view's say is how
// squarely it sees the point (normal against the direction to the camera) and its
// confidence there (view_colours.h), and only views in which the point passes the depth
// test against the mesh itself take part, so the back of an object is not painted with
// its front.
#pragma once
#include <array>
#include <vector>

#include "core/mesh.h"
#include "core/views.h"
#include "render/raster.h"
#include "view_colours.h"

namespace cm {

struct ViewSampler {
    const View* view = nullptr;
    DepthImage depth;
    ViewColours colours;
    double pixel_world = 1; ///< size of a pixel in world units at the object
};

struct SurfaceColourOptions {
    double angle_power = 2; ///< weight = cos(angle)^angle_power
};

/// sRGB colour (as drawn) of point p with unit normal n; false when no view sees it.
bool surface_colour(const std::vector<ViewSampler>& views, const Vec3d& p, const Vec3d& n,
                    const SurfaceColourOptions& opt, std::array<float, 3>& rgb);

/// Cosine between n and the direction from p to the camera of `cam`.
double facing(const Camera& cam, const Vec3d& p, const Vec3d& n);

/// True when p passes the depth test of the view (not hidden behind the mesh), given the
/// cosine `c` of its normal to the view (steep surfaces get more tolerance).
bool visible_in(const ViewSampler& v, const Vec3d& p, double c);

} // namespace cm
