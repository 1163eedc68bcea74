// MinCut against every labelling of small random graphs, and on a grid as image labelling
// uses it.
#include <gtest/gtest.h>

#include <random>

#include "min_cut.h"

using namespace cm;

namespace {

struct Edge {
    int i, j;
    double ij, ji;
};

// The cost of a labelling (bit v set: node v on the source side).
double cost(unsigned labels, const std::vector<std::array<double, 2>>& terminal, const std::vector<Edge>& edges) {
    double c = 0;
    for (std::size_t v = 0; v < terminal.size(); ++v) c += (labels >> v) & 1 ? terminal[v][1] : terminal[v][0];
    for (const auto& e : edges) {
        const bool a = (labels >> e.i) & 1, b = (labels >> e.j) & 1;
        if (a && !b) c += e.ij;
        if (b && !a) c += e.ji;
    }
    return c;
}

} // namespace

TEST(MinCut, EqualsTheBestOfEveryLabellingOnRandomGraphs) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> cap(0, 3);
    std::uniform_int_distribution<int> coin(0, 3);
    for (int trial = 0; trial < 300; ++trial) {
        const int n = 1 + trial % 10;
        std::vector<std::array<double, 2>> terminal(static_cast<std::size_t>(n));
        std::vector<Edge> edges;
        MinCut g(n);
        for (int v = 0; v < n; ++v) {
            // Some nodes without a terminal link, some with both.
            terminal[std::size_t(v)] = {coin(rng) ? cap(rng) : 0.0, coin(rng) ? cap(rng) : 0.0};
            g.add_terminal(v, terminal[std::size_t(v)][0], terminal[std::size_t(v)][1]);
        }
        for (int i = 0; i < n; ++i)
            for (int j = i + 1; j < n; ++j)
                if (coin(rng) != 0) {
                    edges.push_back({i, j, cap(rng), coin(rng) ? cap(rng) : 0.0});
                    g.add_edge(i, j, edges.back().ij, edges.back().ji);
                }
        double best = 1e300;
        for (unsigned labels = 0; labels < (1u << n); ++labels) best = std::min(best, cost(labels, terminal, edges));
        const double flow = g.solve();
        unsigned found = 0;
        for (int v = 0; v < n; ++v) found |= unsigned(g.source_side(v)) << v;
        EXPECT_NEAR(flow, best, 1e-9) << "trial " << trial;
        EXPECT_NEAR(cost(found, terminal, edges), best, 1e-9) << "trial " << trial;
    }
}

TEST(MinCut, SmoothsANoisyDiscOnAGrid) {
    // A disc of radius 20 on a 64 x 64 grid, each pixel's evidence flipped with probability
    // 0.3: with a cost per pair of neighbours apart the disc comes back.
    const int w = 64;
    std::mt19937 rng(5);
    std::bernoulli_distribution flip(0.3);
    MinCut g(w * w);
    for (int y = 0; y < w; ++y)
        for (int x = 0; x < w; ++x) {
            const bool in = (x - 32) * (x - 32) + (y - 32) * (y - 32) < 400;
            const bool says = in != flip(rng);
            g.add_terminal(y * w + x, says ? 1.0 : 0.0, says ? 0.0 : 1.0);
            if (x + 1 < w) g.add_edge(y * w + x, y * w + x + 1, 0.8, 0.8);
            if (y + 1 < w) g.add_edge(y * w + x, (y + 1) * w + x, 0.8, 0.8);
        }
    g.solve();
    int wrong = 0;
    for (int y = 0; y < w; ++y)
        for (int x = 0; x < w; ++x)
            wrong += g.source_side(y * w + x) != ((x - 32) * (x - 32) + (y - 32) * (y - 32) < 400);
    EXPECT_LT(wrong, 60); // of 4096; about 1230 before
}
