// The coarse voxel grid reconciliation measures agreement on: each axis view's silhouette
// sampled on the box's cells, views seeing along one line of sight merged, and the share of
// each drawing whose lines of sight the other views cut away entirely.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/vec.h"

namespace cm {

/// The box cut into cells: n[k] cells of size h[k] along world axis k from lo.
struct ReconcileGrid {
    std::array<int, 3> n{0, 0, 0};
    std::array<double, 3> h{0, 0, 0};
    Vec3d lo;
    /// The box lo..lo+size cut into cells of about longest/cells along every axis.
    static ReconcileGrid over(const Vec3d& lo, const Vec3d& size, int cells);
    Vec3d centre(int i, int j, int k) const {
        return {lo.x + (i + 0.5) * h[0], lo.y + (j + 0.5) * h[1], lo.z + (k + 0.5) * h[2]};
    }
};

/// A mask over two world axes a < b of the grid (the image of an axis view, whatever its
/// direction): cell (i, j) at i + n[a] * j.
struct AxisMask {
    int a = 0, b = 1;
    std::vector<std::uint8_t> in;
};

/// Samples a view onto the grid: `inside(p)` says whether world point p (its coordinate
/// along the view's line of sight is the box's middle) lies in the silhouette.
AxisMask sample_mask(const ReconcileGrid& g, int a, int b, const std::function<bool(const Vec3d&)>& inside);

/// Merges the masks of views with one line of sight: "union", "intersect", or "primary"
/// (the first mask).
AxisMask merge_masks(const std::vector<const AxisMask*>& masks, const std::string& mode);

/// The cells of `own` (a view's mask) whose line of sight holds no cell inside every one of
/// `groups` (the merged masks of all lines of sight): what the views' hull leaves out of the
/// drawing. Flags per cell of `own`.
std::vector<std::uint8_t> missing_cells(const ReconcileGrid& g, const AxisMask& own,
                                        const std::vector<const AxisMask*>& groups);

/// The share of the grid's cells inside every one of `groups`: the hull's volume.
double hull_share(const ReconcileGrid& g, const std::vector<const AxisMask*>& groups);

/// Chamfer distance, in cells, from every cell of a mask to its nearest inside cell.
std::vector<float> distance_to_mask(const ReconcileGrid& g, const AxisMask& m);

} // namespace cm
