// Flat caps flipped away (geometry/flat_caps.h): the surface kept, no face of no area left.
#include <gtest/gtest.h>

#include "core/mesh.h"
#include "geometry/flat_caps.h"
#include "geometry/mesh_check.h"
#include "support/shapes.h"

using namespace cm;

TEST(FlatCaps, ACapIsFlippedAndTheSurfaceStaysAsItWas) {
    Mesh m = test::make_box_with_flat_cap({0, 0, 0}, {2, 1, 3});
    const MeshCheck before = check_mesh(m);
    ASSERT_EQ(before.degenerate_faces, 1u);
    ASSERT_TRUE(before.closed_manifold());
    const FlatCaps r = flip_flat_caps(m);
    EXPECT_EQ(r.found, 1u);
    EXPECT_EQ(r.flipped, 1u);
    EXPECT_EQ(r.left, 0u);
    EXPECT_EQ(count_flat_caps(m), 0u);
    const MeshCheck after = check_mesh(m);
    EXPECT_EQ(after.degenerate_faces, 0u);
    EXPECT_TRUE(after.closed_manifold());
    EXPECT_EQ(after.inconsistent_edges, 0u);
    EXPECT_EQ(m.face_count(), test::make_box_with_flat_cap({0, 0, 0}, {2, 1, 3}).face_count());
    EXPECT_NEAR(after.area, 2 * (2 * 1 + 1 * 3 + 2 * 3), 1e-9);
    EXPECT_NEAR(after.signed_volume, 6.0, 1e-9);
}

TEST(FlatCaps, AMeshWithoutCapsIsLeftAsItIs) {
    Mesh m = test::make_sphere({0, 0, 0}, 1.0f, 3);
    const Mesh before = m;
    const FlatCaps r = flip_flat_caps(m);
    EXPECT_EQ(r.found, 0u);
    EXPECT_EQ(m.triangles, before.triangles);
}

TEST(FlatCaps, ACapAcrossATextureSeamIsLeft) {
    // Corner UVs that differ across the cap's long edge: flipping would join two charts.
    Mesh m = test::make_box_with_flat_cap({0, 0, 0}, {1, 1, 1});
    m.corner_uvs.assign(3 * m.face_count(), {0.25f, 0.25f});
    for (std::size_t k = 0; k < 3; ++k) m.corner_uvs[3 * (m.face_count() - 1) + k] = {0.75f, 0.75f};
    const FlatCaps r = flip_flat_caps(m);
    EXPECT_EQ(r.found, 1u);
    EXPECT_EQ(r.flipped, 0u);
    EXPECT_EQ(r.left, 1u);
}
