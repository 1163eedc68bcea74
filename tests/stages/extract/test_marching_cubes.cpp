// extract.marching_cubes on volumes built in code: analytic shapes with exact
// crossings, tiles touching the outside, thin parts, and random occupancy that
// exercises every ambiguous configuration. Every mesh must be closed, 2-manifold,
// outward and free of degenerate faces.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <random>

#include "core/error.h"
#include "core/mesh.h"
#include "core/stage.h"
#include "core/volume.h"
#include "geometry/mesh_check.h"
#include "marching_cubes.h"
#include "mc_table.h"
#include "sdf_volume.h"
#include "support/stage_harness.h"

using namespace cm;
using openvdb::Coord;
using test::Sdf;
using test::volume_from_sdf;

namespace {

/// Empty thin_enter / thin_leave grids: where a part thinner than a cell enters and
/// leaves the edges from each grid point (-1: no crossing on that axis).
std::pair<openvdb::Vec3fGrid::Ptr, openvdb::Vec3fGrid::Ptr> thin_grids() {
    auto enter = openvdb::Vec3fGrid::create(openvdb::Vec3f(-1.0f));
    auto leave = openvdb::Vec3fGrid::create(openvdb::Vec3f(-1.0f));
    enter->setName("thin_enter");
    leave->setName("thin_leave");
    return {enter, leave};
}

double sphere_sdf(const Vec3d& p, const Vec3d& c, double r) { return length(p - c) - r; }

void expect_good(const Mesh& m, const char* what) {
    SCOPED_TRACE(what);
    const MeshCheck c = check_mesh(m);
    EXPECT_GT(m.face_count(), 0u);
    EXPECT_EQ(c.boundary_edges, 0u);
    EXPECT_EQ(c.nonmanifold_edges, 0u);
    EXPECT_EQ(c.nonmanifold_vertices, 0u);
    EXPECT_EQ(c.inconsistent_edges, 0u);
    EXPECT_EQ(c.degenerate_faces, 0u);
    EXPECT_GT(c.signed_volume, 0.0);
    // Every vertex is used (one per crossed edge, plus loop centroids).
    std::vector<char> used(m.positions.size(), 0);
    for (const auto& t : m.triangles)
        for (auto i : t) used[i] = 1;
    EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0);
}

} // namespace

TEST(MarchingCubesTable, EveryCaseBuildsClosedLoops) {
    const auto& t = mc::Table::get();
    const auto s = t.stats();
    // 256 configurations times every resolution of their ambiguous faces.
    std::size_t expected = 0;
    for (unsigned c = 0; c < 256; ++c) expected += std::size_t(1) << std::popcount(unsigned(t.ambiguous_faces(c)));
    EXPECT_EQ(s.cases, expected);
    EXPECT_EQ(s.fan + s.fixed + s.centroid, s.loops);
    EXPECT_LE(s.max_loop, 12u);
    std::printf("table: %zu cases, %zu loops (fan %zu, fixed %zu, centroid %zu), longest loop %zu\n", s.cases, s.loops,
                s.fan, s.fixed, s.centroid, s.max_loop);
    // The configuration with one inside corner is a single triangle; its complement too.
    for (unsigned c : {1u, 254u}) {
        const auto& cs = t.lookup(c, 0);
        ASSERT_EQ(cs.loop_count, 1);
        EXPECT_EQ(t.loop(cs.first_loop).size, 3);
    }
    // Every crossed edge is on exactly one loop.
    for (unsigned c = 0; c < 256; ++c) {
        const auto& cs = t.lookup(c, t.separating_bits(c));
        int count[12] = {};
        for (unsigned l = 0; l < cs.loop_count; ++l) {
            const auto& loop = t.loop(cs.first_loop + l);
            for (int k = 0; k < loop.size; ++k) ++count[loop.edges[std::size_t(k)]];
        }
        for (int e = 0; e < 12; ++e) {
            const auto d = mc::kEdges[std::size_t(e)];
            const bool crossed = ((c >> d.corner) & 1) != ((c >> (d.corner | (1 << d.axis))) & 1);
            EXPECT_EQ(count[e], crossed ? 1 : 0) << "config " << c << " edge " << e;
        }
    }
}

