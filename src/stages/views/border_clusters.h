// A border of more than one colour (a photograph on a backdrop with a cloth or a table edge
// reaching the frame): the colours of the border samples the smooth background field
// leaves out, clustered.
#pragma once
#include <array>
#include <vector>

#include "io/image_io.h"

namespace cm {

/// A further background colour seen along the image border.
struct BorderCluster {
    std::array<double, 3> colour{}; ///< mean RGB in [0, 1]
    double threshold = 0;           ///< colour distance (RMS over R, G, B) within which a pixel is this background
    double share = 0;               ///< fraction of the border samples it holds
};

/// @brief Clusters (k-means in RGB, up to three clusters) the border samples `outliers` that
/// the main background model does not explain, out of `total` border samples. A cluster
/// counts only when it holds at least `min_share` of the whole border; none when the
/// outliers together hold less. Clusters closer than `base_threshold` (the main model's
/// threshold) are one. A cluster's threshold follows its own spread (3 x its median, 1.5 x
/// its 90th percentile distance) and stays under half the way to `main` (the main
/// background colour) and to the other cluster. Deterministic (farthest-point seeding).
std::vector<BorderCluster> cluster_border(const std::vector<std::array<double, 3>>& outliers, std::size_t total,
                                          double base_threshold, const std::array<double, 3>& main,
                                          double min_share = 0.2);

/// @brief The pixels of `img` (RGBA, row-major) within the cluster's threshold of its
/// colour and 4-connected to the image border through such pixels: where that background
/// reaches. A patch of its colour inside the object (a shaded part) is not reached.
std::vector<char> cluster_reach(const Image& img, const BorderCluster& c);

} // namespace cm
