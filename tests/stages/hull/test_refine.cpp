// hull.marching_intersections: crossings against the analytic hull.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "carve.h"
#include "core/error.h"
#include "geometry/silhouette_field.h"
#include "geometry/visual_hull.h"
#include "hull_steps.h"
#include "refine.h"
#include "support/shapes.h"

using namespace cm;
using namespace cm::test;

namespace {

std::shared_ptr<Views> sphere_views(double r, int size, double scale) {
    std::vector<View> vs;
    for (const char* n : {"front", "right", "top"}) vs.push_back(ortho_view(n, size, scale, sphere_outline(r)));
    return make_views(std::move(vs), {-r, -r, -r}, {r, r, r});
}

// Calls f(world point of the crossing, p inside?) for every crossing.
template <typename F>
void for_each_crossing(const Volume& v, F f) {
    auto acc = v.occupancy->getConstAccessor();
    for (auto it = v.crossings->cbeginValueOn(); it; ++it)
        for (int a = 0; a < 3; ++a) {
            const float t = (*it)[a];
            if (t < 0) continue;
            openvdb::Vec3d p = it.getCoord().asVec3d();
            p[a] += t;
            const auto w = v.transform().indexToWorld(p);
            openvdb::Coord q = it.getCoord();
            q[a] += 1;
            f(Vec3d{w.x(), w.y(), w.z()}, acc.isValueOn(it.getCoord()), acc.isValueOn(q));
        }
}

} // namespace

// Each crossing lies on the tricylinder: the largest distance of its projections from
// the disk outline is zero, to within 0.05 px.
TEST(HullRefine, SphereCrossingsAreSubPixelExact) {
    const double r = 1.0, scale = 150.0;
    auto views = sphere_views(r, 320, scale);
    CarveOptions opt;
    opt.resolution = 48;
    auto vol = carve(views, opt).value;
    const auto refined = refine(*vol, nullptr, {});
    const auto& ref = refined.value;
    const RefineStats& st = refined.stats;
    ASSERT_TRUE(ref->crossings);
    EXPECT_GT(st.crossings, 1000u);
    EXPECT_EQ(st.unresolved, 0u);
    std::size_t n = 0;
    double worst = 0;
    for_each_crossing(*ref, [&](const Vec3d& p, bool pin, bool qin) {
        ASSERT_NE(pin, qin); // only where occupancy differs
        const double d = std::max({std::hypot(p.y, p.z), std::hypot(p.x, p.z), std::hypot(p.x, p.y)});
        worst = std::max(worst, std::abs(d - r) * scale);
        ++n;
    });
    EXPECT_EQ(n, st.crossings);
    EXPECT_LT(worst, 0.05) << "px";
    // Along every x row of grid points the runs with their crossings have the exact
    // length of the row's chord through the tricylinder: 2 sqrt(r^2 - max(y^2, z^2)).
    const double h = vol->voxel_size();
    double rows_exact = 0;
    openvdb::CoordBBox box;
    vol->occupancy->tree().evalActiveVoxelBoundingBox(box);
    box.expand(2);
    for (int j = box.min().y(); j <= box.max().y(); ++j)
        for (int k = box.min().z(); k <= box.max().z(); ++k) {
            const auto w = vol->transform().indexToWorld(openvdb::Coord(0, j, k));
            const double m = std::max(w.y() * w.y(), w.z() * w.z());
            if (w.y() * w.y() + w.z() * w.z() <= r * r) rows_exact += 2 * std::sqrt(r * r - m);
        }
    rows_exact *= h * h;
    EXPECT_NEAR(crossing_volume(*ref), rows_exact, 1e-4 * rows_exact);
    // And both approach the tricylinder's volume.
    const double exact = 8.0 * (2.0 - std::sqrt(2.0));
    EXPECT_NEAR(rows_exact, exact, 0.02 * exact);
}

// Every edge with differing ends has a crossing, and no other edge.
TEST(HullRefine, CrossingsOnExactlyTheChangingEdges) {
    auto views = sphere_views(1.0, 200, 90.0);
    CarveOptions opt;
    opt.resolution = 24;
    auto vol = carve(views, opt).value;
    auto ref = refine(*vol, nullptr, {}).value;
    auto occ = vol->occupancy->getConstAccessor();
    auto cr = ref->crossings->getConstAccessor();
    openvdb::CoordBBox box;
    vol->occupancy->tree().evalActiveVoxelBoundingBox(box);
    box.expand(2);
    std::size_t changing = 0;
    for (auto ijk = box.begin(); ijk; ++ijk)
        for (int a = 0; a < 3; ++a) {
            openvdb::Coord q = *ijk;
            q[a] += 1;
            const bool differ = occ.isValueOn(*ijk) != occ.isValueOn(q);
            const float t = cr.getValue(*ijk)[a];
            changing += differ;
            if (differ) {
                EXPECT_GE(t, 0.f) << *ijk << " axis " << a;
                EXPECT_LE(t, 1.f);
            } else {
                EXPECT_EQ(t, -1.f) << *ijk << " axis " << a;
            }
        }
    EXPECT_GT(changing, 500u);
}