TEST(MarchingCubes, SphereVerticesLieOnTheSphere) {
    const Vec3d c{0.3, -0.2, 0.1};
    const double r = 9.5, h = 0.5;
    const Volume v = volume_from_sdf([&](const Vec3d& p) { return sphere_sdf(p, c, r); },
                                     openvdb::CoordBBox(Coord(-24), Coord(24)), h, {0, 0, 0});
    // Pruning made the interior tiles; the surface is in leaves.
    EXPECT_GT(v.occupancy->tree().activeTileCount(), 0u);
    const auto [m, st] = marching_cubes(v);
    expect_good(m, "sphere");
    const MeshCheck k = check_mesh(m);
    EXPECT_EQ(k.components, 1u);
    EXPECT_EQ(k.euler, 2);
    EXPECT_EQ(st.missing_crossings, 0u);
    const double exact = 4.0 / 3.0 * M_PI * r * r * r;
    EXPECT_NEAR(k.signed_volume, exact, 0.01 * exact);
    EXPECT_NEAR(k.area, 4 * M_PI * r * r, 0.01 * 4 * M_PI * r * r);
    // Every vertex is on the sphere, except those moved off a grid point by min_edge_fraction.
    std::size_t off = 0;
    for (const auto& p : m.positions) {
        const double d = std::abs(length(Vec3d(p) - c) - r);
        EXPECT_LT(d, 0.011 * h);
        off += d > 1e-4;
    }
    EXPECT_LT(off, m.positions.size() / 50);
}

TEST(MarchingCubes, MidpointsWithoutCrossings) {
    const Volume v = volume_from_sdf(
        [](const Vec3d& p) {
            return sphere_sdf(p, {0, 0, 0}, 6.2);
        },
        openvdb::CoordBBox(Coord(-10), Coord(10)), 1.0, {0, 0, 0}, false);
    ASSERT_FALSE(v.crossings);
    const Mesh m = marching_cubes(v).value;
    expect_good(m, "binary sphere");
    for (const auto& p : m.positions) {
        int halves = 0;
        for (int a = 0; a < 3; ++a) {
            const double f = p[a] - std::floor(p[a]);
            if (f == 0.5) ++halves;
            else EXPECT_EQ(f, 0.0);
        }
        EXPECT_EQ(halves, 1);
    }
    // The refined sphere's vertices are on the sphere; the binary ones up to half a cell off.
    const Volume vr = volume_from_sdf(
        [](const Vec3d& p) {
            return sphere_sdf(p, {0, 0, 0}, 6.2);
        },
        openvdb::CoordBBox(Coord(-10), Coord(10)), 1.0, {0, 0, 0}, true);
    auto mean_error = [](const Mesh& mesh) {
        double e = 0;
        for (const auto& p : mesh.positions) e += std::abs(length(Vec3d(p)) - 6.2);
        return e / double(mesh.positions.size());
    };
    EXPECT_GT(mean_error(m), 0.05);
    EXPECT_LT(mean_error(marching_cubes(vr).value), 0.002);
    // crossings = false ignores the refinement.
    MarchingCubesOptions plain;
    plain.use_crossings = false;
    EXPECT_EQ(marching_cubes(vr, plain).value.positions.size(), m.positions.size());
}

