// Self-intersection test of a triangle mesh: for checks in tests, benchmarks and run
// reports ("no self-intersections" is one of the output quality rules), and for the
// stages that must not create any (smoothing repairs the faces it finds here).
#pragma once
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/mesh.h"
#include "core/progress.h"
#include "util/uninit_vector.h"

namespace cm {

using FacePair = std::array<std::uint32_t, 2>; ///< (a, b) with a < b

/// The pairs each thread found (a tbb::enumerable_thread_specific of vectors of pairs, or any
/// range of them), as one sorted list without repeats.
template <typename PerThread>
std::vector<FacePair> merged_pairs(PerThread& found) {
    std::vector<FacePair> pairs;
    for (auto& v : found) pairs.insert(pairs.end(), v.begin(), v.end());
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    return pairs;
}

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
    /// `progress` hears the fraction done per chunk of cells (from the worker threads); a stop
    /// there ends the search (cm::Cancelled). `fans` (optional): embedded_fans() of the
    /// triangles at `p`; two faces sharing only a vertex whose fan is embedded are not tested
    /// (they cannot cross), which leaves the answer as it is.
    std::vector<FacePair> all(const std::vector<Vec3f>& p, Progress progress = {},
                              const std::vector<char>* fans = nullptr) const;
    /// The crossing pairs at positions `p` with at least one face in `faces` (sorted, unique).
    std::vector<FacePair> involving(const std::vector<std::uint32_t>& faces, const std::vector<Vec3f>& p) const;
    /// The faces whose boxes reach the cell holding `point` (into `out`, replacing it): among
    /// them every face with a corner at `point` in either pose.
    void faces_near(const Vec3f& point, std::vector<std::uint32_t>& out) const;
    /// The faces whose boxes reach a cell that `b` reaches (into `out`, replacing it; sorted,
    /// unique): among them every face whose box (covering both poses) meets `b`.
    void candidates(const Box& b, std::vector<std::uint32_t>& out) const;

private:
    class Builder; // the constructor's steps
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
    double cell_ = 1, inv_cell_ = 1; ///< cell size, and its inverse (cells() multiplies)
    std::array<std::uint64_t, 3> dims_{1, 1, 1};
    // An entry: (cell << 32) | (first << kFaceBits) | face, sorted. `first` (3 bits, when the
    // face count leaves room for them: low_bits_) says on which axes the cell is the first of
    // the face's box, which is what the pair pass needs of each face it gathers.
    static constexpr int kFaceBits = 29;
    static constexpr std::uint64_t kFaceMask = (std::uint64_t(1) << kFaceBits) - 1;
    bool low_bits_ = false;
    std::uint32_t face_of(std::uint64_t entry) const {
        return low_bits_ ? std::uint32_t(entry & kFaceMask) : std::uint32_t(entry);
    }
    UninitVector<std::uint64_t> entries_;
    std::vector<std::size_t> runs_; ///< starts of the runs of one cell in entries_, then entries_.size()
};

/// @brief Per vertex of `p`: whether the faces around it form one fan that lies over a plane
/// one-to-one. That is so when every face turns the same way about the fan's summed normal
/// (by a margin), each neighbour follows the vertex in as many faces as it precedes it in (the
/// faces close up into cycles), and the faces' angles at the vertex, seen along that normal,
/// add up to less than two turns (so there is one cycle, winding once). Two faces that share
/// only such a vertex then meet only there: their shadows on the plane are sectors around the
/// vertex with no other point in common. Most vertices of a smooth surface qualify; a crossing
/// test of all pairs may leave theirs out (SelfIntersectionIndex::all). TBB-parallel.
std::vector<char> embedded_fans(const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                const std::vector<Vec3f>& p);

