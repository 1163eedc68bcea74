// A block of hull voxels and a field over it, handed to hull.plausible's output volume as the
// removal leaves them: the tests of what the output volume does with a given removal.
#pragma once
#include <memory>

#include "plausible_state.h"

namespace cm::test {

struct RemovalBlock {
    Volume hull;
    std::unique_ptr<plausible::HullVoxels> vox;
    UninitVector<std::uint8_t> removed;
    UninitVector<float> field;
    PlausibleStats st;

    /// The hull is `box` filled; `field_at(coord)` is each voxel's field (above 0: removed).
    template <typename F>
    RemovalBlock(const openvdb::CoordBBox& box, F&& field_at) {
        hull.occupancy = openvdb::BoolGrid::create(false);
        hull.occupancy->tree().denseFill(box, true, true);
        vox = std::make_unique<plausible::HullVoxels>(*hull.occupancy);
        removed.resize(vox->n);
        field.resize(vox->n);
        for (std::size_t i = 0; i < vox->n; ++i) {
            field[i] = field_at(vox->coord_of(i));
            removed[i] = field[i] > 0;
            st.removed += removed[i];
        }
    }
    std::shared_ptr<Volume> run() {
        return plausible::plausible_volume(hull, *vox, removed, field, {}, false, st, Progress{});
    }
};

} // namespace cm::test
