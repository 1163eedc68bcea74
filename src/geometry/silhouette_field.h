// The sub-pixel silhouette model shared by the visual hull stages (hull.carve and
// hull.marching_intersections), so that occupancy and crossings agree exactly.
//
// Model: the coverage of pixel (i, j) is a sample at its centre (i + 0.5, j + 0.5);
// between centres it is interpolated bilinearly, and beyond the image the border
// pixels extend (clamp to edge, so an object cut by the image border stays cut
// open rather than carved). A continuous image point is inside when the
// interpolated coverage is >= 0.5: the silhouette boundary is the 0.5 iso-line. A
// world point is inside a view when its projection is; a point at or behind a
// perspective camera's plane is outside.
//
// Whole regions are decided at once through a summed-area table of the pixels with
// coverage >= 0.5: the interpolated coverage over a rectangle is bounded by the
// pixels whose centres span it, so a rectangle whose support pixels are all inside
// (all outside) is inside (outside) everywhere. A box in space is decided from the
// bounding rectangle of its projected corners (exact for orthographic views, and
// for perspective views when the box is in front of the camera).
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/vec.h"
#include "core/views.h"
#include "util/uninit_vector.h"

namespace cm {

class SilhouetteField {
public:
    /// The summed-area table of a view's silhouette: the count of the pixels with coverage
    /// >= 0.5 above and left of each pixel corner (x, y), 0 <= x <= width, 0 <= y <= height.
    /// Stored over the bounding box of those pixels only: beyond it the counts repeat the
    /// box's edge (no pixel there adds to them), so a corner clamped into the box reads the
    /// same count. For a drawing that fills a third of its image that is a third of the
    /// memory and of the work. Empty (`valid()` false) when the coverage does not match the
    /// view's size; the field then refuses the view.
    struct Table {
        UninitVector<std::uint32_t> counts; ///< (box_w + 1) x (box_h + 1), row-major
        int width = 0, height = 0;          ///< the image's size
        int box_x = 0, box_y = 0, box_w = 0, box_h = 0;
        bool valid() const { return counts.size() == std::size_t(box_w + 1) * std::size_t(box_h + 1); }
        bool of(int w, int h) const { return valid() && width == w && height == h; }
        /// The count at image corner (x, y) (any integers: clamped to the image as well).
        std::uint32_t at(int x, int y) const {
            x = std::clamp(x - box_x, 0, box_w);
            y = std::clamp(y - box_y, 0, box_h);
            return counts[std::size_t(y) * std::size_t(box_w + 1) + std::size_t(x)];
        }
        std::size_t bytes() const { return counts.size() * sizeof(std::uint32_t); }
    };
    static Table summed_area(const View& view);

    /// Keeps a reference to `view` (its coverage must outlive the field).
    explicit SilhouetteField(const View& view);
    /// The same with the view's summed_area() made already (shared by the fields of one view).
    SilhouetteField(const View& view, std::shared_ptr<const Table> table);

    enum Class : int { Outside = -1, Mixed = 0, Inside = 1 };

    /// Interpolated coverage at continuous pixel coordinates (clamp to edge).
    double coverage(double x, double y) const;
    /// Homogeneous projection: pixel (h[0]/h[2], h[1]/h[2]); h[2] is 1 for orthographic views.
    std::array<double, 3> project_h(const Vec3d& p) const {
        return {m_[0] * p.x + m_[1] * p.y + m_[2] * p.z + m_[3], m_[4] * p.x + m_[5] * p.y + m_[6] * p.z + m_[7],
                m_[8] * p.x + m_[9] * p.y + m_[10] * p.z + m_[11]};
    }
    /// Is the world point inside this view's silhouette cone?
    bool inside(const Vec3d& p) const {
        const auto h = project_h(p);
        if (h[2] <= kMinDepth) return false;
        return coverage(h[0] / h[2], h[1] / h[2]) >= 0.5;
    }
    /// Conservative decision for the axis-aligned world box [lo, hi].
    Class classify_box(const Vec3d& lo, const Vec3d& hi) const;
    /// Conservative decision for the segment [a, b] (its projection is a segment too).
    Class classify_segment(const Vec3d& a, const Vec3d& b) const;
    /// Conservative decision for the pixel rectangle [x0, x1] x [y0, y1].
    Class classify_rect(double x0, double y0, double x1, double y1) const;

    /// The points along the segment a + t (b - a), t in [0, 1], where inside() changes:
    /// `start` is inside(a) (the same test hull.carve uses), `flips` the increasing t
    /// where the state toggles (found exactly on the bilinear model: within a cell of
    /// pixel centres the coverage along a line is a quadratic). Returns the count.
    int transitions(const Vec3d& a, const Vec3d& b, bool& start, double* flips, int max_flips) const;

    /// World size of one pixel near `p` (orthographic: 1/scale).
    double pixel_size_at(const Vec3d& p) const;

    /// The world axis (0, 1, 2) along which the projection is constant (an orthographic
    /// view along a world axis), or -1: then a whole line of grid points shares one test.
    int drop_axis() const { return drop_axis_; }

    const View& view() const { return *view_; }
    int width() const { return w_; }
    int height() const { return h_; }

    static constexpr double kMinDepth = 1e-9;

private:
    float pix(int i, int j) const {
        i = i < 0 ? 0 : (i >= w_ ? w_ - 1 : i);
        j = j < 0 ? 0 : (j >= h_ ? h_ - 1 : j);
        return cov_->at(i, j);
    }
    // Transitions of the 2D segment p0 -> p1 in pixel coordinates, s in [0, 1].
    int transitions_2d(double x0, double y0, double x1, double y1, bool start, double* flips, int max_flips) const;

    const View* view_;
    const Coverage* cov_;
    int w_, h_;
    std::array<double, 12> m_{};       ///< 3x4 projection; orthographic third row is (0,0,0,1)
    std::shared_ptr<const Table> sat_; ///< summed_area(view)
    int drop_axis_ = -1;
};

} // namespace cm
