// hull.plausible on shapes drawn in code: a sphere comes out round, a cube stays a cube
// at roundness 0, a thin fin survives, and every line of sight keeps its voxel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <set>

#include "core/stage.h"
#include "geometry/distance_transform.h"
#include "geometry/hull_distance.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_intersect.h"
#include "hull_steps.h"
#include "load.h"
#include "marching_cubes.h"
#include "mesh_smooth.h"
#include "plausible.h"
#include "plausible_rays.h"
#include "render/raster.h"
#include "support/shapes.h"
#include "support/stage_harness.h"
#include "support/test_support.h"

using namespace cm;
using namespace cm::test;

namespace {

std::shared_ptr<Views> views_of(const std::vector<std::string>& names, int size, double scale,
                                const std::function<Outline(const Camera&)>& outline, Vec3d lo, Vec3d hi) {
    std::vector<View> vs;
    for (const auto& n : names) vs.push_back(ortho_view(n, size, scale, outline(*Camera::named(n))));
    return make_views(std::move(vs), lo, hi);
}

std::shared_ptr<Views> sphere_views(double r) {
    return views_of({"front", "right", "top"}, 320, 150.0, [r](const Camera&) { return sphere_outline(r); },
                    {-r, -r, -r}, {r, r, r});
}

std::size_t occupied(const Volume& v) { return std::size_t(v.occupancy->activeVoxelCount()); }

// Every grid line along x, y and z that held a voxel of the hull still holds one.
void expect_columns_kept(const Volume& hull, const Volume& out) {
    for (int a = 0; a < 3; ++a) EXPECT_EQ(columns(hull, a), columns(out, a)) << "axis " << a;
}

// Mean distance of the mesh's vertices from the sphere of radius r at the origin, in r
// (signed: positive outside).
double sphere_deviation(const Mesh& m, double r, bool signed_mean = false) {
    double s = 0;
    for (const auto& p : m.positions) {
        const double d = double(length(Vec3d(p))) - r;
        s += signed_mean ? d : std::abs(d);
    }
    return s / double(m.positions.size()) / r;
}

// Pixels of `ref` (a re-rendered hull) the mesh `m` leaves uncovered, over all views.
double uncovered_pct(const Mesh& hull, const Mesh& m, const Views& views) {
    double lost = 0, total = 0;
    for (const auto& v : views.views) {
        const auto a = render_mask(hull, v.camera, v.width, v.height);
        const auto b = render_mask(m, v.camera, v.width, v.height);
        for (std::size_t i = 0; i < a.size(); ++i) {
            total += a[i];
            lost += a[i] && !b[i];
        }
    }
    return 100.0 * lost / std::max(total, 1.0);
}

// The angles (degrees) between each vertex normal of `m` and the sphere's radial direction
// there, sorted: how far the surface is from round, crease by crease.
std::vector<double> normal_deviation(Mesh m) {
    m.compute_normals();
    std::vector<double> out;
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
        const Vec3d p(m.positions[v]), nv(m.normals[v]);
        const double c = dot(p, nv) / std::max(length(p) * length(nv), 1e-30);
        out.push_back(std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / 3.14159265358979);
    }
    std::sort(out.begin(), out.end());
    return out;
}

// The number of connected pieces of a mesh (by shared vertices).
std::size_t pieces(const Mesh& m) {
    std::vector<std::uint32_t> parent(m.positions.size());
    for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = std::uint32_t(i);
    auto find = [&](std::uint32_t a) {
        while (parent[a] != a) a = parent[a] = parent[parent[a]];
        return a;
    };
    for (const auto& t : m.triangles)
        for (int k = 1; k < 3; ++k) parent[find(t[std::size_t(k)])] = find(t[0]);
    std::set<std::uint32_t> roots;
    for (const auto& t : m.triangles) roots.insert(find(t[0]));
    return roots.size();
}

} // namespace

TEST(HullPlausible, ProfileFractionIsRoundAndBlends) {
    EXPECT_DOUBLE_EQ(profile_fraction(1.0, 2.0, 1.0), 1.0);
    EXPECT_DOUBLE_EQ(profile_fraction(0.0, 2.0, 1.0), 0.0);
    EXPECT_NEAR(profile_fraction(0.5, 2.0, 1.0), std::sqrt(0.75), 1e-12);
    EXPECT_DOUBLE_EQ(profile_fraction(0.3, 2.0, 0.0), 1.0);
    EXPECT_NEAR(profile_fraction(0.0, 2.0, 0.5), 0.5, 1e-12);
    EXPECT_GT(profile_fraction(0.2, 6.0, 1.0), profile_fraction(0.2, 2.0, 1.0)); // flatter
}

