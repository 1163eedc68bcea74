// A border of more than one colour (a photograph on a backdrop with a cloth or a table edge
// reaching the frame): the colours of the border samples the smooth background field
// leaves out, clustered.
#pragma once
#include <array>
#include <vector>

namespace cm {

/// A further background colour seen along the image border.
struct BorderCluster {
    std::array<double, 3> colour{}; ///< mean RGB in [0, 1]
    double threshold = 0;           ///< colour distance (RMS over R, G, B) within which a pixel is this background
    double share = 0;               ///< fraction of the border samples it holds
};

/// @brief Clusters (k-means in RGB, up to two clusters) the border samples `outliers` that
/// the main background model does not explain, out of `total` border samples. A cluster
/// counts only when it holds at least `min_share` of the whole border; none when the
/// outliers together hold less. `base_threshold` is the main model's threshold, the least
/// a cluster's threshold can be. Deterministic (farthest-point seeding).
std::vector<BorderCluster> cluster_border(const std::vector<std::array<double, 3>>& outliers, std::size_t total,
                                          double base_threshold, double min_share = 0.1);

} // namespace cm
