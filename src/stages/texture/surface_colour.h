// The colour of a surface point from the views that see it: each view's say is how
// squarely it sees the point (normal against the direction to the camera), its
// confidence there (view_colours.h) and the view's own weight (view_balance.h), and
// only views in which the point passes the depth test against the mesh itself take
// part, so the back of an object is not painted with its front. Views that agree are
// averaged; views that disagree by much more than `conflict_de` are not: the point takes
// the colour that costs the views the least (a robust weighted median in CIELAB), so
// no view is painted with a mixture that is wrong for all of them.
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
    double weight = 1;      ///< the view's own weight (view_balance.h), 1 unless balanced
};

struct SurfaceColourOptions {
    double angle_power = 2; ///< say = cos(angle)^angle_power
    /// Delta E scale of a disagreement between views: colours closer than this are averaged,
    /// farther ones decided (the minimum of sum say * sqrt(dE^2 + conflict_de^2), in CIELAB).
    /// 0: the weighted mean of the views' sRGB colours.
    double conflict_de = 0;
};

/// What one view says about a surface point.
struct ViewSample {
    int view = 0;                ///< index into the samplers
    std::array<float, 3> rgb{};  ///< sRGB colour of its (cleaned) drawing there
    std::array<double, 3> lab{}; ///< the same in CIELAB
    double say = 0;              ///< cos^angle_power * (floor + confidence)
    double weight = 1;           ///< the view's own weight (ViewSampler::weight)
    double facing = 0;           ///< cosine of the normal to the view
    bool drawn = false;          ///< the drawing has a colour there (confidence > 0: not ink, not the border)
};

constexpr int kMaxViewSamples = 32; ///< views beyond this many do not take part at one point

/// The views that see point p with unit normal n; returns how many were written to `out`
/// (kMaxViewSamples at most). Their CIELAB colours are filled in with `lab` or when
/// `opt.conflict_de` needs them.
int view_samples(const std::vector<ViewSampler>& views, const Vec3d& p, const Vec3d& n, const SurfaceColourOptions& opt,
                 ViewSample* out, bool lab = false);

/// The colour (sRGB) of `n` view samples (n >= 1), each weighing its say times its weight.
std::array<float, 3> combine_samples(const ViewSample* s, int n, const SurfaceColourOptions& opt);

/// sRGB colour (as drawn) of point p with unit normal n; false when no view sees it.
bool surface_colour(const std::vector<ViewSampler>& views, const Vec3d& p, const Vec3d& n,
                    const SurfaceColourOptions& opt, std::array<float, 3>& rgb);

/// Cosine between n and the direction from p to the camera of `cam`.
double facing(const Camera& cam, const Vec3d& p, const Vec3d& n);

/// True when p passes the depth test of the view (not hidden behind the mesh), given the
/// cosine `c` of its normal to the view (steep surfaces get more tolerance).
bool visible_in(const ViewSampler& v, const Vec3d& p, double c);

} // namespace cm