TEST(HullPlausible, LocalInscribedRadiusOfADiscAndABar) {
    // A disc of radius 20 beside a bar 6 cells high: the disc's cells get about 20, the bar's 3.
    const int w = 100, h = 60;
    std::vector<char> outside(std::size_t(w) * h, 1);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool disc = std::hypot(x - 25.0, y - 30.0) < 20.0;
            const bool bar = x >= 40 && x < 95 && y >= 27 && y < 33;
            outside[std::size_t(y) * w + x] = !(disc || bar);
        }
    std::vector<float> dist = squared_edt(outside, w, h);
    for (auto& d : dist) d = d > 0 ? std::sqrt(d) - 0.5f : 0.0f;
    const auto R = local_inscribed_radius(dist, w, h);
    EXPECT_NEAR(R[std::size_t(30) * w + 25], 19.5, 1.0);
    EXPECT_NEAR(R[std::size_t(30) * w + 12], 19.5, 1.5); // off centre, same disc
    EXPECT_NEAR(R[std::size_t(28) * w + 80], 3.0, 0.6);
    EXPECT_EQ(R[std::size_t(5) * w + 80], 0.0f);
}

// The hull of a sphere from three views is the intersection of three cylinders; the
// plausible volume's deviation from the sphere is at most a third of the hull's.
TEST(HullPlausible, SphereFromThreeViewsComesOutRound) {
    const double r = 1.0;
    auto views = sphere_views(r);
    auto hull = carve_and_refine(views, 128);
    auto [out, st] = make_plausible(*hull, nullptr, {});
    EXPECT_GT(st.removed, 0u);
    EXPECT_LT(occupied(*out), occupied(*hull));
    const Mesh mh = marching_cubes(*hull).value, mp = marching_cubes(*out).value;
    const double dh = sphere_deviation(mh, r), dp = sphere_deviation(mp, r);
    EXPECT_LT(dp, dh / 3.0) << "hull " << dh << ", plausible " << dp << " (signed " << sphere_deviation(mp, r, true)
                            << ")";
    EXPECT_TRUE(check_mesh(mp).closed_manifold());
    expect_columns_kept(*hull, *out);
    EXPECT_LT(uncovered_pct(mh, mp, *views), 0.5);
}

// The new surface is smooth: on the sphere, its normals follow the radial direction (the
// hull of three cylinders has creases where one cylinder takes over from another, and a
// voxel removal would leave steps), and the volume is one piece.
TEST(HullPlausible, TheNewSurfaceOfASphereIsSmooth) {
    const double r = 1.0;
    auto views = sphere_views(r);
    auto hull = carve_and_refine(views, 128);
    auto out = make_plausible(*hull, nullptr, {}).value;
    const Mesh mh = marching_cubes(*hull).value, mp = marching_cubes(*out).value;
    const auto dh = normal_deviation(mh), dp = normal_deviation(mp);
    auto at = [](const std::vector<double>& d, double q) { return d[std::size_t(q * double(d.size() - 1))]; };
    std::cout << "normal deviation, hull / plausible: median " << at(dh, 0.5) << " / " << at(dp, 0.5) << ", 95% "
              << at(dh, 0.95) << " / " << at(dp, 0.95) << ", 99% " << at(dh, 0.99) << " / " << at(dp, 0.99) << "\n";
    // Most of the surface is the new one, round (the hull: 12 degrees); what stays of the
    // hull's cylinders is the band about each silhouette's circle.
    EXPECT_LT(at(dp, 0.5), 0.3 * at(dh, 0.5));
    EXPECT_LT(at(dp, 0.95), 0.75 * at(dh, 0.95));
    EXPECT_EQ(pieces(mp), 1u);
}

// The sphere's three views and an oblique fourth (azimuth 45, elevation 30): a sphere looks
// the same from everywhere.
std::shared_ptr<Views> sphere_views_with_oblique(double r) {
    auto views = sphere_views(r);
    View oblique = views->views[0];
    oblique.name = "oblique";
    Camera c = Camera::from_azimuth_elevation(45, 30);
    c.scale = 150.0, c.cx = c.cy = 160.0;
    oblique.camera = c;
    auto all = std::make_shared<Views>(*views);
    all->views.push_back(oblique);
    return all;
}