TEST(HullRefine, BoxCrossingsAndVolumeAreExact) {
    const Vec3d lo{-1.0, -0.55, -0.33}, hi{0.9, 0.77, 0.41};
    std::vector<View> vs;
    for (const char* n : {"front", "right", "top"})
        vs.push_back(ortho_view(n, 300, 120.0, box_outline(lo, hi, Camera::named(n)->d)));
    auto views = make_views(std::move(vs), lo, hi);
    CarveOptions opt;
    opt.resolution = 30;
    auto vol = carve(views, opt).value;
    auto ref = refine(*vol, nullptr, {}).value;
    double worst = 0;
    for_each_crossing(*ref, [&](const Vec3d& p, bool, bool) {
        // On a face: the smallest distance to one of the six planes.
        double d = 1e9;
        for (int k = 0; k < 3; ++k) d = std::min({d, std::abs(p[k] - lo[k]), std::abs(p[k] - hi[k])});
        worst = std::max(worst, d * 120.0);
    });
    EXPECT_LT(worst, 0.05) << "px";
    const double exact = (hi.x - lo.x) * (hi.y - lo.y) * (hi.z - lo.z);
    // Along x the crossings make the rows exact; y and z still count grid points.
    const double h = vol->voxel_size();
    EXPECT_NEAR(crossing_volume(*ref), exact,
                0.5 * h * 2 * ((hi.x - lo.x) * (hi.y - lo.y) + (hi.x - lo.x) * (hi.z - lo.z)));
}

TEST(HullRefine, PerspectiveCrossingsLieOnTheCones) {
    const Vec3d c{0.2, -0.1, 0.3};
    const double r = 1.0, f = 500;
    std::vector<View> vs = perspective_sphere_ring(c, r, f);
    auto views = make_views(std::move(vs), c - Vec3d{1.5, 1.5, 1.5}, c + Vec3d{1.5, 1.5, 1.5});
    views->calibrated = true;
    const auto ref = carve_and_refine(views, 48);
    double worst = 0;
    std::size_t n = 0;
    for_each_crossing(*ref, [&](const Vec3d& p, bool, bool) {
        // Largest angular excess over the cones, in pixels (f px per radian at the centre).
        double excess = -1e9;
        for (const auto& v : views->views) {
            const Vec3d e = v.camera.center();
            const double ang = std::acos(std::clamp(dot(normalize(p - e), normalize(c - e)), -1.0, 1.0));
            excess = std::max(excess, (ang - std::asin(r / length(c - e))) * f);
        }
        worst = std::max(worst, std::abs(excess));
        ++n;
    });
    EXPECT_GT(n, 1000u);
    EXPECT_LT(worst, 0.05) << "px";
}

