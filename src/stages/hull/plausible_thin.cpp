// See plausible_thin.h.
#include "plausible_thin.h"

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "geometry/disjoint_sets.h"

namespace cm::plausible {

namespace {

using openvdb::Coord;

// One thin-part edge: from grid point p along axis a.
struct ThinEdge {
    Coord p;
    int a = 0;
};

std::uint64_t cell_key(const Coord& c) {
    // Grid coordinates stay well within 21 bits each way of the origin (16384 cells at most).
    const auto k = [](int v) { return std::uint64_t(std::uint32_t(v + (1 << 20)) & 0x1fffff); };
    return k(c.x()) | k(c.y()) << 21 | k(c.z()) << 42;
}

// The 4 cells (by their lowest corner) around an edge.
template <typename F>
void cells_of(const ThinEdge& e, F&& f) {
    const int b = (e.a + 1) % 3, c = (e.a + 2) % 3;
    for (int k = 0; k < 4; ++k) {
        Coord q = e.p;
        q[b] -= k & 1;
        q[c] -= k >> 1;
        f(q);
    }
}

template <typename Acc>
bool cell_has_inside_corner(const Acc& acc, const Coord& c) {
    for (int k = 0; k < 8; ++k)
        if (acc.isValueOn(c.offsetBy(k & 1, k >> 1 & 1, k >> 2))) return true;
    return false;
}

// Whether the removal took a grid point around the edge (its ends' 26 neighbours).
template <typename Acc>
bool cut_beside(const Acc& was, const Acc& now, const ThinEdge& e) {
    Coord q = e.p;
    q[e.a] += 1;
    for (int k = 0; k < 27 * 2; ++k) {
        const Coord g = (k < 27 ? e.p : q).offsetBy(k % 27 / 9 - 1, k % 9 / 3 - 1, k % 3 - 1);
        if (was.isValueOn(g) && !now.isValueOn(g)) return true;
    }
    return false;
}

// Edges grouped into chains (sharing a cell), over the edges where `use` is set.
std::vector<std::size_t> chains(const std::vector<ThinEdge>& edges, const std::vector<char>& use) {
    DisjointSets uf(edges.size());
    std::unordered_map<std::uint64_t, std::size_t> first;
    first.reserve(edges.size() * 4);
    for (std::size_t i = 0; i < edges.size(); ++i)
        if (use[i])
            cells_of(edges[i], [&](const Coord& c) {
                const auto [it, fresh] = first.emplace(cell_key(c), i);
                if (!fresh) uf.unite(std::uint32_t(i), std::uint32_t(it->second));
            });
    std::vector<std::size_t> root(edges.size());
    for (std::size_t i = 0; i < edges.size(); ++i) root[i] = uf.find(std::uint32_t(i));
    return root;
}

// Per edge where `use` is set, whether its chain has a cell with a corner inside `grid`.
std::vector<char> hung_on(const std::vector<ThinEdge>& edges, const std::vector<char>& use,
                          const openvdb::BoolGrid& grid) {
    const std::vector<std::size_t> root = chains(edges, use);
    std::vector<char> hung(edges.size(), 0);
    auto acc = grid.getConstAccessor();
    for (std::size_t i = 0; i < edges.size(); ++i) {
        if (!use[i] || hung[root[i]]) continue;
        cells_of(edges[i], [&](const Coord& c) { hung[root[i]] = hung[root[i]] || cell_has_inside_corner(acc, c); });
    }
    std::vector<char> out(edges.size(), 0);
    for (std::size_t i = 0; i < edges.size(); ++i) out[i] = use[i] && hung[root[i]];
    return out;
}

} // namespace

std::size_t keep_hanging_thin_parts(const Volume& in, const openvdb::BoolGrid& now, Volume& out) {
    auto enter = openvdb::GridBase::grid<openvdb::Vec3fGrid>(in.find_extra("thin_enter"));
    auto leave = openvdb::GridBase::grid<openvdb::Vec3fGrid>(in.find_extra("thin_leave"));
    for (const auto& g : in.extra)
        if (g != enter && g != leave) out.extra.push_back(g);
    if (!enter || !leave) return 0;
    auto was = in.occupancy->getConstAccessor();
    auto nacc = now.getConstAccessor();
    // Every edge, and whether the removal took a grid point beside it.
    std::vector<ThinEdge> edges;
    std::vector<char> uncut;
    for (auto it = enter->cbeginValueOn(); it; ++it)
        for (int a = 0; a < 3; ++a)
            if ((*it)[a] >= 0) {
                edges.push_back({it.getCoord(), a});
                uncut.push_back(!cut_beside(was, nacc, edges.back()));
            }
    // A chain hangs in the hull where its edges, all of them, meet an inside corner; in the
    // output where its uncut edges do.
    const std::vector<char> all(edges.size(), 1);
    const std::vector<char> hung_was = hung_on(edges, all, *in.occupancy);
    const std::vector<char> hung_now = hung_on(edges, uncut, now);
    std::size_t dropped = 0;
    // The same grids (name, transform, metadata), holding the edges kept.
    openvdb::Vec3fGrid::Ptr e2 = enter->copyWithNewTree(), l2 = leave->copyWithNewTree();
    auto ein = enter->getConstAccessor();
    auto lin = leave->getConstAccessor();
    auto ea = e2->getAccessor();
    auto la = l2->getAccessor();
    for (std::size_t i = 0; i < edges.size(); ++i) {
        if (!uncut[i] || (hung_was[i] && !hung_now[i])) {
            ++dropped;
            continue;
        }
        const ThinEdge& e = edges[i];
        openvdb::Vec3f te = ea.getValue(e.p), tl = la.getValue(e.p);
        te[e.a] = ein.getValue(e.p)[e.a];
        tl[e.a] = lin.getValue(e.p)[e.a];
        ea.setValue(e.p, te);
        la.setValue(e.p, tl);
    }
    if (e2->activeVoxelCount() > 0) {
        out.extra.push_back(e2);
        out.extra.push_back(l2);
    }
    return dropped;
}

} // namespace cm::plausible
