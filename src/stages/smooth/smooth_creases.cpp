#include "smooth_creases.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "geometry/disjoint_sets.h"
#include "util/chunked_scatter.h"

namespace cm {

namespace {

// Per vertex: the sharp edges met (to 3, "more than two") and the first two far ends.
struct Sharp {
    std::uint32_t count = 0;
    std::uint32_t ends[2] = {0, 0};
    void add(std::uint32_t w) {
        if (count < 2) ends[count] = w;
        count = std::min<std::uint32_t>(count + 1, 3);
    }
};

using EdgeList = std::vector<std::pair<std::uint32_t, std::uint32_t>>;

// The larger vertex of edge 3 f + k of `in` (from corner k of face f to the next).
std::uint32_t larger_end(const Mesh& in, std::uint32_t e) {
    const auto& t = in.triangles[e / 3];
    return std::max(t[e % 3], t[(e % 3 + 1) % 3]);
}

// Face f's normal, area-weighted (taken where it is needed: a table of every face's would be
// 24 bytes a face of fresh memory, more than the few products it saves).
Vec3d face_normal(const Mesh& in, std::size_t f) {
    const auto& t = in.triangles[f];
    const Vec3d p0(in.positions[t[0]]);
    return cross(Vec3d(in.positions[t[1]]) - p0, Vec3d(in.positions[t[2]]) - p0);
}

// Every edge of every face (3 f + k: from corner k to the next) listed under its smaller vertex
// (`start`: where each vertex's list begins in `edge`), ordered by the larger vertex and then by
// face: the order of sorting every (smaller, larger, face) but by a scatter, without the sort of
// three entries a face (a third of the smoothing's time at 1.5 M faces).
void edges_by_vertex(const Mesh& in, std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& edge) {
    const std::size_t nv = in.positions.size();
    chunked_scatter(
        in.triangles.size(), nv,
        [&](std::size_t f, auto&& emit) {
            const auto& t = in.triangles[f];
            for (std::size_t k = 0; k < 3; ++k) emit(std::min(t[k], t[(k + 1) % 3]), std::uint32_t(3 * f + k));
        },
        start, edge);
    // The scatter keeps the faces' order; a stable insertion sort by the larger vertex (a
    // handful of edges a vertex) leaves equal ones in it.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 1 << 14), [&](const auto& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v)
            for (std::uint32_t i = start[v] + 1; i < start[v + 1]; ++i) {
                const std::uint32_t e = edge[i], key = larger_end(in, e);
                std::uint32_t j = i;
                for (; j > start[v] && larger_end(in, edge[j - 1]) > key; --j) edge[j] = edge[j - 1];
                edge[j] = e;
            }
    });
}

// Joins the sets of two crease ends that continue each other across a gap of at most `gap`
// (each end's last edge points at the other end within about 37 degrees): a drawn corner that
// Marching Cubes bevels in places is one crease in pieces; the steps of a carved surface lie
// side by side, not end to end.
void join_across_gaps(const Mesh& in, const EdgeList& sharp_edges, DisjointSets& sets, double gap) {
    std::vector<std::uint32_t> degree(in.positions.size(), 0), prev(in.positions.size(), 0);
    for (const auto& [a, b] : sharp_edges) {
        ++degree[a], ++degree[b];
        prev[a] = b, prev[b] = a;
    }
    std::vector<std::pair<std::array<std::int64_t, 3>, std::uint32_t>> ends; // cell, end vertex
    const auto cell = [&](const Vec3f& p) {
        return std::array<std::int64_t, 3>{std::int64_t(std::floor(p.x / gap)), std::int64_t(std::floor(p.y / gap)),
                                           std::int64_t(std::floor(p.z / gap))};
    };
    for (const auto& [a, b] : sharp_edges)
        for (const std::uint32_t v : {a, b})
            if (degree[v] == 1) ends.emplace_back(cell(in.positions[v]), v);
    std::sort(ends.begin(), ends.end());
    const auto outward = [&](std::uint32_t v) { return normalize(Vec3d(in.positions[v] - in.positions[prev[v]])); };
    for (const auto& [c, v] : ends) {
        const Vec3d pv(in.positions[v]), dv = outward(v);
        for (std::int64_t dx = -1; dx <= 1; ++dx)
            for (std::int64_t dy = -1; dy <= 1; ++dy)
                for (std::int64_t dz = -1; dz <= 1; ++dz) {
                    const std::array<std::int64_t, 3> k{c[0] + dx, c[1] + dy, c[2] + dz};
                    auto it = std::lower_bound(ends.begin(), ends.end(), std::make_pair(k, std::uint32_t(0)));
                    for (; it != ends.end() && it->first == k; ++it) {
                        const std::uint32_t w = it->second;
                        if (w <= v) continue;
                        const Vec3d gvw = Vec3d(in.positions[w]) - pv;
                        const double d = length(gvw);
                        if (d > gap || d == 0 || dot(dv, gvw) < 0.8 * d || dot(outward(w), gvw) > -0.8 * d) continue;
                        sets.unite(v, w);
                    }
                }
    }
}

