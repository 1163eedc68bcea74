// The self-intersection index (against brute force) and the smoothing guard, on the
// surfaces where smoothing goes wrong: Marching Cubes of random voxels, full of one-voxel
// slots and plates whose sheets cross when the staircase is relaxed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "core/error.h"
#include "core/mesh.h"
#include "core/volume.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_intersect.h"
#include "marching_cubes.h"
#include "mesh_smooth.h"
#include "support/shapes.h"

using namespace cm;
using openvdb::Coord;

namespace {

// Binary Marching Cubes (edge midpoints) of random voxels in an n^3 box.
Mesh random_voxel_surface(std::uint32_t seed, int n, double density) {
    Volume v;
    v.occupancy = openvdb::BoolGrid::create(false);
    auto acc = v.occupancy->getAccessor();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    for (int x = 0; x < n; ++x)
        for (int y = 0; y < n; ++y)
            for (int z = 0; z < n; ++z)
                if (u(rng) < density) acc.setValueOn(Coord(x, y, z), true);
    MarchingCubesOptions o;
    o.use_crossings = false;
    return marching_cubes(v, o).value;
}

std::vector<FacePair> brute_force(const Mesh& m) {
    std::vector<FacePair> out;
    for (std::uint32_t a = 0; a < m.face_count(); ++a)
        for (std::uint32_t b = a + 1; b < m.face_count(); ++b)
            if (triangles_cross(m.positions, m.triangles[a], m.triangles[b])) out.push_back({a, b});
    return out;
}

Mesh smoothed(const Mesh& m, bool guard, SmoothStats* st = nullptr) {
    Mesh s = m;
    SmoothOptions o;
    o.iterations = 10;
    o.guard = guard;
    const SmoothStats r = smooth_mesh_in_place(s, o);
    if (st) *st = r;
    return s;
}

std::size_t turned_or_collapsed(const Mesh& before, const Mesh& after) {
    std::size_t n = 0;
    for (const auto& t : before.triangles) {
        const Vec3d a0(before.positions[t[0]]), b0(before.positions[t[1]]), c0(before.positions[t[2]]);
        const Vec3d a(after.positions[t[0]]), b(after.positions[t[1]]), c(after.positions[t[2]]);
        const Vec3d n0 = cross(b0 - a0, c0 - a0), n1 = cross(b - a, c - a);
        n += dot(n0, n1) <= 0 || length(n1) == 0;
    }
    return n;
}

} // namespace

TEST(SelfIntersections, GridIndexFindsExactlyTheBruteForcePairs) {
    std::size_t found = 0;
    for (std::uint32_t seed : {1u, 2u, 3u, 4u}) {
        const Mesh m = smoothed(random_voxel_surface(seed, 9, 0.45), false);
        const std::vector<FacePair> grid = find_self_intersections(m);
        EXPECT_EQ(grid, brute_force(m)) << "seed " << seed;
        found += grid.size();
    }
    EXPECT_GT(found, 0u) << "these surfaces should have crossings to find";
}

TEST(SelfIntersections, EmbeddedFansLeaveThePairsAsTheyAre) {
    // Surfaces with crossings: the pairs all() leaves out for the fans it is given are pairs
    // that do not cross, and the vertices where two faces sharing only it cross are not vouched for.
    std::size_t found = 0, vouched = 0, vertices = 0;
    for (std::uint32_t seed : {1u, 2u, 3u, 4u, 5u, 6u}) {
        const Mesh m = smoothed(random_voxel_surface(seed, 9, 0.45), false);
        const std::vector<char> fans = embedded_fans(m.triangles, m.positions);
        ASSERT_EQ(fans.size(), m.positions.size());
        const std::vector<FacePair> expected = brute_force(m);
        EXPECT_EQ(SelfIntersectionIndex(m.triangles, m.positions).all(m.positions, {}, &fans), expected)
            << "seed " << seed;
        for (const auto& pr : expected) {
            const auto &a = m.triangles[pr[0]], &b = m.triangles[pr[1]];
            for (auto u : a) {
                if (std::count(b.begin(), b.end(), u)) {
                    EXPECT_FALSE(fans[u]) << "seed " << seed << " vertex " << u;
                }
            }
        }
        found += expected.size();
        vouched += std::size_t(std::count(fans.begin(), fans.end(), char(1)));
        vertices += fans.size();
    }
    EXPECT_GT(found, 0u) << "these surfaces should have crossings to find";
    EXPECT_GT(vouched, vertices / 2) << "most fans of a smoothed surface lie over a plane";
    EXPECT_LT(vouched, vertices) << "the folded ones do not";
}

