// hull.plausible's handle cut (plausible_handles.h): two legs whose knees meet in the front
// view, at depths apart, make a visual hull with a ring through the body; `handles: cut` takes
// it out where it is thinnest, every line of sight of the drawn views keeping a voxel. A ring
// the drawings show (a frame seen through its opening) keeps its handle.
#include <gtest/gtest.h>

#include <filesystem>
#include <vector>

#include "geometry/mesh_check.h"
#include "hull_steps.h"
#include "io/mesh_io.h"
#include "marching_cubes.h"
#include "plausible.h"
#include "plausible_handles.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;
using namespace cm::test;
using openvdb::Coord;
using openvdb::CoordBBox;

namespace {

struct Box {
    Vec3d lo, hi;
};

// x lateral, y up, z depth. A body on two legs; each knee juts across to the other leg's side
// of the middle, the left one in front (z > 0), the right one behind: from the front the knees
// overlap, so the hull joins the legs there; in depth they are apart, so the object has no
// handle (genus 0).
const std::vector<Box> kLegs = {
    {{-3, 0, -1}, {3, 2, 1}},            // body
    {{-3, -5, -0.6}, {-1.8, 0, 0.6}},    // left leg
    {{1.8, -5, -0.6}, {3, 0, 0.6}},      // right leg
    {{-3, -3, 0.1}, {0.4, -2.8, 0.6}},   // left knee, in front
    {{-0.4, -3, -0.6}, {3, -2.8, -0.1}}, // right knee, behind
};

// A frame standing on a plinth, seen through its opening from the front: a drawn ring.
const std::vector<Box> kFrame = {
    {{-3, -3, -1}, {3, 0, 1}},       // plinth
    {{-2, 0, -0.4}, {-1.2, 3, 0.4}}, // left post
    {{1.2, 0, -0.4}, {2, 3, 0.4}},   // right post
    {{-2, 2.2, -0.4}, {2, 3, 0.4}},  // lintel
};

std::shared_ptr<const Views> views_of(const std::vector<Box>& parts, Vec3d lo, Vec3d hi) {
    std::vector<View> vs;
    for (const char* n : {"front", "right", "top"}) {
        const Vec3d d = Camera::named(n)->d;
        Outline all = box_outline(parts[0].lo, parts[0].hi, d);
        for (std::size_t k = 1; k < parts.size(); ++k)
            all = union_outline(all, box_outline(parts[k].lo, parts[k].hi, d));
        vs.push_back(ortho_view(n, 480, 60.0, all));
    }
    return make_views(std::move(vs), lo, hi);
}

// The visual hull kept as it is (roundness 0), its handles cut or kept.
Result<std::shared_ptr<Volume>, PlausibleStats> hull_with(const std::shared_ptr<const Volume>& hull,
                                                          const std::string& handles) {
    PlausibleOptions opt;
    opt.roundness = 0;
    opt.handles = handles;
    return make_plausible(*hull, nullptr, opt);
}

// Pieces and handles of the Marching Cubes surface: genus = pieces - Euler / 2.
std::pair<long, long> surface_genus(const Volume& v) {
    const MeshCheck c = check_mesh(marching_cubes(v).value);
    EXPECT_TRUE(c.closed_manifold());
    return {long(c.components), long(c.components) - c.euler / 2};
}

openvdb::BoolTree filled(const std::vector<CoordBBox>& on, const std::vector<CoordBBox>& off = {}) {
    openvdb::BoolTree t(false);
    for (const auto& b : on) t.fill(b, true, true);
    for (const auto& b : off) t.fill(b, false, false);
    return t;
}

} // namespace

TEST(HullPlausibleHandles, EulerAndPiecesOfVoxelSets) {
    // A block: one piece, no handle.
    auto t = plausible::voxel_topology(filled({CoordBBox({0, 0, 0}, {20, 12, 9})}));
    EXPECT_EQ(t.pieces, 1);
    EXPECT_EQ(t.euler, 1);
    // Two tunnels through it along z, one along x crossing neither: three handles.
    t = plausible::voxel_topology(filled(
        {CoordBBox({0, 0, 0}, {20, 12, 9})},
        {CoordBBox({3, 3, 0}, {5, 5, 9}), CoordBBox({12, 3, 0}, {14, 5, 9}), CoordBBox({0, 9, 3}, {20, 10, 5})}));
    EXPECT_EQ(t.pieces, 1);
    EXPECT_EQ(t.handles(), 3);
    // Three blocks, two of them touching by a corner only (one piece: 26-connected), across leaves.
    t = plausible::voxel_topology(filled(
        {CoordBBox({0, 0, 0}, {4, 4, 4}), CoordBBox({5, 5, 5}, {9, 9, 9}), CoordBBox({30, -20, 7}, {33, -17, 70})}));
    EXPECT_EQ(t.pieces, 2);
    EXPECT_EQ(t.handles(), 0);
    // A ring of voxels joined by edges alone (a diagonal loop) is a handle of the closed cubes.
    t = plausible::voxel_topology(filled({CoordBBox({0, 0, 0}, {0, 0, 0}), CoordBBox({1, 1, 0}, {1, 1, 0}),
                                          CoordBBox({0, 2, 0}, {0, 2, 0}), CoordBBox({-1, 1, 0}, {-1, 1, 0})}));
    EXPECT_EQ(t.pieces, 1);
    EXPECT_EQ(t.handles(), 1);
}

