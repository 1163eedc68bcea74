// Approximate signed distance to the visual hull of a set of views, for stages
// that must keep a surface on the drawn outline (hull-constrained smoothing).
//
// The visual hull is the intersection of the silhouette cones, so a point is
// outside it as soon as one view sees it outside its silhouette. Per view we
// keep a 2D signed distance field of the silhouette (pixels, positive outside),
// and the hull's signed distance at p is approximated by the largest of the
// views' distances at p's projections, each converted to world units with the
// view's pixel size at p. Outside the hull this is a lower bound of the true
// distance; on the hull's surface it is zero; inside it is the distance to the
// nearest silhouette border seen by any view (the shallowest one).
#pragma once
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/vec.h"
#include "core/views.h"
#include "util/uninit_vector.h"

namespace cm {

class SdfBeyondWindow;

/// Signed distance field of one silhouette, in pixels, positive outside.
///
/// Stored for a window of the image: the box of the inside pixels grown by kSdfMargin
/// (clipped to the image), where every caller's points project (a point near the visual hull
/// projects near each silhouette). The window holds the values of the inside pixels and of
/// the outside ones within kSdfReach of an inside one, which is where the smoothing and the
/// reduction read (at most a few pixels out); its other pixels hold NaN. The values are the
/// whole image's, to the bit: the nearest inside pixel of an outside pixel lies in the box, and
/// the nearest outside pixel of an inside one is at most as far as the window's border, which
/// is outside. A sample that reads a NaN pixel or one beyond the window builds the rest of the
/// field (of the window, of the image) on first use.
struct SilhouetteSdf {
    static constexpr int kSdfMargin = 32;     ///< pixels around the inside pixels' box
    static constexpr int kSdfReach = 8;       ///< how far out the window holds the outside pixels' values
    int width = 0, height = 0;                ///< the image
    int ox = 0, oy = 0, stride = 0, rows = 0; ///< the window: its first column and row, its size
    UninitVector<float> sdf;                  ///< the window's values at pixel centres, row-major, row 0 at the top
    /// The field at the window's NaN pixels and beyond the window (null: the window is the
    /// image and holds every value).
    std::shared_ptr<const SdfBeyondWindow> beyond;
    /// Bilinear sample at continuous pixel coordinates (x, y) (pixel centres at i + 0.5);
    /// beyond the image the distance grows with the distance to the image border.
    /// Inline for the common case (the four samples inside the window): the smoothing and the
    /// reduction's outline guard ask it hundreds of millions of times at 2048.
    double sample(double x, double y) const {
        const double fx = x - 0.5 - ox, fy = y - 0.5 - oy; // window pixel-centre lattice coordinates
        if (fx >= 0 && fy >= 0 && fx < double(stride - 1) && fy < double(rows - 1)) {
            const int x0 = int(fx), y0 = int(fy);
            const double tx = fx - x0, ty = fy - y0;
            const float* r0 = sdf.data() + std::size_t(y0) * std::size_t(stride) + std::size_t(x0);
            const float* r1 = r0 + stride;
            const double v = (1 - ty) * ((1 - tx) * double(r0[0]) + tx * double(r0[1])) +
                             ty * ((1 - tx) * double(r1[0]) + tx * double(r1[1]));
            if (!std::isnan(v)) return v; // else a pixel not worked out, far outside
        }
        return sample_edge(x, y);
    }
    /// sample() anywhere: on the window's last row or column, beyond it, beyond the image, at
    /// a pixel not worked out, or not finite.
    double sample_edge(double x, double y) const;
    /// The value at pixel (i, j) of the image.
    float at(int i, int j) const;
};

/// @brief Builds the signed distance field of a coverage mask: the border is where
/// coverage crosses 0.5. Exact Euclidean distance transform of the binary mask
/// (squared_edt_signed()), with pixels of fractional coverage refined to 0.5 - coverage (the
/// sub-pixel position of a straight border through the pixel).
/// @throw cm::Error when the mask has no inside pixel.
SilhouetteSdf silhouette_sdf(const Coverage& coverage, const std::string& view_name);
/// The same from every pixel's coverage (width * height, row-major).
SilhouetteSdf silhouette_sdf(const std::vector<float>& coverage, int width, int height, const std::string& view_name);

/// A view's camera and the signed distance field of its drawing.
struct ViewSdf {
    Camera camera;
    SilhouetteSdf sdf;
};

/// The fields of every view, built side by side (each is parallel inside too).
/// @throw cm::Error naming the first view in order whose silhouette is empty.
std::vector<ViewSdf> view_sdfs(const Views& views);

class HullDistance {
public:
    /// Builds the views' fields (view_sdfs()).
    /// @throw cm::Error naming the view when a view has an empty silhouette.
    explicit HullDistance(const Views& views);
    /// Approximate signed distance from p to the visual hull in world units (positive outside).
    double operator()(const Vec3d& p) const;
    /// Whether |(*this)(p)| <= bound, stopping at the first view that puts p farther out
    /// than `bound` (the same answer, cheaper where p is outside). The view at index
    /// `first` is asked first, and `first` becomes the view that said no: a caller asking
    /// about nearby points in turn (a bisection) meets the binding view at once.
    bool within(const Vec3d& p, double bound, std::size_t& first) const;
    /// Asks the memory for the distance samples near p's projections (no effect on any
    /// answer): a caller going through points in turn names one a few points ahead, so the
    /// fields' rows are in cache when they are read.
    void prefetch(const Vec3d& p) const;
    /// Pixel size of the finest view, world units.
    double finest_pixel() const { return finest_pixel_; }

