// The field of hull.plausible on grids finer than 256: smoothed afterwards over more cells than
// it changes on (the Gaussian's 2.5 cells at 256 are 5 at 512), it is taken only at the hull's
// voxels on the lattice of grid points every `stride` cells, and at the few voxels that no such
// point of the hull surrounds, and interpolated trilinearly in between (stride^3 fewer
// evaluations of the views' fields, their join and the lofted prior).
#pragma once
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tree/LeafManager.h>

#include "util/uninit_vector.h"

#include "leaf_masks.h"

namespace cm::plausible {

class CoarseLattice {
public:
    using Leaves = openvdb::tree::LeafManager<openvdb::BoolTree>;
    /// The lattice every `stride` cells (2 to 8) over the voxels of `leaves`, numbered leaf
    /// base + rank of the on voxel (`base`, as HullVoxels).
    CoarseLattice(const Leaves& leaves, const std::vector<std::size_t>& base, int stride);

    int stride() const { return s_; }
    /// Per leaf (LeafManager order), the voxels whose value is taken exactly: those on the
    /// lattice, and those with no lattice point of the hull among the corners of their
    /// lattice cell that weigh in (a part thinner than the lattice between its points).
    const std::vector<LeafMask>& exact() const { return exact_; }
    /// Every voxel not in exact() gets the trilinear value of `value` at the lattice points of
    /// the hull about it (the others weigh nothing; the weights renormalised). With `flags`,
    /// bit `bit` of a voxel not in exact() is set where the same interpolation of that bit is
    /// at least 0.5, cleared elsewhere.
    void interpolate(UninitVector<float>& value, UninitVector<std::uint8_t>* flags, std::uint8_t bit) const;

private:
    struct Frame;
    Frame frame(std::size_t l) const;
    // Per lattice point about leaf l (m^3 of them, see Frame): the index of its voxel, or
    // kNone where the hull has no voxel there.
    void points(std::size_t l, const Frame& f, std::uint32_t* index) const;
    void interpolate_leaf(std::size_t l, UninitVector<float>& value, UninitVector<std::uint8_t>* flags,
                          std::uint8_t bit) const;

    static constexpr std::uint32_t kNone = ~std::uint32_t(0);
    const Leaves& leaves_;
    const std::vector<std::size_t>& base_;
    const int s_;
    std::unordered_map<std::uint64_t, std::uint32_t> leaf_of_;
    std::vector<LeafMask> exact_;
};

} // namespace cm::plausible
