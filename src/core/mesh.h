// The mesh passed between stages: compact indexed triangles with shared
// vertices. Compact arrays (not a half-edge structure) because the stages that
// touch millions of faces (marching cubes, smoothing, reduction) are fastest on
// flat arrays; io/mesh_io.h reads and writes them (through OpenMesh and tinygltf).
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/vec.h"

namespace cm {

struct Image; // core/views.h

struct Mesh {
    std::vector<Vec3f> positions;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<Vec3f> normals;               ///< per vertex; empty or positions.size()
    std::vector<std::array<float, 2>> uvs;    ///< per vertex; empty or positions.size()
    std::vector<std::array<float, 4>> colors; ///< per vertex RGBA; empty or positions.size()
    /// Per face corner (v up, as OBJ): corner k of triangle f at 3 f + k; empty or
    /// 3 * triangles.size(). Corners of one vertex differ across atlas seams, so the
    /// triangles stay shared and the mesh stays closed; writers split vertices as their
    /// format needs. Takes precedence over `uvs`.
    std::vector<std::array<float, 2>> corner_uvs;
    /// Base-colour texture (RGBA, row 0 at the top = v 1) that the UVs address; may be null.
    std::shared_ptr<const Image> texture;

    std::size_t vertex_count() const { return positions.size(); }
    std::size_t face_count() const { return triangles.size(); }
    void bounds(Vec3f& lo, Vec3f& hi) const { bounds_of(positions, lo, hi); } ///< zero box for an empty mesh
    /// The box of `points` (a zero box when there are none). TBB-parallel.
    static void bounds_of(const std::vector<Vec3f>& points, Vec3f& lo, Vec3f& hi);
    /// Area-weighted per-vertex normals from the triangles (outward for an outward mesh).
    void compute_normals();
};

} // namespace cm
