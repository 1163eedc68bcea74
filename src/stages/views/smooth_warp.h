// A smooth, low-frequency displacement field over an image, for bending a drawn view
// (reconcile.h): a uniform cubic B-spline lattice (a free-form deformation, as image
// registration uses) fitted to a few wished displacements by regularised least squares.
// Internal to the views family.
#pragma once
#include <algorithm>
#include <array>
#include <vector>

#include "core/vec.h"

namespace cm {

/// One wish of the field: at pixel position `at`, the displacement `v`, weighed `weight`.
struct WarpTarget {
    Vec2d at;
    Vec2d v;
    double weight = 1;
};

/// A displacement field: a cubic B-spline of control displacements on a square lattice.
/// Zero where no target was given nearby: the lattice spans the given box and three
/// spacings beyond it, and its outer three rings of control points are held at zero, so
/// the field falls to zero smoothly (continuous to its second derivative) and is zero
/// beyond.
class WarpField {
public:
    WarpField() = default;
    /// A lattice of spacing h (pixels) over the box [x0, x1] x [y0, y1].
    WarpField(double x0, double y0, double x1, double y1, double h);
    /// The displacement at (x, y).
    Vec2d operator()(double x, double y) const;
    /// @brief Fits the free control points: the least squares of the targets (each
    /// weighed), plus `membrane` times the membrane energy of the lattice (the squared
    /// differences of neighbouring control points), which keeps the field low in frequency
    /// and brings it to zero away from the targets.
    void fit(const std::vector<WarpTarget>& targets, double membrane);
    /// The control points the fit sets (all but the three rings held at zero).
    int free_points() const { return std::max(0, nx_ - 6) * std::max(0, ny_ - 6); }
    /// The box beyond which the field is zero: x0, y0, x1, y1.
    std::array<double, 4> support() const;
    double spacing() const { return h_; }

private:
    double ox_ = 0, oy_ = 0, h_ = 1;
    int nx_ = 0, ny_ = 0;
    std::vector<Vec2d> c_; // control displacements, nx_ * ny_, row-major
};

} // namespace cm
