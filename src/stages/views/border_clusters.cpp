#include "border_clusters.h"
#include "pixel_flood.h"

#include <algorithm>
#include <cmath>

namespace cm {

namespace {

using Rgb = std::array<double, 3>;

double rms(const Rgb& a, const Rgb& b) {
    const double dr = a[0] - b[0], dg = a[1] - b[1], db = a[2] - b[2];
    return std::sqrt((dr * dr + dg * dg + db * db) / 3.0);
}

// Lloyd iterations from the given centres; `member` gets each sample's cluster.
void lloyd(const std::vector<Rgb>& s, std::vector<Rgb>& centre, std::vector<int>& member) {
    member.assign(s.size(), 0);
    for (int iter = 0; iter < 20; ++iter) {
        for (std::size_t i = 0; i < s.size(); ++i) {
            int best = 0;
            for (int k = 1; k < int(centre.size()); ++k)
                if (rms(s[i], centre[std::size_t(k)]) < rms(s[i], centre[std::size_t(best)])) best = k;
            member[i] = best;
        }
        std::vector<Rgb> sum(centre.size(), Rgb{});
        std::vector<std::size_t> count(centre.size(), 0);
        for (std::size_t i = 0; i < s.size(); ++i) {
            for (int c = 0; c < 3; ++c) sum[std::size_t(member[i])][std::size_t(c)] += s[i][std::size_t(c)];
            ++count[std::size_t(member[i])];
        }
        for (std::size_t k = 0; k < centre.size(); ++k)
            if (count[k])
                for (int c = 0; c < 3; ++c) centre[k][std::size_t(c)] = sum[k][std::size_t(c)] / double(count[k]);
    }
}

} // namespace

std::vector<BorderCluster> cluster_border(const std::vector<Rgb>& outliers, std::size_t total, double base_threshold,
                                          const Rgb& main, double min_share) {
    std::vector<BorderCluster> out;
    if (total == 0 || double(outliers.size()) < min_share * double(total)) return out;
    // Seeds: the first sample, then twice the sample farthest from the seeds so far (when
    // it is farther than the threshold): up to three clusters, so an object touching the
    // border gets a cluster of its own (too small to count) and does not pull the others.
    std::vector<Rgb> centre{outliers[0]};
    for (int extra = 0; extra < 2; ++extra) {
        std::size_t far = 0;
        double far_d = -1;
        for (std::size_t i = 0; i < outliers.size(); ++i) {
            double d = 1e9;
            for (const auto& c : centre) d = std::min(d, rms(outliers[i], c));
            if (d > far_d) {
                far_d = d;
                far = i;
            }
        }
        if (far_d > base_threshold) centre.push_back(outliers[far]);
    }
    std::vector<int> member;
    lloyd(outliers, centre, member);
    for (std::size_t k = 0; k < centre.size(); ++k) {
        std::vector<double> d;
        for (std::size_t i = 0; i < outliers.size(); ++i)
            if (member[i] == int(k)) d.push_back(rms(outliers[i], centre[k]));
        const double share = double(d.size()) / double(total);
        if (share < min_share) continue;
        std::sort(d.begin(), d.end());
        const double median = d[d.size() / 2], p90 = d[std::min(d.size() - 1, d.size() * 9 / 10)];
        BorderCluster c;
        c.colour = centre[k];
        c.share = share;
        // The cluster's own spread, and at most half-way to the main background (or another
        // cluster would swallow it).
        double room = 0.5 * rms(centre[k], main);
        for (std::size_t j = 0; j < centre.size(); ++j)
            if (j != k) room = std::min(room, 0.5 * rms(centre[k], centre[j]));
        c.threshold = std::clamp(std::max(3.0 * median, 1.5 * p90), 0.03, std::min(0.5, room));
        out.push_back(c);
    }
    return out;
}

std::vector<char> cluster_reach(const Image& img, const BorderCluster& c) {
    const int w = img.width, h = img.height;
    std::vector<char> near(std::size_t(w) * h), reached(near.size(), 0);
    for (std::size_t i = 0; i < near.size(); ++i) {
        const float* p = &img.pixels[i * 4];
        near[i] = rms({p[0], p[1], p[2]}, c.colour) < c.threshold;
    }
    flood_from_border(w, h, reached, [&](int p) { return near[std::size_t(p)] != 0; });
    return reached;
}

} // namespace cm