TEST(MarchingCubes, BoxOnTileBoundariesIsExact) {
    // Inside points [0, 127]^3: one level-1 tile whose faces are the surface, no leaves.
    Volume v;
    v.occupancy = openvdb::BoolGrid::create(false);
    v.occupancy->setTransform(openvdb::math::Transform::createLinearTransform(0.25));
    v.occupancy->tree().fill(openvdb::CoordBBox(Coord(0), Coord(127)), true, true);
    ASSERT_EQ(v.occupancy->tree().leafCount(), 0u);
    ASSERT_EQ(v.occupancy->tree().activeTileCount(), 1u);
    const auto [m, st] = marching_cubes(v);
    expect_good(m, "tile box");
    EXPECT_EQ(st.surface_cells, std::size_t(6 * 127 * 127 + 12 * 127 + 8));
    Vec3f lo, hi;
    m.bounds(lo, hi);
    for (int a = 0; a < 3; ++a) {
        EXPECT_FLOAT_EQ(lo[a], -0.5f * 0.25f);
        EXPECT_FLOAT_EQ(hi[a], 127.5f * 0.25f);
    }
    // Faces flat, edges and corners chamfered: volume just under the box's.
    const double side = 128 * 0.25;
    const double vol = check_mesh(m).signed_volume;
    EXPECT_LT(vol, side * side * side);
    EXPECT_GT(vol, 0.99 * side * side * side);
}

TEST(MarchingCubes, BoxWithExactCrossingsAndTransform) {
    const Vec3d lo{-3.3, 1.1, 0.45}, hi{4.7, 6.9, 5.05};
    auto box_sdf = [&](const Vec3d& p) {
        double d = -1e9;
        for (int a = 0; a < 3; ++a) d = std::max(d, std::max(lo[a] - p[a], p[a] - hi[a]));
        return d;
    };
    const Vec3d origin{-5, -1, -2};
    const Volume v = volume_from_sdf(box_sdf, openvdb::CoordBBox(Coord(0), Coord(40)), 0.4, origin);
    const Mesh m = marching_cubes(v).value;
    expect_good(m, "box");
    Vec3f mlo, mhi;
    m.bounds(mlo, mhi);
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(mlo[a], lo[a], 1e-4);
        EXPECT_NEAR(mhi[a], hi[a], 1e-4);
    }
    const double exact = (hi.x - lo.x) * (hi.y - lo.y) * (hi.z - lo.z);
    EXPECT_NEAR(check_mesh(m).signed_volume, exact, 0.02 * exact);
}

TEST(MarchingCubes, TwoTouchingSpheres) {
    // Two spheres touching at one point between grid points, and two overlapping barely:
    // near-contact configurations with ambiguous faces.
    for (double gap : {0.0, -0.05, 0.05}) {
        const double r = 4.3;
        const Vec3d c1{0.1, 0.2, 0.3}, c2 = c1 + Vec3d(1, 1, 1) * ((2 * r + gap) / std::sqrt(3.0));
        auto sdf = [&](const Vec3d& p) { return std::min(sphere_sdf(p, c1, r), sphere_sdf(p, c2, r)); };
        const Volume v = volume_from_sdf(sdf, openvdb::CoordBBox(Coord(-8), Coord(16)), 1.0, {0, 0, 0});
        for (auto amb : {MarchingCubesOptions::Ambiguity::Geometric, MarchingCubesOptions::Ambiguity::Separate,
                         MarchingCubesOptions::Ambiguity::Join}) {
            MarchingCubesOptions o;
            o.ambiguity = amb;
            const Mesh m = marching_cubes(v, o).value;
            expect_good(m, "touching spheres");
            const MeshCheck k = check_mesh(m);
            if (gap > 0 && amb == MarchingCubesOptions::Ambiguity::Separate) {
                EXPECT_EQ(k.components, 2u);
            }
        }
    }
}