// Whether the edge a-b runs along a line of sight of one of `views` (within 20 degrees): the
// wall a view's outline sweeps has its corners along its lines of sight.
bool along_a_view(const Mesh& in, std::uint32_t a, std::uint32_t b, const std::vector<Camera>& views) {
    const Vec3d e = Vec3d(in.positions[b]) - Vec3d(in.positions[a]);
    const double le = length(e);
    return le > 0 && std::any_of(views.begin(), views.end(), [&](const Camera& c) {
               return c.orthographic() && std::fabs(dot(e, c.d)) > 0.94 * le * length(c.d);
           });
}

// The sharp edges that belong to a crease reaching at least `reach` (the diagonal of the box
// around its connected sharp edges, pieces continuing each other across `gap` joined), or that
// run along a view; the others dropped. Returns how many short creases there were.
std::size_t keep_long_creases(const Mesh& in, EdgeList& sharp_edges, double reach, double gap,
                              const std::vector<Camera>& views) {
    DisjointSets sets(in.positions.size());
    for (const auto& [a, b] : sharp_edges) sets.unite(a, b);
    join_across_gaps(in, sharp_edges, sets, gap);
    struct Box {
        Vec3f lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
    };
    std::vector<Box> box(in.positions.size());
    for (const auto& [a, b] : sharp_edges)
        for (const std::uint32_t v : {a, b}) {
            Box& x = box[sets.find(v)];
            const Vec3f& p = in.positions[v];
            x.lo = Vec3f(std::min(x.lo.x, p.x), std::min(x.lo.y, p.y), std::min(x.lo.z, p.z));
            x.hi = Vec3f(std::max(x.hi.x, p.x), std::max(x.hi.y, p.y), std::max(x.hi.z, p.z));
        }
    const auto is_short = [&](std::uint32_t root) { return double(length(box[root].hi - box[root].lo)) < reach; };
    std::size_t dropped = 0;
    std::vector<char> counted(in.positions.size(), 0);
    for (const auto& [a, b] : sharp_edges)
        if (const std::uint32_t r = sets.find(a); !counted[r] && is_short(r)) {
            counted[r] = 1;
            ++dropped;
        }
    std::erase_if(sharp_edges, [&](const auto& e) {
        return is_short(sets.find(e.first)) && !along_a_view(in, e.first, e.second, views);
    });
    return dropped;
}

} // namespace

