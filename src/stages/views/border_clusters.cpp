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

// The 90th-percentile distance of each cluster's members from its centre.
std::vector<double> radii(const std::vector<Rgb>& s, const std::vector<Rgb>& centre, const std::vector<int>& member) {
    std::vector<double> r(centre.size(), 0);
    for (std::size_t k = 0; k < centre.size(); ++k) {
        std::vector<double> d;
        for (std::size_t i = 0; i < s.size(); ++i)
            if (member[i] == int(k)) d.push_back(rms(s[i], centre[k]));
        if (d.empty()) continue;
        std::nth_element(d.begin(), d.begin() + std::ptrdiff_t(d.size() * 9 / 10), d.end());
        r[k] = d[d.size() * 9 / 10];
    }
    return r;
}

// One colour that Lloyd split in parts (a cloth's folds and grain: dark and light parts of one
// weave) is one background: clusters whose centres are closer than `base_threshold`, or than
// the sum of their 90th-percentile radii, are merged (the closest pair first).
void merge_overlapping(const std::vector<Rgb>& s, double base_threshold, std::vector<Rgb>& centre,
                       std::vector<int>& member) {
    while (centre.size() > 1) {
        const std::vector<double> r = radii(s, centre, member);
        std::size_t a = 0, b = 0;
        double best = 1e9;
        for (std::size_t i = 0; i < centre.size(); ++i)
            for (std::size_t j = i + 1; j < centre.size(); ++j) {
                const double d = rms(centre[i], centre[j]);
                if (d < std::max(base_threshold, r[i] + r[j]) && d < best) {
                    best = d;
                    a = i;
                    b = j;
                }
            }
        if (best == 1e9) return;
        Rgb sum{};
        std::size_t count = 0;
        for (std::size_t i = 0; i < s.size(); ++i) {
            if (member[i] == int(b)) member[i] = int(a);
            else if (member[i] > int(b)) --member[i];
            if (member[i] != int(a)) continue;
            for (int c = 0; c < 3; ++c) sum[std::size_t(c)] += s[i][std::size_t(c)];
            ++count;
        }
        for (int c = 0; c < 3; ++c)
            centre[a][std::size_t(c)] = sum[std::size_t(c)] / double(std::max<std::size_t>(1, count));
        centre.erase(centre.begin() + std::ptrdiff_t(b));
    }
}

// The inverse of the members' covariance about `centre`, widened by 0.01^2 per channel (a
// flat colour, or one that varies along one direction only, keeps a usable width).
std::array<double, 9> inverse_covariance(const std::vector<Rgb>& s, const std::vector<int>& member, int k,
                                         const Rgb& centre) {
    std::array<double, 9> c{};
    std::size_t count = 0;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (member[i] != k) continue;
        ++count;
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                c[std::size_t(3 * a + b)] +=
                    (s[i][std::size_t(a)] - centre[std::size_t(a)]) * (s[i][std::size_t(b)] - centre[std::size_t(b)]);
    }
    for (double& x : c) x /= double(std::max<std::size_t>(1, count));
    for (int a = 0; a < 3; ++a) c[std::size_t(4 * a)] += 1e-4;
    // The adjugate over the determinant (symmetric positive definite: the determinant is > 0).
    const std::array<double, 9> adj{c[4] * c[8] - c[5] * c[7], c[2] * c[7] - c[1] * c[8], c[1] * c[5] - c[2] * c[4],
                                    c[5] * c[6] - c[3] * c[8], c[0] * c[8] - c[2] * c[6], c[2] * c[3] - c[0] * c[5],
                                    c[3] * c[7] - c[4] * c[6], c[1] * c[6] - c[0] * c[7], c[0] * c[4] - c[1] * c[3]};
    const double det = c[0] * adj[0] + c[1] * adj[3] + c[2] * adj[6];
    std::array<double, 9> inv{};
    for (int i = 0; i < 9; ++i) inv[std::size_t(i)] = adj[std::size_t(i)] / det;
    return inv;
}

} // namespace

double BorderCluster::distance(const std::array<double, 3>& c) const {
    const double d[3] = {c[0] - colour[0], c[1] - colour[1], c[2] - colour[2]};
    double q = 0;
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) q += d[a] * inverse[std::size_t(3 * a + b)] * d[b];
    return std::sqrt(std::max(q, 0.0));
}

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
    merge_overlapping(outliers, base_threshold, centre, member);
    for (std::size_t k = 0; k < centre.size(); ++k) {
        BorderCluster c;
        c.colour = centre[k];
        c.inverse = inverse_covariance(outliers, member, int(k), centre[k]);
        std::vector<double> d;
        for (std::size_t i = 0; i < outliers.size(); ++i)
            if (member[i] == int(k)) d.push_back(c.distance(outliers[i]));
        c.share = double(d.size()) / double(total);
        if (c.share < min_share) continue;
        std::sort(d.begin(), d.end());
        const double median = d[d.size() / 2], p90 = d[std::min(d.size() - 1, d.size() * 9 / 10)];
        // The cluster's own spread, and at most half-way to the main background (or another
        // cluster would swallow it).
        double room = 0.5 * c.distance(main);
        for (std::size_t j = 0; j < centre.size(); ++j)
            if (j != k) room = std::min(room, 0.5 * c.distance(centre[j]));
        c.threshold = std::min(std::max({3.0 * median, 1.5 * p90, 3.0}), room);
        out.push_back(c);
    }
    return out;
}

std::vector<char> cluster_reach(const Image& img, const BorderCluster& c) {
    const int w = img.width, h = img.height;
    std::vector<char> near(std::size_t(w) * h), reached(near.size(), 0);
    for (std::size_t i = 0; i < near.size(); ++i) {
        const auto p = img.rgba(i);
        near[i] = c.distance({p[0], p[1], p[2]}) < c.threshold;
    }
    flood_from_border(w, h, reached, [&](int p) { return near[std::size_t(p)] != 0; });
    return reached;
}

} // namespace cm