TEST(MarchingCubes, RandomOccupancyStaysManifold) {
    std::mt19937 rng(12345);
    for (int trial = 0; trial < 24; ++trial) {
        const double density = 0.2 + 0.6 * (trial % 4) / 3.0;
        Volume v;
        v.occupancy = openvdb::BoolGrid::create(false);
        v.crossings = openvdb::Vec3fGrid::create(openvdb::Vec3f(-1.0f));
        auto acc = v.occupancy->getAccessor();
        std::uniform_real_distribution<double> u(0, 1);
        const int n = 13 + trial % 5;
        const Coord shift(trial * 3 - 30, 5 - trial, 8 * (trial % 3) - 4); // across block and sign boundaries
        for (int x = 0; x < n; ++x)
            for (int y = 0; y < n; ++y)
                for (int z = 0; z < n; ++z)
                    if (u(rng) < density) acc.setValueOn(Coord(x, y, z) + shift, true);
        // Random crossings, including exact 0 and 1 (coincident with grid points).
        auto cacc = v.crossings->getAccessor();
        for (int x = -1; x <= n; ++x)
            for (int y = -1; y <= n; ++y)
                for (int z = -1; z <= n; ++z) {
                    const Coord p = Coord(x, y, z) + shift;
                    openvdb::Vec3f c(-1.0f);
                    bool any = false;
                    for (int a = 0; a < 3; ++a) {
                        Coord q = p;
                        q[a] += 1;
                        if (acc.isValueOn(p) == acc.isValueOn(q)) continue;
                        const double r = u(rng);
                        c[a] = r < 0.1 ? 0.0f : r < 0.2 ? 1.0f : float(u(rng));
                        any = true;
                    }
                    if (any) cacc.setValueOn(p, c);
                }
        for (auto amb : {MarchingCubesOptions::Ambiguity::Geometric, MarchingCubesOptions::Ambiguity::Separate,
                         MarchingCubesOptions::Ambiguity::Join}) {
            MarchingCubesOptions o;
            o.ambiguity = amb;
            const auto [m, st] = marching_cubes(v, o);
            expect_good(m, ("random trial " + std::to_string(trial)).c_str());
            EXPECT_EQ(st.missing_crossings, 0u);
            if (trial == 0) {
                EXPECT_GT(st.ambiguous_faces, 0u);
            }
        }
    }
}

TEST(MarchingCubes, ThinSheetBetweenGridPointsSurvives) {
    // A sheet 0.2 cells thick inside the cells between x = 10 and x = 11: every grid point
    // is outside, only the x-edges through it know (thin_enter/thin_leave).
    Volume v;
    v.occupancy = openvdb::BoolGrid::create(false);
    auto [enter, leave] = thin_grids();
    for (int y = 5; y <= 15; ++y)
        for (int z = 5; z <= 15; ++z) {
            enter->tree().setValueOn(Coord(10, y, z), openvdb::Vec3f(0.3f, -1.0f, -1.0f));
            leave->tree().setValueOn(Coord(10, y, z), openvdb::Vec3f(0.5f, -1.0f, -1.0f));
        }
    v.extra = {enter, leave};
    const auto [m, st] = marching_cubes(v);
    expect_good(m, "thin sheet");
    EXPECT_EQ(st.thin_points, 121u);
    EXPECT_EQ(check_mesh(m).components, 1u);
    Vec3f lo, hi;
    m.bounds(lo, hi);
    EXPECT_NEAR(hi.x, 10.5f, 1e-5);   // the far side of the sheet, exact
    EXPECT_NEAR(lo.x, 10.3f, 0.011f); // the near side, moved onto the part's near face
    EXPECT_NEAR(lo.y, 4.99f, 1e-5);   // the edges hug the outermost thin edges
    EXPECT_NEAR(hi.y, 15.01f, 1e-5);
    // Without the thin grids nothing is inside.
    MarchingCubesOptions off;
    off.use_thin = false;
    EXPECT_TRUE(marching_cubes(v, off).value.triangles.empty());
}

TEST(MarchingCubes, SurfaceBulgeBetweenGridPointsRaisesNoSpike) {
    // An x-edge just outside a box face whose ends are outside but whose middle grazes a
    // bump of the surface: next to the solid, alone, so it is not promoted.
    const Volume body = volume_from_sdf(
        [](const Vec3d& p) {
            return std::max({std::abs(p.x) - 4.5, std::abs(p.y) - 4.5, std::abs(p.z) - 4.5});
        },
        openvdb::CoordBBox(Coord(-8), Coord(8)), 1.0, {0, 0, 0});
    Volume v = body;
    auto [enter, leave] = thin_grids();
    enter->tree().setValueOn(Coord(0, 5, 0), openvdb::Vec3f(0.4f, -1.0f, -1.0f));
    leave->tree().setValueOn(Coord(0, 5, 0), openvdb::Vec3f(0.6f, -1.0f, -1.0f));
    v.extra = {enter, leave};
    const auto [m, st] = marching_cubes(v);
    expect_good(m, "box with bulge");
    EXPECT_EQ(st.thin_points, 0u);
    Vec3f lo, hi;
    m.bounds(lo, hi);
    EXPECT_NEAR(hi.y, 4.5f, 1e-4);
}

