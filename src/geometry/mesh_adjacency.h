// Vertex-to-vertex adjacency of a triangle mesh in compressed rows (CSR): the
// neighbours of vertex v are neighbours[offsets[v] .. offsets[v + 1]). Flat
// arrays so the smoothing loops over millions of vertices stay cache friendly.
#pragma once
#include <cstdint>
#include <vector>

#include "core/mesh.h"

namespace cm {

struct VertexAdjacency {
    std::vector<std::uint32_t> offsets;    ///< vertex_count + 1 entries
    std::vector<std::uint32_t> neighbours; ///< sorted, unique per vertex

    std::size_t vertex_count() const { return offsets.empty() ? 0 : offsets.size() - 1; }
    std::uint32_t degree(std::uint32_t v) const { return offsets[v + 1] - offsets[v]; }
    const std::uint32_t* begin(std::uint32_t v) const { return neighbours.data() + offsets[v]; }
    const std::uint32_t* end(std::uint32_t v) const { return neighbours.data() + offsets[v + 1]; }
};

/// @brief Builds the one-ring of every vertex (any triangle soup: boundaries and
/// non-manifold edges are fine; isolated vertices get no neighbours). TBB-parallel.
VertexAdjacency build_vertex_adjacency(const Mesh& mesh);

} // namespace cm