TEST(HullPlausibleHandles, KneesMeetingInTheFrontViewAreCutApart) {
    const auto views = views_of(kLegs, Vec3d(-3, -5, -1), Vec3d(3, 2, 1));
    const auto hull = carve_and_refine(views, 256);
    // The hull joins the knees: a ring through the body.
    const auto in = plausible::voxel_topology(hull->occupancy->tree());
    EXPECT_EQ(in.pieces, 1);
    EXPECT_EQ(in.handles(), 1);
    const auto kept = hull_with(hull, "keep");
    EXPECT_EQ(plausible::voxel_topology(kept.value->occupancy->tree()).handles(), 1);
    const auto cut = hull_with(hull, "cut");
    const PlausibleStats& st = cut.stats;
    EXPECT_EQ(st.handles, 1u);
    EXPECT_EQ(st.handles_left, 0u);
    EXPECT_GT(st.handle_voxels, 0u);
    // A cut, not a carving: a few hundred voxels of the knees' contact.
    EXPECT_LT(st.handle_voxels, 2000u);
    const auto out = plausible::voxel_topology(cut.value->occupancy->tree());
    EXPECT_EQ(out.pieces, 1);
    EXPECT_EQ(out.handles(), 0);
    // Every line of sight of the three views keeps a voxel.
    for (int axis = 0; axis < 3; ++axis) EXPECT_EQ(columns(*cut.value, axis), columns(*hull, axis)) << "axis " << axis;
    // The surface has the voxels' topology: one piece, genus 0 (and the kept hull genus 1).
    EXPECT_EQ(surface_genus(*cut.value), std::make_pair(1L, 0L));
    EXPECT_EQ(surface_genus(*kept.value), std::make_pair(1L, 1L));
}

TEST(HullPlausibleHandles, AFrameSeenThroughItsOpeningKeepsItsHandle) {
    const auto views = views_of(kFrame, Vec3d(-3, -3, -1), Vec3d(3, 3, 1));
    const auto hull = carve_and_refine(views, 128);
    EXPECT_EQ(plausible::voxel_topology(hull->occupancy->tree()).handles(), 1);
    const auto cut = hull_with(hull, "cut");
    EXPECT_EQ(cut.stats.handles, 1u);
    EXPECT_EQ(cut.stats.handles_left, 1u);
    EXPECT_EQ(cut.stats.handle_voxels, 0u);
    EXPECT_EQ(plausible::voxel_topology(cut.value->occupancy->tree()).handles(), 1);
}

TEST(HullPlausibleHandles, ALargeGridFindsItsCutsOnACoarserOneFirst) {
    // Over 320 cells the cut is found on a grid twice as coarse, then grown voxel by voxel
    // about it only: the same ring comes out, every line of sight keeping a voxel.
    const auto views = views_of(kLegs, Vec3d(-3, -5, -1), Vec3d(3, 2, 1));
    const auto hull = carve_and_refine(views, 384);
    const auto cut = hull_with(hull, "cut");
    EXPECT_EQ(cut.stats.handles, 1u);
    EXPECT_EQ(cut.stats.handles_left, 0u);
    EXPECT_GT(cut.stats.handle_voxels, 0u);
    // A cut one voxel thick across the knees' contact (about 2.3 times the 256 grid's).
    EXPECT_LT(cut.stats.handle_voxels, 4500u);
    for (int axis = 0; axis < 3; ++axis) EXPECT_EQ(columns(*cut.value, axis), columns(*hull, axis)) << "axis " << axis;
    EXPECT_EQ(surface_genus(*cut.value), std::make_pair(1L, 0L));
}

// The models of ../shared/data/models whose front is +z (bench/models.txt), drawn as the shape
// bench draws them (1024 px masks from front, right and top) and reconstructed with
// loft.yaml's options at 256: each surface one piece with the model's genus. Fertility's
// statue has four openings, its hull ten handles; the cut once left a pinhole through a plate
// where the growth went round a voxel (five). The camel's knees meet in its front view (two).
TEST(HullPlausibleHandles, ModelsDrawnAsMasksComeBackWithTheirGenus) {
    for (const auto& [name, genus] : {std::pair<std::string, long>{"fertility.off", 4}, {"camel.off", 0}}) {
        const auto file = shared_dir() / "data" / "models" / name;
        if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " is not there (../shared/data/models)";
        const Mesh m = read_mesh(file);
        const auto [lo, hi] = box_of(m);
        std::vector<View> vs;
        for (const char* n : {"front", "right", "top"}) vs.push_back(mask_view(m, n, *Camera::named(n), 1024, lo, hi));
        const auto hull = carve_and_refine(make_views(std::move(vs), lo, hi), 256);
        PlausibleOptions opt; // loft.yaml's
        opt.loft = 0.5;
        opt.hard_surface = 1.0;
        opt.ghost = 1.0;
        opt.handles = "cut";
        const auto cut = make_plausible(*hull, nullptr, opt);
        EXPECT_GT(cut.stats.handles, std::size_t(genus)) << name;
        EXPECT_EQ(surface_genus(*cut.value), std::make_pair(1L, genus)) << name;
    }
}