TEST(MarchingCubes, ThinRodNextToABody) {
    // A body with exact crossings, plus a rod thinner than a cell along z attached to it.
    const Volume body = volume_from_sdf(
        [](const Vec3d& p) {
            return sphere_sdf(p, {0, 0, 0}, 5.0);
        },
        openvdb::CoordBBox(Coord(-8), Coord(8)), 1.0, {0, 0, 0});
    Volume v = body;
    auto [enter, leave] = thin_grids();
    // The rod runs along +x at y = 0.3..0.6 (between y = 0 and 1), z = 0: y-edges at (x, 0, 0).
    for (int x = 5; x <= 12; ++x) {
        enter->tree().setValueOn(Coord(x, 0, 0), openvdb::Vec3f(-1.0f, 0.3f, -1.0f));
        leave->tree().setValueOn(Coord(x, 0, 0), openvdb::Vec3f(-1.0f, 0.6f, -1.0f));
    }
    v.extra = {enter, leave};
    const Mesh m = marching_cubes(v).value;
    expect_good(m, "body with rod");
    EXPECT_EQ(check_mesh(m).components, 1u);
    Vec3f lo, hi;
    m.bounds(lo, hi);
    EXPECT_GT(hi.x, 12.0f);
    EXPECT_LT(hi.x, 13.0f);
}

TEST(MarchingCubes, EmptyAndBadVolumes) {
    Volume v;
    EXPECT_THROW(marching_cubes(v), Error);
    v.occupancy = openvdb::BoolGrid::create(false);
    EXPECT_TRUE(marching_cubes(v).value.triangles.empty());
    // A single inside point: an octahedron.
    v.occupancy->tree().setValueOn(Coord(3, -4, 5), true);
    const Mesh m = marching_cubes(v).value;
    expect_good(m, "single point");
    EXPECT_EQ(m.face_count(), 8u);
    EXPECT_EQ(m.vertex_count(), 6u);
    // Crossings on another transform are refused.
    v.crossings = openvdb::Vec3fGrid::create(openvdb::Vec3f(-1.0f));
    v.crossings->setTransform(openvdb::math::Transform::createLinearTransform(2.0));
    EXPECT_THROW(marching_cubes(v), Error);
}

TEST(ExtractMarchingCubesStage, ReportsCountsAndRefusesAnEmptyVolume) {
    test::StageHarness stage("extract.marching_cubes"); // every parameter at its default
    const StageInfo info = stage.info();
    EXPECT_EQ(info.name, "extract.marching_cubes");

    auto vol = std::make_shared<Volume>(volume_from_sdf(
        [](const Vec3d& p) {
            return sphere_sdf(p, {0, 0, 0}, 5.3);
        },
        openvdb::CoordBBox(Coord(-8), Coord(8)), 1.0, {0, 0, 0}));
    stage.input("volume", vol);
    const auto mesh = stage.run<Mesh>();
    ASSERT_TRUE(mesh);
    const auto& m = stage.metrics();
    EXPECT_EQ(m.at("faces"), std::to_string(mesh->face_count()) + ".0");
    EXPECT_EQ(m.at("boundary_edges"), "0.0");
    EXPECT_EQ(m.at("nonmanifold_vertices"), "0.0");
    EXPECT_EQ(m.at("refined"), "\"yes\"");
    EXPECT_TRUE(stage.warnings().empty());

    auto empty = std::make_shared<Volume>();
    empty->occupancy = openvdb::BoolGrid::create(false);
    stage.input("volume", empty);
    try {
        stage.run<Mesh>();
        FAIL() << "an empty volume must be refused";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("no surface"), std::string::npos) << e.what();
    }
}