TEST(SelfIntersections, EmbeddedFanIsOneClosedFanWindingOnce) {
    // Vertex 0 at the origin and a ring around it; `turns` times round the z axis in n steps.
    auto fan = [](int n, double turns, double lift) {
        Mesh m;
        m.positions.push_back({0, 0, 0});
        for (int i = 0; i < n; ++i) {
            const double a = 2 * 3.14159265358979 * turns * i / n;
            m.positions.push_back({float(std::cos(a)), float(std::sin(a)), float(lift * (i % 2))});
        }
        for (int i = 0; i < n; ++i) m.triangles.push_back({0u, std::uint32_t(1 + i), std::uint32_t(1 + (i + 1) % n)});
        return m;
    };
    EXPECT_TRUE(embedded_fans(fan(6, 1, 0.0).triangles, fan(6, 1, 0.0).positions)[0]) << "a flat hexagon";
    EXPECT_TRUE(embedded_fans(fan(7, 1, 0.4).triangles, fan(7, 1, 0.4).positions)[0]) << "a crinkled one";
    const Mesh twice = fan(10, 2, 0.3);
    EXPECT_FALSE(embedded_fans(twice.triangles, twice.positions)[0]) << "a ring round twice";
    // An open fan (a boundary vertex), and a fan with a face turned over.
    Mesh open = fan(6, 1, 0.0);
    open.triangles.pop_back();
    EXPECT_FALSE(embedded_fans(open.triangles, open.positions)[0]);
    EXPECT_FALSE(embedded_fans(open.triangles, open.positions)[1]) << "ring vertices have open fans";
    Mesh folded = fan(6, 1, 0.0);
    folded.positions[3] = {0.3f, -0.2f, 0.0f}; // across its neighbours' sector
    EXPECT_FALSE(embedded_fans(folded.triangles, folded.positions)[0]);
    // Two closed fans through one vertex (a pinch): each winds once, together twice.
    Mesh pinch = fan(6, 1, 0.0);
    const Mesh other = fan(5, 1, 0.0);
    for (std::size_t i = 1; i < other.positions.size(); ++i)
        pinch.positions.push_back(other.positions[i] + Vec3f(0, 0, 0.5f));
    for (auto t : other.triangles) pinch.triangles.push_back({0u, t[1] + 6, t[2] + 6});
    EXPECT_FALSE(embedded_fans(pinch.triangles, pinch.positions)[0]);
    // A face naming a vertex that does not exist: no fan is vouched for.
    Mesh broken = fan(6, 1, 0.0);
    broken.triangles.push_back({0u, 1u, 99u});
    const std::vector<char> none = embedded_fans(broken.triangles, broken.positions);
    EXPECT_EQ(std::count(none.begin(), none.end(), char(1)), 0);
}

TEST(SelfIntersections, TwoPoseIndexAnswersForBlendsAndSubsets) {
    const Mesh a = random_voxel_surface(4, 9, 0.45);
    const Mesh b = smoothed(a, false);
    const SelfIntersectionIndex index(a.triangles, a.positions, &b.positions);
    for (float w : {0.0f, 0.5f, 1.0f}) {
        Mesh blend = a;
        for (std::size_t v = 0; v < blend.positions.size(); ++v)
            blend.positions[v] = a.positions[v] + (b.positions[v] - a.positions[v]) * w;
        const std::vector<FacePair> expected = find_self_intersections(blend);
        EXPECT_EQ(index.all(blend.positions), expected) << "blend " << w;
        // involving(): the pairs with a face among every third face.
        std::vector<std::uint32_t> some;
        for (std::uint32_t f = 0; f < blend.face_count(); f += 3) some.push_back(f);
        std::vector<FacePair> want;
        for (const auto& p : expected)
            if (p[0] % 3 == 0 || p[1] % 3 == 0) want.push_back(p);
        EXPECT_EQ(index.involving(some, blend.positions), want) << "blend " << w;
    }
    EXPECT_TRUE(find_self_intersections(a).empty()) << "Marching Cubes itself gives an embedded surface";
    // faces_near(): every face around a vertex, from the vertex's position in either pose.
    std::vector<std::vector<std::uint32_t>> around(a.positions.size());
    for (std::uint32_t f = 0; f < a.face_count(); ++f)
        for (auto v : a.triangles[f]) around[v].push_back(f);
    std::vector<std::uint32_t> near;
    for (std::uint32_t v = 0; v < a.positions.size(); ++v)
        for (const auto* pose : {&a.positions, &b.positions}) {
            index.faces_near((*pose)[v], near);
            for (auto f : around[v])
                ASSERT_NE(std::find(near.begin(), near.end(), f), near.end()) << "vertex " << v << " face " << f;
        }
}

