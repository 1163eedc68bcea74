// Self-intersection test of a triangle mesh: for checks in tests, benchmarks and run
// reports ("no self-intersections" is one of the output quality rules), and for the
// stages that must not create any (smoothing repairs the faces it finds here).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/mesh.h"

namespace cm {

using FacePair = std::array<std::uint32_t, 2>; ///< (a, b) with a < b

/// An allocator whose resize() leaves trivial elements uninitialised, for large arrays
/// that are filled right after (no pass of zeros over hundreds of megabytes).
template <typename T>
struct UninitAllocator : std::allocator<T> {
    template <typename U>
    struct rebind {
        using other = UninitAllocator<U>;
    };
    UninitAllocator() = default;
    template <typename U>
    UninitAllocator(const UninitAllocator<U>&) noexcept {}
    template <typename U>
    void construct(U* p) noexcept {
        ::new (static_cast<void*>(p)) U;
    }
    template <typename U, typename... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};
template <typename T>
using UninitVector = std::vector<T, UninitAllocator<T>>;

/// @brief Do triangles ta and tb (vertex indices into p) cross at a point inside both?
/// Triangles sharing an edge never cross; with one shared vertex only the edges away
/// from it are tested. Coplanar overlaps are not counted.
bool triangles_cross(const std::vector<Vec3f>& p, const std::array<std::uint32_t, 3>& ta,
                     const std::array<std::uint32_t, 3>& tb);

/// @brief Broad phase for self-intersection queries: a uniform grid of about two mean
/// face sizes, built by sorting (cell, face) keys. Each face's box covers its triangle at
/// positions `a` and, when given, at positions `b` (and so at every blend of the two):
/// the index then answers for any vertex positions between the two poses, which is what
/// a stage that moves vertices back towards where they were needs. The index keeps
/// references to `triangles`, `a` and `b`: they must outlive it and not change.
class SelfIntersectionIndex {
public:
    struct Box {
        Vec3f lo, hi;
    };
    SelfIntersectionIndex(const std::vector<std::array<std::uint32_t, 3>>& triangles, const std::vector<Vec3f>& a,
                          const std::vector<Vec3f>* b = nullptr);
    /// Every crossing pair at positions `p` (each pair once, sorted). TBB-parallel.
    /// `progress`, when given, is called per chunk of cells with the fraction done (from the
    /// worker threads); it may throw to stop.
    std::vector<FacePair> all(const std::vector<Vec3f>& p, const std::function<void(double)>& progress = {}) const;
    /// The crossing pairs at positions `p` with at least one face in `faces` (sorted, unique).
    std::vector<FacePair> involving(const std::vector<std::uint32_t>& faces, const std::vector<Vec3f>& p) const;

private:
    struct Range {
        std::array<std::uint64_t, 3> lo{}, hi{};
    };
    Range cells(const Box& b) const;
    Box box(std::uint32_t face) const; ///< covering both poses
    std::uint64_t key(std::uint64_t i, std::uint64_t j, std::uint64_t k) const {
        return (i * dims_[1] + j) * dims_[2] + k;
    }

    const std::vector<std::array<std::uint32_t, 3>>& triangles_;
    const std::vector<Vec3f>& a_;
    const std::vector<Vec3f>* b_ = nullptr;
    Vec3d origin_;
    double cell_ = 1;
    std::array<std::uint64_t, 3> dims_{1, 1, 1};
    UninitVector<std::uint64_t> entries_; ///< (cell << 32) | face, sorted
    std::vector<std::size_t> runs_;       ///< starts of the runs of one cell in entries_, then entries_.size()
};

/// @brief The pairs of triangles of `mesh` that cross each other, sorted (see
/// triangles_cross). About 0.2 s for a million faces on two cores.
std::vector<FacePair> find_self_intersections(const Mesh& mesh);

/// @brief Number of pairs find_self_intersections() reports.
std::size_t count_self_intersections(const Mesh& mesh);

/// The output rules of a mesh leaving the tool: closed, 2-manifold, consistently oriented,
/// outward, no degenerate face, no crossing faces (mesh.write and `conceptmesh check`).
struct OutputCheck {
    MeshCheck mesh;
    std::vector<FacePair> crossings;
    /// Vertices with another vertex within kCoincidentTolerance of the bounding-box diagonal:
    /// an importer that merges by distance (Blender, most engines) welds them, and the
    /// welded mesh may be non-manifold where this one is not.
    std::size_t coincident_vertices = 0;
    bool clean() const;
    /// One phrase per broken rule ("3 boundary edges", ...); empty when clean.
    std::vector<std::string> broken() const;
};
/// `progress`, when given, is called per chunk with the fraction done and may throw to stop.
OutputCheck check_output(const Mesh& mesh, const std::function<void(double)>& progress = {});

/// Distance, as a fraction of the bounding-box diagonal, within which two vertices count
/// as one (a millionth: far above float rounding, far below any feature a mesh means).
constexpr double kCoincidentTolerance = 1e-6;
/// Vertices hashed into cells of twice a tolerance: a vertex within the tolerance of a point
/// lies in one of the 8 cells around the cell corner nearest to it.
class CoincidenceIndex {
public:
    /// Indexes `positions` (those listed in `only`, when given) as they are now.
    CoincidenceIndex(const std::vector<Vec3f>& positions, double tolerance,
                     const std::vector<std::uint32_t>* only = nullptr);
    /// Calls found(j), until it returns false, for the indexed vertices j other than `self`
    /// whose cell is near `p` (at most 8 cells; the caller checks the distance).
    template <typename F>
    void each_candidate(const Vec3f& p, std::uint32_t self, F&& found) const;
    double tolerance() const { return tolerance_; }

private:
    std::uint64_t key_at(const Vec3f& p, int dx, int dy, int dz, const int* dir) const;
    bool maybe(std::uint64_t key) const {
        const std::uint64_t b = (key * 0xD6E8FEB86659FD93ull) >> (64 - bits_log_);
        return occupied_[b >> 6] >> (b & 63) & 1;
    }
    double tolerance_, cell_;
    int bits_log_ = 16;
    std::vector<std::pair<std::uint64_t, std::uint32_t>> cells_; // sorted
    std::vector<std::uint64_t> occupied_;                        // a bit per hashed cell key
};

template <typename F>
void CoincidenceIndex::each_candidate(const Vec3f& p, std::uint32_t self, F&& found) const {
    int dir[3];
    for (int a = 0; a < 3; ++a) {
        const double u = double(p[a]) / cell_;
        dir[a] = u - std::floor(u) < 0.5 ? -1 : 1;
    }
    for (int k = 0; k < 8; ++k) {
        const std::uint64_t want = key_at(p, k & 1, (k >> 1) & 1, (k >> 2) & 1, dir);
        if (!maybe(want)) continue;
        auto it = std::lower_bound(cells_.begin(), cells_.end(), std::make_pair(want, std::uint32_t(0)));
        for (; it != cells_.end() && it->first == want; ++it)
            if (it->second != self && !found(it->second)) return;
    }
}

/// The vertices (ascending) that have another vertex within `tolerance` (absolute distance).
/// With `near`, only pairs with at least one vertex in `near` are looked for (both of each
/// such pair are returned): what a caller that moved only those vertices needs to re-check.
std::vector<std::uint32_t> find_coincident_vertices(const std::vector<Vec3f>& positions, double tolerance,
                                                    const std::vector<std::uint32_t>* near = nullptr);
/// Number of vertices that have another vertex within `tolerance` (absolute distance).
std::size_t count_coincident_vertices(const Mesh& mesh, double tolerance);

} // namespace cm
