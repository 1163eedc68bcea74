// The loops of Dual Marching Cubes (dmc_loops.h): the fans of the Marching Cubes mesh, the
// loops around a crossing, and the loops cut where two would share two edges.
#include "dmc_loops.h"

#include <algorithm>
#include <utility>

namespace cm::dmc {
namespace {

/// The fans of every vertex of `m`.
Fans build_fans(const Mesh& m) {
    Fans f;
    f.first.assign(m.positions.size() + 1, 0);
    for (const auto& t : m.triangles)
        for (Index v : t) ++f.first[v + 1];
    for (std::size_t v = 0; v < m.positions.size(); ++v) f.first[v + 1] += f.first[v];
    f.tri.resize(f.first.back());
    std::vector<Index> fill(f.first.begin(), f.first.end() - 1);
    for (Index t = 0; t < Index(m.triangles.size()); ++t) {
        const auto& tr = m.triangles[t];
        for (int k = 0; k < 3; ++k) f.tri[fill[tr[k]]++] = {t, tr[(k + 1) % 3], tr[(k + 2) % 3]};
    }
    return f;
}

/// The loops around vertex v, in the order of its fan (outward orientation); returns the count.
int ring(const Fans& f, const MarchingCubesPatches& P, Index v, Index* out, int cap) {
    const Index b = f.first[v], e = f.first[v + 1];
    const int deg = int(e - b);
    if (deg == 0) return 0;
    Index order[32];
    if (deg > 32) return -1;
    // Walk the fan: the triangle (v, a, c) is followed by the one that starts (v, c, ...).
    order[0] = b;
    for (int k = 1; k < deg; ++k) {
        const Index c = f.tri[order[k - 1]][2];
        Index next = e;
        for (Index j = b; j < e; ++j)
            if (f.tri[j][1] == c) next = j;
        if (next == e) return -1;
        order[k] = next;
    }
    int n = 0;
    for (int k = 0; k < deg; ++k) {
        const Index loop = P.triangle_loop[f.tri[order[k]][0]];
        if (n > 0 && out[n - 1] == loop) continue;
        if (n == cap) return -1;
        out[n++] = loop;
    }
    while (n > 1 && out[n - 1] == out[0]) --n;
    return n;
}

/// The faces (bit 2 n + side) of `cell` that hold the lattice edge e (start point, axis).
unsigned face_mask(const std::array<std::int32_t, 4>& e, const openvdb::Coord& cell) {
    unsigned m = 0;
    for (int n = 0; n < 3; ++n) {
        if (n == e[3]) continue;
        const int d = e[std::size_t(n)] - cell[n];
        if (d == 0 || d == 1) m |= 1u << (2 * n + d);
    }
    return m;
}

/// The loop's crossings in outward order: the boundary of its triangles [t0, t1).
std::vector<Index> loop_cycle(const Mesh& mc, Index t0, Index t1) {
    std::vector<std::pair<Index, Index>> e, b;
    for (Index t = t0; t < t1; ++t)
        for (int k = 0; k < 3; ++k) e.emplace_back(mc.triangles[t][k], mc.triangles[t][(k + 1) % 3]);
    for (const auto& d : e)
        if (std::find(e.begin(), e.end(), std::pair(d.second, d.first)) == e.end()) b.push_back(d);
    std::vector<Index> cyc;
    if (b.empty()) return cyc;
    cyc.push_back(b[0].first);
    while (cyc.size() < b.size()) {
        const auto it = std::find_if(b.begin(), b.end(), [&](const auto& d) { return d.first == cyc.back(); });
        if (it == b.end() || it->second == cyc.front()) break;
        cyc.push_back(it->second);
    }
    return cyc;
}

/// The loop of `cell` around crossing x (every crossing is in one loop of each of its cells).
Index loop_around(const Fans& f, const MarchingCubesPatches& P, const std::vector<openvdb::Coord>& cell_of, Index x,
                  const openvdb::Coord& cell) {
    for (Index j = f.first[x]; j < f.first[x + 1]; ++j) {
        const Index l = P.triangle_loop[f.tri[j][0]];
        if (cell_of[l] == cell) return l;
    }
    return kNoIndex;
}

/// Cuts loops so that no two loops share two edges (see dmc_loops.h): where loops
/// A < B in neighbouring cells each hold all four crossings of their common face, A's piece
/// that holds both of the face's segments is cut by a chord between the middles of the two
/// arcs that separate them. New pieces get loop indices from nloops on (D.loop_cell grows);
/// D.loop_first / loop_cross are rebuilt with the pieces' crossings. Returns the cut loops;
/// split_of[l] indexes them (-1: not cut).
std::vector<SplitLoop> split_shared_faces(const Mesh& mc, const MarchingCubesPatches& P, const Fans& fans,
                                          const std::vector<Index>& tfirst, DualMesh& D, std::vector<int>& split_of) {
    const std::size_t nloops = D.loop_cell.size();
    auto face_count = [&](Index l, int f) {
        int n = 0;
        for (Index i = D.loop_first[l]; i < D.loop_first[l + 1]; ++i)
            n += (face_mask(P.vertex_edge[D.loop_cross[i]], D.loop_cell[l]) >> f) & 1;
        return n;
    };
    std::vector<std::pair<Index, int>> todo; // (loop, face) to cut
    for (Index a = 0; a < Index(nloops); ++a) {
        const Index n = D.loop_first[a + 1] - D.loop_first[a];
        if (n < 6) continue; // both segments of a face and a way round between them
        for (int f = 0; f < 6; ++f) {
            if (face_count(a, f) != 4) continue;
            openvdb::Coord nb = D.loop_cell[a];
            nb[f / 2] += (f & 1) ? 1 : -1;
            Index x = kNoIndex;
            for (Index i = D.loop_first[a]; i < D.loop_first[a + 1] && x == kNoIndex; ++i)
                if ((face_mask(P.vertex_edge[D.loop_cross[i]], D.loop_cell[a]) >> f) & 1) x = D.loop_cross[i];
            const Index b = loop_around(fans, P, D.loop_cell, x, nb);
            if (b != kNoIndex && a < b && face_count(b, f ^ 1) == 4) todo.emplace_back(a, f);
        }
    }
    std::vector<SplitLoop> splits;
    if (todo.empty()) return splits;
    split_of.assign(nloops, -1);
    Index next_id = Index(nloops);
    for (const auto& [a, f] : todo) {
        if (split_of[a] < 0) {
            split_of[a] = int(splits.size());
            SplitLoop s;
            s.cycle = loop_cycle(mc, tfirst[a], tfirst[a + 1]);
            s.pieces = {s.cycle};
            s.id = {a};
            splits.push_back(std::move(s));
        }
        SplitLoop& s = splits[std::size_t(split_of[a])];
        auto on_f = [&, a = a, f = f](Index v) { return (face_mask(P.vertex_edge[v], D.loop_cell[a]) >> f) & 1; };
        for (std::size_t k = 0; k < s.pieces.size(); ++k) {
            const std::vector<Index> cyc = s.pieces[k];
            const int n = int(cyc.size());
            int seg[2], ns = 0;
            for (int i = 0; i < n && ns < 2; ++i)
                if (on_f(cyc[std::size_t(i)]) && on_f(cyc[std::size_t((i + 1) % n)])) seg[ns++] = i;
            if (ns < 2) continue;
            // Arcs cyc[seg0 + 1 .. seg1] and cyc[seg1 + 1 .. seg0 + n], each of two or more
            // crossings (the segments share none): a chord between their middles leaves
            // one segment on each side.
            const int len1 = seg[1] - seg[0], len2 = n - len1;
            const int ia = (seg[0] + 1 + len1 / 2) % n, ib = (seg[1] + 1 + len2 / 2) % n;
            std::vector<Index> p1, p2;
            for (int i = ia;; i = (i + 1) % n) {
                p1.push_back(cyc[std::size_t(i)]);
                if (i == ib) break;
            }
            for (int i = ib;; i = (i + 1) % n) {
                p2.push_back(cyc[std::size_t(i)]);
                if (i == ia) break;
            }
            s.pieces[k] = std::move(p1);
            s.pieces.push_back(std::move(p2));
            s.id.push_back(next_id++);
            break;
        }
    }
    // The crossings of every loop, the pieces' in place of their loops'.
    std::vector<Index> first(next_id + 1, 0), cross;
    cross.reserve(D.loop_cross.size() + 8 * splits.size());
    D.loop_cell.resize(next_id);
    std::vector<const std::vector<Index>*> piece(next_id, nullptr);
    for (const SplitLoop& s : splits)
        for (std::size_t k = 0; k < s.pieces.size(); ++k) {
            piece[s.id[k]] = &s.pieces[k];
            D.loop_cell[s.id[k]] = D.loop_cell[s.id[0]];
        }
    for (Index l = 0; l < next_id; ++l) {
        if (piece[l]) cross.insert(cross.end(), piece[l]->begin(), piece[l]->end());
        else
            cross.insert(cross.end(), D.loop_cross.begin() + D.loop_first[l],
                         D.loop_cross.begin() + D.loop_first[l + 1]);
        first[l + 1] = Index(cross.size());
    }
    D.loop_first = std::move(first);
    D.loop_cross = std::move(cross);
    return splits;
}

/// The pieces of cut loop s around its crossing v, in the order of v's fan: from the piece
/// holding the loop's edge out of v, across the chords at v, to the one holding the edge in.
int pieces_around(const SplitLoop& s, Index v, Index* out, int cap) {
    const std::size_t n = s.cycle.size();
    const std::size_t at = std::size_t(std::find(s.cycle.begin(), s.cycle.end(), v) - s.cycle.begin());
    if (at == n) return -1;
    const Index pred = s.cycle[(at + n - 1) % n];
    Index to = s.cycle[(at + 1) % n]; // the piece to emit holds the edge v -> to
    int k = 0;
    for (std::size_t guard = 0; guard <= s.pieces.size(); ++guard) {
        std::size_t found = s.pieces.size();
        Index back = kNoIndex;
        for (std::size_t p = 0; p < s.pieces.size() && found == s.pieces.size(); ++p) {
            const auto& c = s.pieces[p];
            for (std::size_t i = 0; i < c.size(); ++i)
                if (c[i] == v && c[(i + 1) % c.size()] == to) {
                    found = p;
                    back = c[(i + c.size() - 1) % c.size()];
                }
        }
        if (found == s.pieces.size() || k == cap) return -1;
        out[k++] = s.id[found];
        if (back == pred) return k;
        to = back; // a chord v - back: the next piece holds v -> back
    }
    return -1;
}

} // namespace

DualLoops::DualLoops(const Mesh& mc, const MarchingCubesPatches& P, DualMesh& D)
    : P_(P), fans_(build_fans(mc)), uncut_(P.loop_cell.size()) {
    // Each loop's crossings (its triangles are consecutive).
    const std::size_t nloops = uncut_, nv = mc.positions.size();
    std::vector<Index> tfirst(nloops + 1, Index(mc.triangles.size()));
    for (Index t = Index(mc.triangles.size()); t-- > 0;) tfirst[P.triangle_loop[t]] = t;
    D.loop_first.assign(nloops + 1, 0);
    D.loop_cross.reserve(nv * 4);
    for (std::size_t l = 0; l < nloops; ++l) {
        const std::size_t b = D.loop_cross.size();
        for (Index t = tfirst[l]; t < tfirst[l + 1]; ++t)
            for (Index v : mc.triangles[t])
                if (P.vertex_edge[v][3] >= 0 &&
                    std::find(D.loop_cross.begin() + std::ptrdiff_t(b), D.loop_cross.end(), v) == D.loop_cross.end())
                    D.loop_cross.push_back(v);
        D.loop_first[l + 1] = Index(D.loop_cross.size());
    }
    D.loop_cell = P.loop_cell;
    splits_ = split_shared_faces(mc, P, fans_, tfirst, D, split_of_);
}

int DualLoops::around(Index v, Index* out, int cap) const {
    if (splits_.empty()) return ring(fans_, P_, v, out, cap);
    Index loops[16];
    const int n = ring(fans_, P_, v, loops, 16);
    if (n < 0) return n;
    int k = 0;
    for (int i = 0; i < n; ++i) {
        const int s = loops[i] < uncut_ ? split_of_[loops[i]] : -1;
        if (s < 0) {
            if (k == cap) return -1;
            out[k++] = loops[i];
            continue;
        }
        const int m = pieces_around(splits_[std::size_t(s)], v, out + k, cap - k);
        if (m < 0) return -1;
        k += m;
    }
    return k;
}

} // namespace cm::dmc
