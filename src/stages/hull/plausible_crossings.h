// Step 7 of hull.plausible (plausible_state.h): the output volume's crossings. The input's
// exact crossings stay wherever an edge still runs from an inside point to a point outside the
// hull; edges into the removed region get the smoothed field's zero crossing.
#pragma once
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <openvdb/openvdb.h>

#include "core/volume.h"
#include "leaf_masks.h"
#include "util/uninit_vector.h"

namespace cm::plausible {

/// The hull's voxels by leaf and the field on them, through the voxels' numbering
/// (HullVoxels: voxel index = base[leaf] + rank of the voxel in its leaf's mask).
struct HullField {
    const std::vector<LeafMask>& masks;   ///< the hull's voxels, per leaf
    const std::vector<Coord>& origins;    ///< each leaf's origin
    const std::vector<std::size_t>& base; ///< each leaf's first voxel index
    const UninitVector<float>& field;     ///< the field, per voxel
};

/// The field at a grid point of the hull (0 elsewhere), through the voxels' numbering.
class FieldAt {
public:
    explicit FieldAt(const HullField& hull) : hull_(hull) {
        leaf_of_.reserve(hull.origins.size() * 2);
        for (std::size_t l = 0; l < hull.origins.size(); ++l)
            leaf_of_.emplace(leaf_key(hull.origins[l]), std::uint32_t(l));
    }
    float operator()(const Coord& g) const {
        const auto it = leaf_of_.find(leaf_key(g));
        if (it == leaf_of_.end()) return 0.0f;
        const std::size_t l = it->second;
        const openvdb::Index off = openvdb::BoolGrid::TreeType::LeafNodeType::coordToOffset(g);
        const std::uint64_t bit = std::uint64_t(1) << (off & 63), word = hull_.masks[l][off >> 6];
        if (!(word & bit)) return 0.0f;
        std::size_t i = hull_.base[l] + std::size_t(__builtin_popcountll(word & (bit - 1)));
        for (openvdb::Index w = 0; w < (off >> 6); ++w) i += std::size_t(__builtin_popcountll(hull_.masks[l][w]));
        return hull_.field[i];
    }

private:
    const HullField& hull_;
    std::unordered_map<std::uint64_t, std::uint32_t> leaf_of_;
};

/// The crossings of the volume whose occupancy is `now` (a subset of the hull's, `in`'s, with
/// removed voxels put back in places): `in`'s crossings, the leaves at `touched` (sorted, each
/// once: those about the removed voxels) made anew, a leaf kept only where it holds a crossing.
/// `placed` gets the number of crossings placed on the field's zero level.
openvdb::Vec3fGrid::Ptr recrossed(const Volume& in, const openvdb::BoolGrid& now, const std::vector<Coord>& touched,
                                  const HullField& hull, std::size_t& placed);

} // namespace cm::plausible