// The removal leaves no plate one cell thin that it cut on both sides (Marching Cubes
// would give it two mirrored faces that smoothing draws onto one another).
TEST(HullPlausible, NoPlateOneCellThinWhereTheRemovalCut) {
    auto views = sphere_views(1.0);
    auto hull = carve_and_refine(views, 128);
    auto out = make_plausible(*hull, nullptr, {}).value;
    auto grid = out->occupancy->deepCopy();
    grid->tree().voxelizeActiveTiles();
    auto now = out->occupancy->getConstAccessor();
    auto was = hull->occupancy->getConstAccessor();
    std::size_t plates = 0;
    for (auto it = grid->cbeginValueOn(); it; ++it)
        for (int a = 0; a < 3; ++a) {
            openvdb::Coord lo = it.getCoord(), hi = it.getCoord();
            lo[a] -= 1;
            hi[a] += 1;
            if (!now.isValueOn(lo) && !now.isValueOn(hi) && (was.isValueOn(lo) || was.isValueOn(hi))) ++plates;
        }
    EXPECT_EQ(plates, 0u);
    EXPECT_TRUE(check_mesh(marching_cubes(*out).value).closed_manifold());
    expect_columns_kept(*hull, *out);
}

// With three views and with an oblique fourth (whose lines of sight cross the grid's), the
// mesh the pipeline makes of the volume (Marching Cubes, ten Laplacian steps with the
// guard, kept inside the hull) is clean: closed, 2-manifold, one piece, no face crossing
// another, no two vertices drawn onto one another.
TEST(HullPlausible, SmoothedMeshIsCleanWithThreeAndFourViews) {
    for (bool oblique : {false, true}) {
        auto views = oblique ? sphere_views_with_oblique(1.0) : sphere_views(1.0);
        auto hull = carve_and_refine(views, 128);
        auto out = make_plausible(*hull, nullptr, {}).value;
        Mesh m = marching_cubes(*out).value;
        const HullDistance hd(*views);
        SmoothOptions so;
        so.constrain = SmoothOptions::Constrain::Inside;
        so.tolerance_px = 0.5;
        smooth_mesh_in_place(m, so, &hd);
        const OutputCheck c = check_output(m);
        EXPECT_TRUE(c.clean()) << (oblique ? "four views: " : "three views: ") << ::testing::PrintToString(c.broken());
        EXPECT_EQ(pieces(m), 1u) << oblique;
    }
}

// On the bundled drawings of Spot the removal leaves pockets of the hull sealed inside the
// kept volume (between the legs and the body): they are put back, so Marching Cubes makes
// one surface, not the body and a closed shell for each pocket.
TEST(HullPlausible, NoCavitySealedInsideOnTheBundledCow) {
    auto views = std::make_shared<Views>(
        load_views(std::filesystem::path(CM_SOURCE_DIR) / "examples/spot/views.yaml", {}).value);
    auto hull = carve_and_refine(views, 256);
    auto [out, st] = make_plausible(*hull, nullptr, {});
    EXPECT_GT(st.cavities_filled, 0u); // the case is met
    EXPECT_EQ(pieces(marching_cubes(*out).value), 1u);
    expect_columns_kept(*hull, *out);
}

