#include "border_clusters.h"

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
                                          double min_share) {
    std::vector<BorderCluster> out;
    if (total == 0 || double(outliers.size()) < min_share * double(total)) return out;
    // Seeds: the first sample, then the sample farthest from it.
    std::vector<Rgb> centre{outliers[0]};
    std::size_t far = 0;
    for (std::size_t i = 1; i < outliers.size(); ++i)
        if (rms(outliers[i], centre[0]) > rms(outliers[far], centre[0])) far = i;
    if (rms(outliers[far], centre[0]) > base_threshold) centre.push_back(outliers[far]);
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
        c.threshold = std::clamp(std::max({base_threshold, 0.1 + 5.0 * median, 2.0 * p90}), 0.1, 0.5);
        out.push_back(c);
    }
    return out;
}

} // namespace cm