TEST(Coincidence, IndexFollowsMovedVerticesAsBruteForceDoes) {
    // Points on a coarse lattice (many within the tolerance of a cell side), some moved onto
    // others, onto fresh places and back again; the index must answer as brute force does.
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> cellpick(0, 9);
    const double tol = 0.01;
    std::vector<Vec3f> p;
    for (int i = 0; i < 600; ++i)
        p.push_back(Vec3f{float(cellpick(rng)), float(cellpick(rng)), float(cellpick(rng))} * 0.05f +
                    Vec3f{float(i % 7) * 0.3f, 0, 0});
    auto brute = [&] {
        std::vector<std::uint32_t> out;
        for (std::size_t i = 0; i < p.size(); ++i)
            for (std::size_t k = 0; k < p.size(); ++k) {
                const Vec3f d = p[i] - p[k];
                if (i != k && double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z <= tol * tol) {
                    out.push_back(std::uint32_t(i));
                    break;
                }
            }
        return out;
    };
    CoincidenceIndex index(p, tol);
    ASSERT_EQ(index.all(), brute());
    std::uniform_int_distribution<std::uint32_t> pick(0, std::uint32_t(p.size() - 1));
    std::uniform_real_distribution<float> jitter(-0.008f, 0.008f);
    for (int round = 0; round < 30; ++round) {
        for (int k = 0; k < 20; ++k) {
            const std::uint32_t v = pick(rng);
            p[v] = k % 2 ? p[pick(rng)] + Vec3f{jitter(rng), jitter(rng), 0} // onto another
                         : Vec3f{jitter(rng), jitter(rng), jitter(rng)} * 100.0f;
            index.moved(v);
        }
        const auto want = brute();
        ASSERT_EQ(index.all(), want) << "round " << round;
        std::vector<std::uint32_t> asked;
        for (std::uint32_t v = 0; v < p.size(); ++v)
            if (index.has_near(v)) asked.push_back(v);
        ASSERT_EQ(asked, want) << "round " << round;
        for (std::uint32_t v = 0; v < p.size(); v += 37) {
            std::vector<std::uint32_t> near;
            index.near(v, [&](std::uint32_t w) { near.push_back(w); });
            std::sort(near.begin(), near.end());
            std::vector<std::uint32_t> expect;
            for (std::uint32_t w = 0; w < p.size(); ++w) {
                const Vec3f d = p[v] - p[w];
                if (w != v && double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z <= tol * tol)
                    expect.push_back(w);
            }
            ASSERT_EQ(near, expect) << "vertex " << v << " round " << round;
        }
    }
    // Arbitrary points (on the vertices and beside them, and far away) against a fresh index.
    const CoincidenceIndex fresh(p, tol);
    for (std::uint32_t v = 0; v < p.size(); v += 7) {
        const Vec3f q = v % 2 ? p[v] : p[v] + Vec3f{jitter(rng), jitter(rng), jitter(rng)};
        std::vector<std::uint32_t> near, expect;
        fresh.near_point(q, [&](std::uint32_t w) { near.push_back(w); });
        std::sort(near.begin(), near.end());
        for (std::uint32_t w = 0; w < p.size(); ++w) {
            const Vec3f d = q - p[w];
            if (double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z <= tol * tol) expect.push_back(w);
        }
        ASSERT_EQ(near, expect) << "point near vertex " << v;
    }
    std::size_t far = 0;
    fresh.near_point({1e30f, 0, 0}, [&](std::uint32_t) { ++far; });
    EXPECT_EQ(far, 0u);
}

TEST(SmoothGuard, LeavesNoCrossingTurnedOrCollapsedFace) {
    std::size_t unguarded_total = 0;
    for (std::uint32_t seed : {11u, 12u, 13u, 14u}) {
        const Mesh input = random_voxel_surface(seed, 14, 0.5);
        ASSERT_EQ(count_self_intersections(input), 0u);
        const Mesh plain = smoothed(input, false);
        unguarded_total += count_self_intersections(plain) + turned_or_collapsed(input, plain);
        SmoothStats st;
        const Mesh guarded = smoothed(input, true, &st);
        EXPECT_EQ(count_self_intersections(guarded), 0u) << "seed " << seed;
        EXPECT_EQ(turned_or_collapsed(input, guarded), 0u) << "seed " << seed;
        const MeshCheck c = check_mesh(guarded);
        EXPECT_TRUE(c.closed_manifold());
        EXPECT_EQ(c.degenerate_faces, 0u);
        EXPECT_EQ(st.unresolved, 0u);
        EXPECT_GT(st.guard_rounds, 0u);
        // The guard is local: only the vertices around bad faces differ from plain smoothing.
        std::size_t differ = 0;
        for (std::size_t v = 0; v < input.positions.size(); ++v) differ += guarded.positions[v] != plain.positions[v];
        EXPECT_LE(differ, st.pulled_back);
        EXPECT_LT(double(differ), 0.25 * double(input.positions.size())) << "seed " << seed;
    }
    EXPECT_GT(unguarded_total, 0u) << "plain smoothing of these surfaces should go wrong somewhere";
}