// Two blocks kept inside one hull, the volume between them removed, and a third block that
// is a piece of the hull of its own: the two are joined by the shortest path through the
// removed voxels (20 cells long), the third stays apart (no path within the hull).
TEST(HullPlausible, PiecesApartAreBridgedThroughTheRemovedVolume) {
    using plausible::LeafColumns;
    openvdb::BoolGrid hull(false), kept(false);
    auto fill = [](openvdb::BoolGrid& g, openvdb::Coord lo, openvdb::Coord hi) {
        g.tree().denseFill(openvdb::CoordBBox(lo, hi), true, true);
    };
    fill(hull, {0, 0, 0}, {39, 15, 15});
    fill(hull, {60, 0, 0}, {69, 7, 7});
    hull.tree().voxelizeActiveTiles();
    fill(kept, {0, 0, 0}, {9, 15, 15});
    fill(kept, {30, 0, 0}, {39, 15, 15});
    fill(kept, {60, 0, 0}, {69, 7, 7});
    kept.tree().voxelizeActiveTiles();
    openvdb::tree::LeafManager<openvdb::BoolTree> leaves(hull.tree());
    std::vector<LeafColumns::Mask> hm(leaves.leafCount()), km(leaves.leafCount());
    auto acc = kept.getConstAccessor();
    for (std::size_t l = 0; l < leaves.leafCount(); ++l)
        for (openvdb::Index off = 0; off < 512; ++off) {
            const auto c = leaves.leaf(l).offsetToGlobalCoord(off);
            if (leaves.leaf(l).isValueOn(off)) hm[l][off >> 6] |= std::uint64_t(1) << (off & 63);
            if (acc.isValueOn(c)) km[l][off >> 6] |= std::uint64_t(1) << (off & 63);
        }
    std::size_t joined = 0;
    const auto path = plausible::bridges(leaves, plausible::leaf_neighbours(leaves), hm, km, 64, &joined);
    EXPECT_EQ(joined, 1u);
    ASSERT_EQ(path.size(), 20u);
    for (const auto& c : path) {
        EXPECT_TRUE(hull.tree().isValueOn(c)) << c;
        EXPECT_FALSE(kept.tree().isValueOn(c)) << c;
        kept.tree().setValueOn(c, true);
    }
    // Now one piece holds both blocks: a flood from the first reaches the second.
    std::vector<LeafColumns::Mask> seed(leaves.leafCount()), km2(leaves.leafCount());
    auto acc2 = kept.getConstAccessor();
    for (std::size_t l = 0; l < leaves.leafCount(); ++l)
        for (openvdb::Index off = 0; off < 512; ++off) {
            const auto c = leaves.leaf(l).offsetToGlobalCoord(off);
            if (acc2.isValueOn(c)) km2[l][off >> 6] |= std::uint64_t(1) << (off & 63);
            if (c == openvdb::Coord(0, 0, 0)) seed[l][0] |= 1;
        }
    const auto reached = plausible::flood(leaves, seed, km2, false);
    auto reached_at = [&](openvdb::Coord c) {
        for (std::size_t l = 0; l < leaves.leafCount(); ++l)
            if (leaves.leaf(l).origin() == (c & ~7)) {
                const auto off = openvdb::BoolTree::LeafNodeType::coordToOffset(c);
                return (reached[l][off >> 6] >> (off & 63) & 1) != 0;
            }
        return false;
    };
    EXPECT_TRUE(reached_at({35, 8, 8}));
    EXPECT_FALSE(reached_at({65, 4, 4}));
}

// At roundness 0 the cube is the hull, voxel for voxel and crossing for crossing; at any
// roundness it keeps its three squares.
TEST(HullPlausible, CubeStaysACubeAtRoundnessZero) {
    auto views = std::make_shared<Views>(make_box_views(-1.0f, 1.0f, 200));
    auto hull = carve_and_refine(views, 48);
    PlausibleOptions opt;
    opt.roundness = 0;
    auto [out, st] = make_plausible(*hull, nullptr, opt);
    EXPECT_EQ(st.removed, 0u);
    EXPECT_EQ(occupied(*out), occupied(*hull));
    std::size_t same = 0, total = 0;
    auto acc = out->crossings->getConstAccessor();
    for (auto it = hull->crossings->cbeginValueOn(); it; ++it, ++total) same += acc.getValue(it.getCoord()) == *it;
    EXPECT_EQ(same, total);
    for (double roundness : {0.5, 1.0}) {
        opt.roundness = roundness;
        auto o = make_plausible(*hull, nullptr, opt).value;
        expect_columns_kept(*hull, *o);
        const Mesh m = marching_cubes(*o).value;
        EXPECT_TRUE(check_mesh(m).closed_manifold()) << roundness;
        EXPECT_LT(uncovered_pct(marching_cubes(*hull).value, m, *views), 0.5) << roundness;
    }
}

// A fin two cells thick on a ball: the fin has no volume to spare and stays whole.
TEST(HullPlausible, ThinFinSurvives) {
    const double r = 0.6;
    const Vec3d flo{-1.0, -0.1, -0.035}, fhi{1.0, 0.1, 0.035};
    auto views = views_of({"front", "right", "top"}, 320, 150.0,
                          [&](const Camera& c) { return union_outline(sphere_outline(r), box_outline(flo, fhi, c.d)); },
                          {-1.0, -r, -r}, {1.0, r, r});
    auto hull = carve_and_refine(views, 64);
    auto [out, st] = make_plausible(*hull, nullptr, {});
    EXPECT_GT(st.removed, 0u);
    // Grid points of the fin (outside the ball) in the hull, and how many stay.
    std::size_t fin = 0, kept = 0;
    auto grid = hull->occupancy->deepCopy();
    grid->tree().voxelizeActiveTiles();
    auto acc = out->occupancy->getConstAccessor();
    for (auto it = grid->cbeginValueOn(); it; ++it) {
        const auto w = hull->transform().indexToWorld(it.getCoord());
        if (std::abs(w.x()) < r + 0.1) continue;
        ++fin;
        kept += acc.isValueOn(it.getCoord());
    }
    ASSERT_GT(fin, 100u);
    EXPECT_EQ(kept, fin);
    expect_columns_kept(*hull, *out);
}