// A fin thinner than a cell, between two planes of grid points: no grid point is inside
// it, but the edges through it keep where they enter and leave.
TEST(HullRefine, ThinPartsBetweenGridPointsAreKept) {
    const double scale = 200.0;
    const Vec3d body0{-1, -1, -1}, body1{1, 0, 1}, fin0{-1, 0, 0.02}, fin1{1, 0.8, 0.05};
    std::vector<View> vs;
    vs.push_back(ortho_view("front", 480, scale, box_outline({-1, -1, -1}, {1, 0.8, 1}, {0, 0, -1})));
    vs.push_back(ortho_view("right", 480, scale,
                            union_outline(box_outline(body0, body1, {-1, 0, 0}), box_outline(fin0, fin1, {-1, 0, 0}))));
    vs.push_back(ortho_view("top", 480, scale, box_outline(body0, body1, {0, -1, 0})));
    auto views = make_views(std::move(vs), {-1, -1, -1}, {1, 0.8, 1});
    CarveOptions opt;
    opt.resolution = 20; // h = 0.1 = 20 px; the fin is 0.03 = 6 px thick
    auto vol = carve(views, opt).value;
    const auto refined = refine(*vol, nullptr, {});
    const auto& ref = refined.value;
    const RefineStats& st = refined.stats;
    auto enter = ref->find_extra("thin_enter");
    auto leave = ref->find_extra("thin_leave");
    ASSERT_TRUE(enter && leave);
    auto ge = openvdb::gridPtrCast<openvdb::Vec3fGrid>(enter);
    auto gl = openvdb::gridPtrCast<openvdb::Vec3fGrid>(leave);
    ASSERT_TRUE(ge && gl);
    EXPECT_EQ(ge->activeVoxelCount(), gl->activeVoxelCount());
    // z edges from z = 0 to z = 0.1 at y = 0.1 .. 0.7 (y = 0.8 is on the fin's edge) and 21 x values.
    std::size_t n = 0;
    auto la = gl->getConstAccessor();
    for (auto it = ge->cbeginValueOn(); it; ++it) {
        const auto v = *it;
        EXPECT_EQ(v[0], -1.f);
        EXPECT_EQ(v[1], -1.f);
        ASSERT_GE(v[2], 0.f);
        const auto w = ge->transform().indexToWorld(it.getCoord());
        EXPECT_NEAR(w.z(), 0.0, 1e-9);
        ++n;
        if (std::abs(w.y() - 0.8) < 1e-6) continue; // on the fin's edge: how much of it is inside is moot
        EXPECT_NEAR(v[2], 0.2, 0.05 / 20) << w;     // within 0.05 px (a cell is 20 px)
        EXPECT_NEAR(la.getValue(it.getCoord())[2], 0.5, 0.05 / 20) << w;
    }
    EXPECT_GE(n, 21u * 7u);
    EXPECT_LE(n, 21u * 8u);
    EXPECT_EQ(st.thin_crossings, n);
    EXPECT_TRUE(st.thin_searched);
    EXPECT_NEAR(st.cell_px, 20.0, 1e-9);
    // And without the search, none.
    RefineOptions off;
    off.thin = RefineOptions::Thin::Off;
    auto plain = refine(*vol, nullptr, off).value;
    EXPECT_FALSE(plain->find_extra("thin_enter"));
}

// The sub-pixel model itself: transitions agree with point tests along a segment.
TEST(SilhouetteField, TransitionsAgreeWithPointTests) {
    View v = ortho_view("front", 64, 20.0, sphere_outline(1.0));
    SilhouetteField f(v);
    for (int s = 0; s < 200; ++s) {
        const Vec3d a{-1.4 + 0.013 * s, -1.3 + 0.011 * s, 0}, b{1.3 - 0.007 * s, 0.9 - 0.01 * s, 0.5};
        bool start;
        double flips[64];
        const int n = f.transitions(a, b, start, flips, 64);
        EXPECT_EQ(start, f.inside(a));
        // Sample between flips: the state must match.
        bool cur = start;
        double prev = 0;
        for (int k = 0; k <= n; ++k) {
            const double next = k < n ? flips[k] : 1.0;
            if (next - prev > 1e-6) {
                const double mid = 0.5 * (prev + next);
                EXPECT_EQ(f.inside(a + (b - a) * mid), cur) << s << " at " << mid;
            }
            cur = !cur;
            prev = next;
        }
    }
}