CreaseHold hold_creases(const Mesh& in, const VertexAdjacency& ring, double angle_deg, double min_reach,
                        const std::vector<Camera>& views) {
    const std::size_t nv = in.positions.size(), nf = in.triangles.size();
    // Every edge with exactly two faces is sharp when their normals are further apart than the angle.
    std::vector<std::uint32_t> start, edge;
    edges_by_vertex(in, start, edge);
    const auto larger = [&](std::uint32_t e) { return larger_end(in, e); };
    const double cos_angle = std::cos(angle_deg * 3.14159265358979323846 / 180.0);
    // Per block of vertices, in parallel: its edges' lengths and its sharp edges, in vertex
    // order; the lengths are summed after in that order (the sum of one loop over them).
    constexpr std::size_t kBlock = 1 << 14;
    struct Block {
        std::vector<float> lengths;
        EdgeList sharp;
    };
    std::vector<Block> blocks((nv + kBlock - 1) / kBlock);
    tbb::parallel_for(std::size_t(0), blocks.size(), [&](std::size_t k) {
        Block& out = blocks[k];
        for (auto a = std::uint32_t(k * kBlock), last = std::uint32_t(std::min(nv, (k + 1) * kBlock)); a < last; ++a)
            for (std::uint32_t i = start[a], end = start[a + 1]; i < end;) {
                const std::uint32_t b = larger(edge[i]);
                std::uint32_t j = i + 1;
                while (j < end && larger(edge[j]) == b) ++j;
                out.lengths.push_back(length(in.positions[a] - in.positions[b]));
                if (j - i == 2) {
                    const Vec3d n0 = face_normal(in, edge[i] / 3), n1 = face_normal(in, edge[i + 1] / 3);
                    const double l0 = length(n0), l1 = length(n1);
                    if (l0 > 0 && l1 > 0 && dot(n0, n1) < cos_angle * l0 * l1) out.sharp.emplace_back(a, b);
                }
                i = j;
            }
    });
    EdgeList sharp_edges;
    double edge_length = 0;
    std::size_t edge_count = 0;
    for (Block& b : blocks) {
        for (const float l : b.lengths) edge_length += double(l);
        edge_count += b.lengths.size();
        sharp_edges.insert(sharp_edges.end(), b.sharp.begin(), b.sharp.end());
        b = Block{};
    }
    std::vector<std::uint32_t>().swap(start);
    std::vector<std::uint32_t>().swap(edge);
    CreaseHold h;
    if (min_reach > 0 && edge_count > 0) {
        const double mean_edge = edge_length / double(edge_count);
        h.short_creases = keep_long_creases(in, sharp_edges, min_reach * mean_edge, 3 * mean_edge, views);
    }
    std::vector<Sharp> sharp(nv);
    for (const auto& [a, b] : sharp_edges) {
        sharp[a].add(b);
        sharp[b].add(a);
    }
    // The vertices off the creases beside one, numbered: only theirs of the faces' summed
    // normals are taken (in face order, as a sum over every vertex would add them).
    constexpr std::uint32_t kOff = 0xFFFFFFFFu;
    std::vector<std::uint32_t> slot(nv, kOff);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, kBlock), [&](const auto& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            const auto u = std::uint32_t(v);
            if (sharp[v].count == 0 &&
                std::any_of(ring.begin(u), ring.end(u), [&](std::uint32_t w) { return sharp[w].count > 0; }))
                slot[v] = 0;
        }
    });
    std::uint32_t beside_count = 0;
    for (std::uint32_t& s : slot)
        if (s != kOff) s = beside_count++;
    std::vector<Vec3d> mean(beside_count, Vec3d(0, 0, 0));
    if (beside_count > 0)
        for (std::size_t f = 0; f < nf; ++f) {
            const auto& t = in.triangles[f];
            if (slot[t[0]] == kOff && slot[t[1]] == kOff && slot[t[2]] == kOff) continue;
            const Vec3d n = face_normal(in, f);
            for (auto v : t)
                if (slot[v] != kOff) mean[slot[v]] += n;
        }
    // Each vertex's neighbours (a crease vertex keeps two, a held one none), counted, then
    // laid out and filled in parallel.
    h.plane.assign(nv, Vec3f(0, 0, 0));
    h.adj.offsets.assign(nv + 1, 0);
    for (std::size_t v = 0; v < nv; ++v) {
        const auto u = std::uint32_t(v);
        const std::uint32_t n = sharp[v].count == 2  ? 2
                                : sharp[v].count > 0 ? 0
                                                     : std::uint32_t(ring.end(u) - ring.begin(u));
        h.adj.offsets[v + 1] = h.adj.offsets[v] + n;
        h.crease_vertices += sharp[v].count == 2;
        h.held_vertices += sharp[v].count == 1 || sharp[v].count == 3; // stays
    }
    h.adj.neighbours.resize(h.adj.offsets[nv]);
    std::atomic<std::size_t> planes{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, kBlock), [&](const auto& r) {
        std::size_t count = 0;
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            const auto u = std::uint32_t(v);
            std::uint32_t* out = h.adj.neighbours.data() + h.adj.offsets[v];
            if (sharp[v].count == 2) {
                std::copy(sharp[v].ends, sharp[v].ends + 2, out);
            } else if (sharp[v].count == 0) {
                std::copy(ring.begin(u), ring.end(u), out);
                if (slot[v] != kOff && length(mean[slot[v]]) > 0) {
                    h.plane[v] = Vec3f(normalize(mean[slot[v]]));
                    ++count;
                }
            }
        }
        planes += count;
    });
    h.plane_vertices = planes;
    return h;
}

} // namespace cm