// The umbrella operator (factor 1) draws two vertices with the same ring of neighbours onto
// the ring's centroid: the two tips of a part one cell across. Faces neither cross nor turn
// there, but an importer that merges by distance welds the two and pinches the surface.
TEST(SmoothGuard, DrawsNoTwoVerticesOntoOneAnother) {
    std::size_t unguarded_total = 0;
    for (std::uint32_t seed : {11u, 12u, 13u, 14u, 21u, 22u}) {
        const Mesh input = random_voxel_surface(seed, 14, seed > 20 ? 0.2 : 0.5);
        Vec3f lo, hi;
        input.bounds(lo, hi);
        const double tol = kCoincidentTolerance * length(Vec3d(hi) - Vec3d(lo));
        ASSERT_EQ(count_coincident_vertices(input, tol), 0u);
        unguarded_total += count_coincident_vertices(smoothed(input, false), tol);
        SmoothStats st;
        const Mesh guarded = smoothed(input, true, &st);
        EXPECT_EQ(count_coincident_vertices(guarded, tol), 0u) << "seed " << seed;
        EXPECT_EQ(count_self_intersections(guarded), 0u) << "seed " << seed;
        EXPECT_EQ(turned_or_collapsed(input, guarded), 0u) << "seed " << seed;
    }
    EXPECT_GT(unguarded_total, 0u) << "plain smoothing of these surfaces should draw vertices together";
}

TEST(SmoothGuard, ChangesNothingWhereSmoothingIsHarmless) {
    const Mesh box = test::make_grid_box(-1.0f, 1.0f, 12);
    SmoothStats st;
    const Mesh guarded = smoothed(box, true, &st);
    const Mesh plain = smoothed(box, false);
    EXPECT_EQ(st.bad_faces, 0u);
    EXPECT_EQ(st.pulled_back, 0u);
    EXPECT_EQ(guarded.positions, plain.positions);
}

TEST(SelfIntersections, NonFiniteCoordinatesAreAClearError) {
    Mesh m = test::make_grid_box(-1.0f, 1.0f, 4);
    m.positions[3].y = std::numeric_limits<float>::quiet_NaN();
    try {
        find_self_intersections(m);
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("NaN"), std::string::npos) << e.what();
    }
}

// The answers kept by content: a mesh asked again (or a copy of it) gets the same pairs, and
// any change of a position or a triangle is asked afresh, so no answer goes stale.
TEST(SelfIntersections, KeptAnswersFollowTheMeshContent) {
    std::uint32_t seed = 1;
    Mesh m;
    std::vector<FacePair> first;
    for (; seed <= 8 && first.empty(); ++seed) {
        m = smoothed(random_voxel_surface(seed, 9, 0.45), false);
        first = find_self_intersections(m);
    }
    ASSERT_FALSE(first.empty()) << "one of these surfaces should have crossings to find";
    --seed;
    EXPECT_EQ(find_self_intersections(m), first);
    const Mesh copy = m;
    EXPECT_EQ(find_self_intersections(copy), first);
    // Each crossing taken away by moving the vertices back where Marching Cubes put them,
    // one face at a time: each state's answer is the brute force's.
    const Mesh clean = random_voxel_surface(seed, 9, 0.45);
    ASSERT_EQ(clean.positions.size(), m.positions.size());
    for (std::size_t k = 0; k < 3 && k < first.size(); ++k) {
        for (auto v : m.triangles[first[k][0]]) m.positions[v] = clean.positions[v];
        EXPECT_EQ(find_self_intersections(m), brute_force(m)) << "after putting back face " << first[k][0];
    }
    m.positions = clean.positions;
    EXPECT_TRUE(find_self_intersections(m).empty());
    // A change of the triangles alone (one face turned over) is a new question too.
    Mesh turned = copy;
    std::swap(turned.triangles[first[0][1]][1], turned.triangles[first[0][1]][2]);
    EXPECT_EQ(find_self_intersections(turned), brute_force(turned));
    EXPECT_EQ(find_self_intersections(copy), first);
}