/// @brief The pairs of triangles of `mesh` that cross each other, sorted (see
/// triangles_cross; pairs sharing only a vertex whose fan is embedded are left out untested,
/// see embedded_fans). About 0.2 s for a million faces on two cores. `progress` as in
/// SelfIntersectionIndex::all(). The last few answers are kept by a 128-bit fingerprint of the
/// positions and triangles: the same mesh asked again (mesh.reduce checks its result,
/// mesh.write what it writes) is answered at the cost of the fingerprint (under a millisecond
/// for 100 k faces).
std::vector<FacePair> find_self_intersections(const Mesh& mesh, Progress progress = {});

/// @brief Number of pairs find_self_intersections() reports.
std::size_t count_self_intersections(const Mesh& mesh);

/// Distance, as a fraction of the bounding-box diagonal, within which two vertices count
/// as one (a millionth: far above float rounding, far below any feature a mesh means).
constexpr double kCoincidentTolerance = 1e-6;
/// @brief Which vertices lie within a distance of another, asked again as a few vertices
/// move: a stage that moves vertices back one by one (the smoothing guard) re-asks only
/// about those and their neighbours instead of the whole mesh. Keeps a reference to
/// `positions`; call moved(v) after changing positions[v].
class CoincidenceIndex {
public:
    CoincidenceIndex(const std::vector<Vec3f>& positions, double tolerance);
    /// The vertices (ascending) with another vertex within the tolerance. TBB-parallel.
    std::vector<std::uint32_t> all() const;
    /// Whether another vertex lies within the tolerance of v.
    bool has_near(std::uint32_t v) const;
    /// Calls f(j) for each vertex j != v within the tolerance of v.
    void near(std::uint32_t v, const std::function<void(std::uint32_t)>& f) const;
    /// Calls f(j) for each vertex j within the tolerance of the point p.
    void near_point(const Vec3f& p, const std::function<void(std::uint32_t)>& f) const;
    /// positions[v] has changed.
    void moved(std::uint32_t v);

private:
    struct Entry {
        std::uint32_t key; ///< the cell's
        std::uint32_t v;
    };
    static constexpr std::uint32_t kNone = 0xFFFFFFFFu;
    std::uint32_t key_of(const Vec3f& p) const;
    bool close(const Vec3f& p, const Vec3f& q) const;
    std::size_t run_of(std::uint32_t key) const; ///< first entry of the cell, or sorted_.size()
    // Calls f for the vertices of the cell `key` within the tolerance of p (v's position)
    // until f returns false (then returns false); `from` is the index of v's own entry when
    // `key` is its cell, else sorted_.size().
    bool in_cell(std::uint32_t v, const Vec3f& p, std::uint32_t key, std::size_t from,
                 const std::function<bool(std::uint32_t)>& f) const;
    void visit(std::uint32_t v, std::size_t slot, const std::function<bool(std::uint32_t)>& f) const;
    // The same about the point p, leaving out vertex v (kNone: none).
    void visit_at(const Vec3f& p, std::uint32_t v, std::size_t slot, const std::function<bool(std::uint32_t)>& f) const;

    const std::vector<Vec3f>& positions_;
    double tol2_ = 0, cell_ = 1, reach_ = 0;
    Vec3d lo_, hi_;                                               ///< the box of the positions at build time
    std::vector<Entry> sorted_;                                   ///< by cell key, at build time
    bool any_stale_ = false;                                      ///< some vertex has moved since
    std::vector<std::uint32_t> table_;                            ///< hash table: the first entry of each cell's run
    std::vector<char> stale_;                                     ///< moved since: its entry is stale
    std::unordered_multimap<std::uint32_t, std::uint32_t> moved_; ///< moved vertices by their cell key
    std::unordered_map<std::uint32_t, std::uint32_t> moved_key_;
};

/// The vertices (ascending) that have another vertex within `tolerance` (absolute distance).
std::vector<std::uint32_t> find_coincident_vertices(const std::vector<Vec3f>& positions, double tolerance);
/// Number of vertices that have another vertex within `tolerance` (absolute distance).
std::size_t count_coincident_vertices(const Mesh& mesh, double tolerance);

} // namespace cm