// An oblique fourth view (azimuth 45, elevation 30) and perspective cameras: every pixel
// the hull covers stays covered.
TEST(HullPlausible, ObliqueAndPerspectiveViewsKeepTheirSilhouettes) {
    const double r = 1.0;
    auto all = sphere_views_with_oblique(r);
    auto hull = carve_and_refine(all, 64);
    auto [out, st] = make_plausible(*hull, nullptr, {});
    EXPECT_GT(st.removed, 0u);
    const Mesh mh = marching_cubes(*hull).value, mp = marching_cubes(*out).value;
    EXPECT_LT(uncovered_pct(mh, mp, *all), 0.5);
    EXPECT_LT(sphere_deviation(mp, r), sphere_deviation(mh, r));

    auto persp = make_views(perspective_sphere_ring({0.1, 0.2, -0.1}, 1.0, 500.0), {-1.2, -1.0, -1.4}, {1.4, 1.4, 1.2});
    persp->calibrated = true;
    auto ph = carve_and_refine(persp, 48);
    const auto persp_plausible = make_plausible(*ph, nullptr, {});
    const auto& po = persp_plausible.value;
    st = persp_plausible.stats;
    EXPECT_GT(st.removed, 0u);
    const Mesh pmh = marching_cubes(*ph).value, pmp = marching_cubes(*po).value;
    EXPECT_TRUE(check_mesh(pmp).closed_manifold());
    EXPECT_LT(uncovered_pct(pmh, pmp, *persp), 0.5);
}

// The run report says where the stage's time went: every step's wall seconds, in order, as
// one JSON object.
TEST(HullPlausible, StepSecondsNameEveryStepInOrder) {
    auto views = sphere_views(1.0);
    auto hull = carve_and_refine(views, 48);
    PlausibleOptions opt;
    opt.handles = "cut";
    const PlausibleStats st = make_plausible(*hull, nullptr, opt).stats;
    const std::vector<std::string> steps = {"voxels", "views", "priors",  "smooth",   "cover",
                                            "volume", "genus", "handles", "crossings"};
    ASSERT_EQ(st.step_seconds.size(), steps.size());
    for (std::size_t i = 0; i < steps.size(); ++i) {
        EXPECT_EQ(st.step_seconds[i].first, steps[i]);
        EXPECT_GE(st.step_seconds[i].second, 0.0) << steps[i];
        EXPECT_LT(st.step_seconds[i].second, 60.0) << steps[i];
    }
    struct Capture : Metrics {
        std::string json;
        void metric(const std::string&, double) override {}
        void metric(const std::string&, const std::string&) override {}
        void metric_json(const std::string& key, const std::string& text) override {
            if (key == "step_seconds") json = text;
        }
        void warn(const std::string&) override {}
    } m;
    st.report(m);
    ASSERT_FALSE(m.json.empty());
    EXPECT_EQ(m.json.front(), '{');
    EXPECT_EQ(m.json.back(), '}');
    std::size_t at = 0;
    for (const std::string& step : steps) { // each named once, in order
        const std::size_t found = m.json.find("\"" + step + "\": ", at);
        ASSERT_NE(found, std::string::npos) << step << " in " << m.json;
        at = found + step.size();
    }
}

TEST(HullPlausible, StageRunsAndRefusesBadParameters) {
    auto views = sphere_views(1.0);
    auto hull = carve_and_refine(views, 32);
    StageHarness h("hull.plausible");
    h.params("{roundness: 0.8, ray_keep: 2}").input("volume", hull);
    auto out = h.run<Volume>();
    ASSERT_TRUE(out && out->occupancy);
    EXPECT_LT(occupied(*out), occupied(*hull));
    StageHarness bad("hull.plausible");
    bad.params("{roundness: 1.5}").input("volume", hull);
    EXPECT_NE(error_of([&] { bad.run<Volume>(); }).find("roundness"), std::string::npos);
    Volume empty;
    EXPECT_NE(error_of([&] { make_plausible(empty, views, {}); }).find("occupancy"), std::string::npos);
}
