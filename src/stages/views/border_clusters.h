// A border of more than one colour (a photograph on a backdrop with a cloth or a table edge
// reaching the frame): the colours of the border samples the smooth background field
// leaves out, clustered.
#pragma once
#include <array>
#include <vector>

#include "io/image_io.h"

namespace cm {

/// A further background colour seen along the image border: a colour with its own spread
/// (a cloth varies along its folds' light and dark far more than in hue).
struct BorderCluster {
    std::array<double, 3> colour{};  ///< mean RGB in [0, 1]
    std::array<double, 9> inverse{}; ///< inverse covariance of its samples (widened by 0.01^2 per channel)
    double threshold = 0;            ///< distance() within which a pixel is this background
    double share = 0;                ///< fraction of the border samples it holds
    /// Mahalanobis distance of `c` from the colour: in units of the samples' spread.
    double distance(const std::array<double, 3>& c) const;
};

/// @brief Clusters (k-means in RGB, up to three clusters) the border samples `outliers` that
/// the main background model does not explain, out of `total` border samples. A cluster
/// counts only when it holds at least `min_share` of the whole border; none when the
/// outliers together hold less. Clusters closer than `base_threshold` (the main model's
/// threshold), or than the sum of their 90th-percentile radii, are one (a cloth's folds and
/// grain split by k-means are one background). Distances to a cluster are Mahalanobis
/// distances under its samples' covariance. Its threshold follows its own spread (3 x the
/// median, 1.5 x the 90th percentile distance of its samples, at least 3) and stays under
/// half the way to `main` (the main background colour) and to the other clusters.
/// Deterministic (farthest-point seeding).
std::vector<BorderCluster> cluster_border(const std::vector<std::array<double, 3>>& outliers, std::size_t total,
                                          double base_threshold, const std::array<double, 3>& main,
                                          double min_share = 0.2);

/// @brief The pixels of `img` (RGBA, row-major) within the cluster's threshold of its
/// colour and 4-connected to the image border through such pixels: where that background
/// reaches. A patch of its colour inside the object (a shaded part) is not reached.
std::vector<char> cluster_reach(const Image& img, const BorderCluster& c);

} // namespace cm