// The summed-area table (built in row and column strips side by side, over the box of the
// inside pixels) counts the inside pixels of every box: checked corner by corner, and beyond
// the image, against a count row after row, on an image wider than several strips and taller
// than several row blocks, with a ragged outline; once with stray inside pixels all over the
// image (the box is the image) and once with the disc alone (the box is the disc's).
TEST(SilhouetteField, SummedAreaCountsEveryBox) {
    for (const bool strays : {true, false}) {
        View v;
        v.name = "front";
        v.width = 2600;
        v.height = 301;
        std::vector<float> cov(std::size_t(v.width) * std::size_t(v.height));
        std::uint32_t state = 12345;
        for (int y = 0; y < v.height; ++y)
            for (int x = 0; x < v.width; ++x) {
                state = state * 1664525u + 1013904223u;
                const bool disc = (x - 1300) * (x - 1300) / 16 + (y - 150) * (y - 150) < 140 * 140;
                const float stray = strays && (state >> 24) < 8 ? 0.5f : 0.0f;
                cov[std::size_t(y) * std::size_t(v.width) + std::size_t(x)] =
                    disc ? ((state >> 24) < 200 ? 1.0f : 0.49f) : stray;
            }
        v.coverage = Coverage(cov, v.width, v.height);
        const SilhouetteField::Table sat = SilhouetteField::summed_area(v);
        ASSERT_TRUE(sat.of(v.width, v.height));
        const std::size_t stride = std::size_t(v.width) + 1;
        if (strays) {
            EXPECT_EQ(sat.box_w * sat.box_h, v.width * v.height);
        } else {
            EXPECT_LE(sat.box_w, 1119); // the disc's box: 2 * 4 * 140 px wide, 2 * 140 px tall
            EXPECT_LE(sat.box_h, 279);
            EXPECT_LT(2 * sat.bytes(), 4 * stride * std::size_t(v.height + 1)); // under half the image's table
        }
        std::vector<std::uint32_t> above(stride, 0), here(stride, 0);
        std::size_t wrong = 0;
        for (int x = -3; x <= v.width + 3; ++x) wrong += sat.at(x, 0) != 0 || sat.at(x, -5) != 0;
        for (int y = 0; y < v.height; ++y) {
            std::uint32_t row = 0;
            here[0] = 0;
            for (int x = 0; x < v.width; ++x) {
                row += v.coverage[std::size_t(y) * std::size_t(v.width) + std::size_t(x)] >= 0.5f ? 1u : 0u;
                here[std::size_t(x) + 1] = above[std::size_t(x) + 1] + row;
            }
            for (int x = 0; x <= v.width; ++x) wrong += sat.at(x, y + 1) != here[std::size_t(x)];
            wrong += sat.at(-1, y + 1) != 0 || sat.at(v.width + 7, y + 1) != here[stride - 1];
            std::swap(above, here);
        }
        EXPECT_EQ(wrong, 0u) << (strays ? "with strays" : "the disc alone");
        EXPECT_EQ(sat.at(v.width + 1, v.height + 9), above[stride - 1]);
        EXPECT_GT(sat.at(v.width, v.height), 100000u); // the disc is there: the test counts something
    }
    View empty;
    empty.width = 40;
    empty.height = 30;
    empty.coverage = Coverage(std::vector<float>(1200, 0.2f), 40, 30);
    const SilhouetteField::Table none = SilhouetteField::summed_area(empty);
    ASSERT_TRUE(none.of(40, 30));
    EXPECT_EQ(none.at(40, 30), 0u);
    EXPECT_EQ(none.bytes(), sizeof(std::uint32_t));
}

// The views' summed-area tables are made once for every hull of a run, and freed when the
// last volume or hull that reads them goes (they are a run's largest view data after the
// hull stages: 4 bytes per drawing pixel).
TEST(SilhouetteField, SummedAreaTablesLiveAsLongAsAVolumeOrAHullHoldsThem) {
    auto views = sphere_views(1.0, 320, 150.0);
    CarveOptions opt;
    opt.resolution = 32;
    auto vol = carve(views, opt).value;
    ASSERT_TRUE(vol->silhouette_tables);
    const std::weak_ptr<const SilhouetteTables> tables = vol->silhouette_tables;
    auto ref = refine(*vol, nullptr, {}).value;
    EXPECT_EQ(ref->silhouette_tables, vol->silhouette_tables); // the crossings read the carving's tables
    vol.reset();
    EXPECT_FALSE(tables.expired()); // the refined volume still holds them
    {
        const VisualHull hull(*views, {-2, -2, -2}, {2, 2, 2}, ref->silhouette_tables);
        EXPECT_EQ(hull.tables(), tables.lock());
    }
    ref.reset();
    EXPECT_TRUE(tables.expired()); // nothing reads them any more: freed, though the views live on
    // Made again for the next hull, and shared by the hulls alive together.
    std::weak_ptr<const SilhouetteTables> again;
    {
        const VisualHull a(*views, {-2, -2, -2}, {2, 2, 2});
        ASSERT_TRUE(a.tables());
        const VisualHull b(*views, {-1, -1, -1}, {1, 1, 1}, a.tables());
        EXPECT_EQ(a.tables(), b.tables());
        EXPECT_TRUE(a.inside({0, 0, 0}));
        EXPECT_FALSE(a.inside({0.9, 0.9, 0.9}));
        again = a.tables();
    }
    EXPECT_TRUE(again.expired());
    // Tables are data of one set of views: a copy of the views gets its own, and a hull refuses
    // the tables of other views.
    const Views copy = *views;
    const auto held = silhouette_tables(*views);
    EXPECT_NE(silhouette_tables(copy), held);
    EXPECT_TRUE(held->fit(copy));
    Views fewer = copy;
    fewer.views.pop_back();
    EXPECT_FALSE(held->fit(fewer));
    EXPECT_THROW(VisualHull(fewer, {-2, -2, -2}, {2, 2, 2}, held), Error);
    // A volume made elsewhere, without tables, gets them where they are needed, and hands them on.
    auto bare = std::make_shared<Volume>(*carve(views, opt).value);
    bare->silhouette_tables = nullptr;
    const auto made = refine(*bare, nullptr, {}).value;
    ASSERT_TRUE(made->silhouette_tables);
    EXPECT_TRUE(made->silhouette_tables->fit(*views));
}
