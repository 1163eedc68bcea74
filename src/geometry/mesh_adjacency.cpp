#include "geometry/mesh_adjacency.h"

#include <algorithm>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace cm {

VertexAdjacency build_vertex_adjacency(const Mesh& mesh) {
    const std::size_t nv = mesh.positions.size();
    // Every corner contributes its two edge partners; duplicates (each edge is seen
    // from both of its faces) are removed per vertex afterwards.
    std::vector<std::uint32_t> count(nv + 1, 0);
    for (const auto& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) count[t[k] + 1] += 2;
    for (std::size_t v = 0; v < nv; ++v) count[v + 1] += count[v];
    std::vector<std::uint32_t> raw(count[nv]);
    std::vector<std::uint32_t> fill(count.begin(), count.end() - 1);
    for (const auto& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = t[k];
            raw[fill[v]++] = t[(k + 1) % 3];
            raw[fill[v]++] = t[(k + 2) % 3];
        }
    std::vector<std::uint32_t> unique_count(nv + 1, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 4096), [&](const auto& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            auto* b = raw.data() + count[v];
            auto* e = raw.data() + count[v + 1];
            std::sort(b, e);
            e = std::unique(b, e);
            // A degenerate triangle can name v as its own neighbour.
            e = std::remove(b, e, std::uint32_t(v));
            unique_count[v + 1] = std::uint32_t(e - b);
        }
    });
    VertexAdjacency adj;
    adj.offsets.resize(nv + 1, 0);
    for (std::size_t v = 0; v < nv; ++v) adj.offsets[v + 1] = adj.offsets[v] + unique_count[v + 1];
    adj.neighbours.resize(adj.offsets[nv]);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 4096), [&](const auto& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v)
            std::copy_n(raw.data() + count[v], unique_count[v + 1], adj.neighbours.data() + adj.offsets[v]);
    });
    return adj;
}

} // namespace cm
