// Disjoint sets (union-find) over the integers 0..n-1, with path halving: pieces of a mesh,
// creases made of sharp edges, chains of thin-part edges.
#pragma once
#include <cstdint>
#include <numeric>
#include <vector>

namespace cm {

struct DisjointSets {
    std::vector<std::uint32_t> parent;
    explicit DisjointSets(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
    /// The root of x's set.
    std::uint32_t find(std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }
    /// Joins the sets of a and b.
    void unite(std::uint32_t a, std::uint32_t b) { parent[find(a)] = find(b); }
};

} // namespace cm