    // Per view, for callers that know some views are far inside at a point (a vertex deep
    // inside a view's silhouette moves a little and is still deep inside it): the max of
    // operator() over a subset of the views, the subset as a bit set (bit i: view i).
    using ViewMask = std::uint32_t;
    std::size_t view_count() const { return fields().size(); }
    /// All views; views beyond the 32 a mask holds are always asked.
    ViewMask all_views() const { return fields().size() >= 32 ? ~ViewMask(0) : (ViewMask(1) << fields().size()) - 1; }
    /// View i's signed distance at p, world units (operator() is the largest of these).
    double view_distance(std::size_t i, const Vec3d& p) const { return view_distance(fields()[i], p); }
    /// How much a view's distance can change per world unit p moves, for the views whose
    /// distance at p can be bounded so (orthographic ones); 0 for the others, which a caller
    /// must always ask. The fields are bilinear samples of an exact distance transform,
    /// refined within half a pixel of the border: at most 2 per pixel along a pixel edge, so
    /// at most 2 sqrt(2) per pixel in any direction; 4 leaves room for rounding.
    double lipschitz(std::size_t i) const { return i < 32 && fields()[i].camera.orthographic() ? 4.0 : 0.0; }
    /// The largest distance over the views in `views` (minus infinity when there is none).
    double distance(const Vec3d& p, ViewMask views) const;
    /// within() over the views in `views`: false as soon as one of them puts p farther out
    /// than `bound`; otherwise their largest distance, in `largest`, decides.
    bool within(const Vec3d& p, double bound, std::size_t& first, ViewMask views, double& largest) const;
    /// prefetch() for the views in `views`.
    void prefetch(const Vec3d& p, ViewMask views) const;

private:
    using Entry = ViewSdf;
    // View e's distance at p in world units. Inline for orthographic views (the smoothing asks
    // it millions of times a run).
    double view_distance(const Entry& e, const Vec3d& p) const {
        if (!e.camera.orthographic()) return perspective_distance(e, p);
        const Vec2d q = e.camera.project(p);
        return e.sdf.sample(q.x, q.y) * (1.0 / e.camera.scale);
    }
    double perspective_distance(const Entry& e, const Vec3d& p) const;
    const std::vector<Entry>& fields() const { return fields_; }
    std::vector<Entry> fields_;
    double finest_pixel_ = 1.0;
};

} // namespace cm
