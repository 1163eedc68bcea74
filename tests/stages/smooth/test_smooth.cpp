#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <set>
#include <vector>

#include <tbb/parallel_for.h>

#include "core/error.h"
#include "geometry/distance_transform.h"
#include "geometry/hull_distance.h"
#include "geometry/mesh_adjacency.h"
#include "geometry/mesh_check.h"
#include "mesh_smooth.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;

namespace {

double rms_radius_error(const Mesh& m, float r) {
    double s = 0;
    for (const auto& p : m.positions) {
        const double e = length(Vec3d(p)) - r;
        s += e * e;
    }
    return std::sqrt(s / double(m.positions.size()));
}

double max_abs_hull(const Mesh& m, const HullDistance& h) {
    double worst = 0;
    for (const auto& p : m.positions) worst = std::max(worst, std::fabs(h(Vec3d(p))));
    return worst;
}

} // namespace

TEST(VertexAdjacency, IcosahedronHasFiveNeighboursEach) {
    const Mesh m = test::make_sphere({0, 0, 0}, 1.0f, 0);
    const VertexAdjacency adj = build_vertex_adjacency(m);
    ASSERT_EQ(adj.vertex_count(), 12u);
    for (std::uint32_t v = 0; v < 12; ++v) {
        EXPECT_EQ(adj.degree(v), 5u);
        for (auto it = adj.begin(v); it != adj.end(v); ++it) EXPECT_NE(*it, v);
    }
}

// The one-rings as sets, the slow way, for any triangle soup.
std::vector<std::vector<std::uint32_t>> rings_by_sets(const Mesh& m) {
    std::vector<std::set<std::uint32_t>> s(m.positions.size());
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k)
            for (int j = 1; j < 3; ++j)
                if (t[(k + j) % 3] != t[k]) s[t[k]].insert(t[(k + j) % 3]);
    std::vector<std::vector<std::uint32_t>> out;
    for (const auto& x : s) out.emplace_back(x.begin(), x.end());
    return out;
}

// Closed oriented meshes take the short way (each neighbour once as the corner after v);
// open, non-manifold and degenerate ones the general one: both give the sorted rings.
TEST(VertexAdjacency, SortedRingsOfClosedOpenNonManifoldAndDegenerateMeshes) {
    std::vector<Mesh> meshes;
    meshes.push_back(test::make_sphere({0, 0, 0}, 1.0f, 3)); // closed
    meshes.push_back(test::make_grid_box(-1.0f, 1.0f, 5));   // closed, valence 4 to 6
    Mesh open = meshes[0];
    open.triangles.resize(open.triangles.size() / 2); // a boundary: corners before v not after it
    meshes.push_back(open);
    Mesh fins; // three triangles on one edge (0, 1)
    fins.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, -1, 0}, {5, 5, 5}};
    fins.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
    meshes.push_back(fins);
    Mesh degenerate = meshes[0];
    degenerate.triangles.push_back({0, 0, 1}); // names 0 as its own neighbour
    meshes.push_back(degenerate);
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        const VertexAdjacency adj = build_vertex_adjacency(meshes[i]);
        const auto want = rings_by_sets(meshes[i]);
        ASSERT_EQ(adj.vertex_count(), want.size()) << "mesh " << i;
        for (std::uint32_t v = 0; v < want.size(); ++v)
            ASSERT_EQ(std::vector<std::uint32_t>(adj.begin(v), adj.end(v)), want[v]) << "mesh " << i << " vertex " << v;
    }
}

// Large meshes are counted in chunks of faces side by side (one per thread): the rings are
// the same, closed or open, whatever chunk a vertex's faces fall in.
TEST(VertexAdjacency, LargeMeshesCountedInChunksGiveTheSameRings) {
    Mesh closed = test::make_sphere({0, 0, 0}, 1.0f, 6);
    ASSERT_GT(closed.face_count(), 65536u);
    std::mt19937 rng(7); // faces out of order: a vertex's corners in every chunk
    std::shuffle(closed.triangles.begin(), closed.triangles.end(), rng);
    Mesh open = closed;
    open.triangles.resize(open.triangles.size() - 1000);
    for (const Mesh* m : {&closed, &open}) {
        const VertexAdjacency adj = build_vertex_adjacency(*m);
        const auto want = rings_by_sets(*m);
        ASSERT_EQ(adj.vertex_count(), want.size());
        for (std::uint32_t v = 0; v < want.size(); ++v)
            ASSERT_EQ(std::vector<std::uint32_t>(adj.begin(v), adj.end(v)), want[v]) << "vertex " << v;
    }
}

TEST(Smooth, LaplacianReducesNoiseOfASphere) {
    Mesh m = test::make_sphere({0, 0, 0}, 1.0f, 4);
    test::add_radial_noise(m, {0, 0, 0}, 0.03f);
    const double before = rms_radius_error(m, 1.0f);
    SmoothOptions opt;
    opt.iterations = 3;
    smooth_mesh_in_place(m, opt);
    // Laplacian smoothing shrinks, so compare with the best-fitting radius too.
    const double after = rms_radius_error(m, 1.0f);
    EXPECT_LT(after, 0.6 * before) << "before " << before << " after " << after;
    EXPECT_TRUE(check_mesh(m).closed_manifold());
}

TEST(Smooth, IntoAnotherMeshGivesWhatSmoothingInPlaceGives) {
    Mesh in = test::make_sphere({0, 0, 0}, 1.0f, 4);
    test::add_radial_noise(in, {0, 0, 0}, 0.03f);
    in.compute_normals();
    in.colors.assign(in.positions.size(), {0.1f, 0.2f, 0.3f, 1.0f});
    for (int iterations : {0, 4}) {
        SmoothOptions opt;
        opt.iterations = iterations;
        Mesh in_place = in, out;
        const SmoothStats a = smooth_mesh_in_place(in_place, opt);
        auto [smoothed, b] = smooth_mesh(in, opt);
        out = std::move(smoothed);
        EXPECT_EQ(out.positions, in_place.positions);
        EXPECT_EQ(out.normals, in_place.normals);
        EXPECT_EQ(out.triangles, in_place.triangles);
        EXPECT_EQ(out.colors, in_place.colors);
        EXPECT_EQ(a.pulled_back, b.pulled_back);
        EXPECT_EQ(iterations == 0, out.positions == in.positions);
    }
}

TEST(Smooth, TaubinReducesNoiseAndKeepsVolumeWhereLaplacianShrinks) {
    Mesh noisy = test::make_sphere({0, 0, 0}, 1.0f, 4);
    test::add_radial_noise(noisy, {0, 0, 0}, 0.03f);
    const double v0 = check_mesh(noisy).signed_volume;
    Mesh lap = noisy, tau = noisy;
    SmoothOptions lo;
    lo.iterations = 10;
    smooth_mesh_in_place(lap, lo);
    SmoothOptions to;
    to.method = SmoothOptions::Method::Taubin;
    to.iterations = 10;
    smooth_mesh_in_place(tau, to);
    const double lap_change = (check_mesh(lap).signed_volume - v0) / v0;
    const double tau_change = (check_mesh(tau).signed_volume - v0) / v0;
    EXPECT_LT(lap_change, -0.02) << "Laplacian should shrink the sphere";
    EXPECT_LT(std::fabs(tau_change), 0.01) << "Taubin volume change " << tau_change;
    EXPECT_LT(rms_radius_error(tau, 1.0f), 0.5 * rms_radius_error(noisy, 1.0f));
}

TEST(Smooth, FactorScalesTheStep) {
    const Mesh m0 = test::make_sphere({0, 0, 0}, 1.0f, 3);
    Mesh full = m0, half = m0;
    SmoothOptions o;
    o.iterations = 1;
    smooth_mesh_in_place(full, o);
    o.factor = 0.5;
    smooth_mesh_in_place(half, o);
    for (std::size_t v = 0; v < m0.positions.size(); ++v) {
        const Vec3f expect = m0.positions[v] + (full.positions[v] - m0.positions[v]) * 0.5f;
        EXPECT_NEAR(length(half.positions[v] - expect), 0.0f, 1e-6f);
    }
}

// The distance transform against brute force, on a mask with the lines it skips (columns and
// rows all seed or without a seed) beside lines that need the full pass.
TEST(DistanceTransform, MatchesBruteForceWithBlankAndFullLines) {
    const int w = 37, h = 23;
    std::vector<char> seed(std::size_t(w) * h, 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool full_column = x == 30 || x == 31, full_row = y == 20;
            const bool blob = (x - 12) * (x - 12) + (y - 9) * (y - 9) < 30 || (x * 7 + y * 3) % 23 == 0;
            seed[std::size_t(y) * w + x] = (x < 26 && blob) || full_column || full_row;
        }
    for (int y = 0; y < h; ++y) seed[std::size_t(y) * w + 35] = 0; // a column without a seed but the full row's
    const std::vector<float> d = squared_edt(seed, w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float best = kEdtFar;
            for (int j = 0; j < h; ++j)
                for (int i = 0; i < w; ++i)
                    if (seed[std::size_t(j) * w + i])
                        best = std::min(best, float((i - x) * (i - x) + (j - y) * (j - y)));
            ASSERT_EQ(d[std::size_t(y) * w + x], best) << x << "," << y;
        }
    // All seed: zeros; no seed: kEdtFar everywhere.
    for (float v : squared_edt(std::vector<char>(std::size_t(w) * h, 1), w, h)) ASSERT_EQ(v, 0.0f);
    for (float v : squared_edt(std::vector<char>(std::size_t(w) * h, 0), w, h)) ASSERT_EQ(v, kEdtFar);
}

// The field is stored for the box of the silhouette grown by a margin and built beyond it on
// first use: every pixel's value, and samples inside the window, across its border, beyond it
// and beyond the image, are those of the whole image's field (brute force here), to the bit.
// The part beyond the window is asked for from many threads at once.
TEST(HullDistance, TheWindowedFieldIsTheWholeImagesField) {
    const int w = 190, h = 150;
    std::vector<float> coverage(std::size_t(w) * h, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double r = std::hypot(x - 60.3, (y - 55.7) * 1.4);
            float c = float(std::clamp(17.0 - r, 0.0, 1.0));      // a disc with a soft rim
            if (x >= 70 && x < 84 && y >= 50 && y < 54) c = 1.0f; // an arm
            if ((x * 5 + y * 3) % 31 == 0 && r < 14) c = 0.0f;    // pinholes
            coverage[std::size_t(y) * w + x] = c;
        }
    coverage[std::size_t(90) * w + 52] = 0.3f; // a faint pixel apart from the disc
    const SilhouetteSdf f = silhouette_sdf(coverage, w, h, "v");
    ASSERT_LT(std::size_t(f.stride) * f.rows, std::size_t(w) * h / 2) << "the window is a part of the image";
    ASSERT_TRUE(f.beyond);
    auto inside = [&](int x, int y) { return coverage[std::size_t(y) * w + x] >= 0.5f; };
    std::vector<float> want(coverage.size());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float best = kEdtFar;
            for (int j = 0; j < h; ++j)
                for (int i = 0; i < w; ++i)
                    if (inside(i, j) != inside(x, y))
                        best = std::min(best, float((i - x) * (i - x) + (j - y) * (j - y)));
            float d = inside(x, y) ? -(std::sqrt(best) - 0.5f) : std::sqrt(best) - 0.5f;
            const float c = coverage[std::size_t(y) * w + x];
            if (c > 0.0f && c < 1.0f && std::fabs(d) <= 0.5f) d = 0.5f - c;
            want[std::size_t(y) * w + x] = d;
        }
    // Samples first, from many threads: the field beyond the window is built by one of them.
    std::vector<std::array<double, 2>> points;
    for (int k = 0; k < 4000; ++k)
        points.push_back({-20.0 + std::fmod(k * 37.31, w + 40.0), -20.0 + std::fmod(k * 17.97, h + 40.0)});
    for (double x : {0.5, 0.7, double(f.ox) + 0.5, double(f.ox) + 0.2, double(f.ox + f.stride) - 0.5,
                     double(f.ox + f.stride) - 0.1, double(w) - 0.5, double(w) + 3.0})
        for (double y : {0.5, double(f.oy) + 0.5, double(f.oy + f.rows) - 0.5, double(f.oy + f.rows) + 0.4, 57.25})
            points.push_back({x, y});
    std::vector<double> got(points.size());
    tbb::parallel_for(std::size_t(0), points.size(),
                      [&](std::size_t k) { got[k] = f.sample(points[k][0], points[k][1]); });
    int beyond = 0;
    for (std::size_t k = 0; k < points.size(); ++k) {
        const double x = points[k][0], y = points[k][1];
        const double fx = x - 0.5, fy = y - 0.5;
        const double cx = std::clamp(fx, 0.0, double(w - 1)), cy = std::clamp(fy, 0.0, double(h - 1));
        const int x0 = std::min(int(cx), w - 1), y0 = std::min(int(cy), h - 1);
        const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
        const double tx = cx - x0, ty = cy - y0;
        auto at = [&](int i, int j) { return double(want[std::size_t(j) * w + i]); };
        double v =
            (1 - ty) * ((1 - tx) * at(x0, y0) + tx * at(x1, y0)) + ty * ((1 - tx) * at(x0, y1) + tx * at(x1, y1));
        if (fx != cx || fy != cy) v = std::max(v, 0.0) + std::hypot(fx - cx, fy - cy);
        ASSERT_EQ(got[k], v) << x << "," << y;
        beyond += x < f.ox || y < f.oy || x > f.ox + f.stride || y > f.oy + f.rows;
    }
    EXPECT_GT(beyond, 1000);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) ASSERT_EQ(f.at(x, y), want[std::size_t(y) * w + x]) << x << "," << y;
    // A silhouette whose window is the whole image keeps nothing beyond it.
    EXPECT_FALSE(silhouette_sdf(std::vector<float>(std::size_t(w) * h, 1.0f), w, h, "v").beyond);
}

TEST(HullDistance, SignedDistanceOfABoxFromItsViews) {
    const Views views = test::make_box_views(-1.0f, 1.0f, 200);
    const HullDistance h(views);
    const double px = h.finest_pixel();
    EXPECT_NEAR(px, 2.0 / 160.0, 1e-12);
    EXPECT_NEAR(h({1.0, 0.3, -0.2}), 0.0, 0.1 * px);               // on a face
    EXPECT_NEAR(h({1.0 + 10 * px, 0.0, 0.0}), 10 * px, 0.1 * px);  // outside, along x
    EXPECT_NEAR(h({1.0 - 10 * px, 0.0, 0.0}), -10 * px, 0.1 * px); // inside, nearest face x
    EXPECT_NEAR(h({0.0, 0.0, 0.0}), -1.0, 2 * px);                 // centre
    EXPECT_GT(h({5.0, 0.0, 0.0}), 3.0);                            // far outside the images
}

// within() gives the answer of |h(p)| <= bound whichever view it asks first.
TEST(HullDistance, WithinAgreesWithTheDistance) {
    const Views views = test::make_box_views(-1.0f, 1.0f, 200);
    const HullDistance h(views);
    const double px = h.finest_pixel();
    int inside = 0, outside = 0;
    for (int i = 0; i < 2000; ++i) {
        const Vec3d p{std::sin(i * 1.7) * 1.3, std::cos(i * 0.9) * 1.2, std::sin(i * 2.3 + 1) * 1.25};
        for (double bound : {0.5 * px, 5 * px, 0.3}) {
            const bool want = std::fabs(h(p)) <= bound;
            for (std::size_t first : {std::size_t(0), std::size_t(1), std::size_t(2), std::size_t(7)}) {
                std::size_t f = first;
                ASSERT_EQ(h.within(p, bound, f), want) << i << " " << bound << " " << first;
                ASSERT_LT(f, views.views.size());
            }
            (want ? inside : outside)++;
        }
    }
    EXPECT_GT(inside, 100);
    EXPECT_GT(outside, 100);
}

TEST(HullDistance, EmptySilhouetteIsAnErrorNamingTheView) {
    Views views = test::make_box_views(-1.0f, 1.0f, 32);
    views.views[1].coverage =
        Coverage(std::vector<float>(views.views[1].coverage.size(), 0.0f), views.views[1].width, views.views[1].height);
    try {
        HullDistance h(views);
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("\"right\""), std::string::npos) << e.what();
    }
}

TEST(Smooth, HullConstraintKeepsVerticesOnTheOutline) {
    // A finely gridded cube is its own visual hull; Laplacian smoothing rounds its
    // corners and edges away unless the hull constraint holds them.
    const Views views = test::make_box_views(-1.0f, 1.0f, 256);
    const HullDistance hull(views);
    const double tol = 0.5 * hull.finest_pixel();
    const Mesh box = test::make_grid_box(-1.0f, 1.0f, 16);
    ASSERT_LT(max_abs_hull(box, hull), tol);

    Mesh free = box;
    SmoothOptions o;
    o.iterations = 10;
    smooth_mesh_in_place(free, o);
    EXPECT_GT(max_abs_hull(free, hull), 10 * tol);

    Mesh held = box;
    o.constrain = SmoothOptions::Constrain::Hull;
    o.tolerance_px = tol / hull.finest_pixel();
    const SmoothStats st = smooth_mesh_in_place(held, o, &hull);
    EXPECT_GT(st.clamped_steps, 0u);
    EXPECT_LE(st.max_hull_distance, tol * (1 + 1e-6));
    EXPECT_LE(max_abs_hull(held, hull), tol * (1 + 1e-6));
    EXPECT_TRUE(check_mesh(held).closed_manifold());
    EXPECT_GT(check_mesh(held).signed_volume, 0.97 * 8.0);
}

// Views that see a vertex far inside are not asked while it stays near: the positions are the
// same as when every view is asked at every step (bit for bit), and most steps skip a view.
TEST(Smooth, SkippingViewsFarInsideGivesTheSamePositions) {
    const Views views = test::make_box_views(-1.0f, 1.0f, 256);
    const HullDistance hull(views);
    const double tol = 0.5 * hull.finest_pixel();
    Mesh box = test::make_grid_box(-1.0f, 1.0f, 24);
    test::add_radial_noise(box, {0, 0, 0}, 0.004f); // steps of several pixels, some clamped
    Mesh sphere = test::make_sphere({0, 0, 0}, 0.7f, 4);
    test::add_radial_noise(sphere, {0, 0, 0}, 0.03f);
    for (const bool inside : {false, true})
        for (const Mesh* in : {&box, &sphere}) {
            SmoothOptions o;
            o.iterations = 10;
            o.constrain = inside ? SmoothOptions::Constrain::Inside : SmoothOptions::Constrain::Hull;
            o.tolerance_px = tol / hull.finest_pixel();
            Mesh skipped = *in, asked = *in;
            const SmoothStats a = smooth_mesh_in_place(skipped, o, &hull);
            o.skip_far_views = false;
            const SmoothStats b = smooth_mesh_in_place(asked, o, &hull);
            const char* what = in == &box ? "box" : "sphere";
            EXPECT_EQ(b.skipping_steps, 0u);
            EXPECT_GT(a.skipping_steps, in->positions.size() * o.iterations / 2) << what << " inside " << inside;
            EXPECT_EQ(a.clamped_steps, b.clamped_steps) << what << " inside " << inside;
            if (in == &box) {
                EXPECT_GT(a.clamped_steps, 100u);
            }
            for (std::size_t v = 0; v < in->positions.size(); ++v)
                ASSERT_EQ(skipped.positions[v], asked.positions[v]) << what << " inside " << inside << " vertex " << v;
        }
}

// constrain: inside (a surface carved inside the hull, hull.plausible): vertices on the hull
// stay on it as with the hull constraint; the others smooth as if free, where the hull
// constraint would only let them move towards the hull.
TEST(Smooth, InsideConstraintFreesTheVerticesInsideAndHoldsThoseOnTheHull) {
    const Views views = test::make_box_views(-1.0f, 1.0f, 256);
    const HullDistance hull(views);
    const double tol = 0.5 * hull.finest_pixel();
    SmoothOptions o;
    o.iterations = 3;
    o.constrain = SmoothOptions::Constrain::Hull;
    o.tolerance_px = tol / hull.finest_pixel();

    Mesh noisy = test::make_sphere({0, 0, 0}, 0.6f, 4);
    test::add_radial_noise(noisy, {0, 0, 0}, 0.03f);
    Mesh free = noisy, held = noisy, inside = noisy;
    SmoothOptions none = o;
    none.constrain = SmoothOptions::Constrain::None;
    smooth_mesh_in_place(free, none);
    smooth_mesh_in_place(held, o, &hull);
    o.constrain = SmoothOptions::Constrain::Inside;
    smooth_mesh_in_place(inside, o, &hull);
    const double e_free = rms_radius_error(free, 0.6f), e_held = rms_radius_error(held, 0.6f),
                 e_inside = rms_radius_error(inside, 0.6f);
    EXPECT_NEAR(e_inside, e_free, 1e-9);
    EXPECT_GT(e_held, 1.5 * e_inside) << "held " << e_held << ", inside " << e_inside;

    Mesh box = test::make_grid_box(-1.0f, 1.0f, 16);
    o.iterations = 10;
    const SmoothStats st = smooth_mesh_in_place(box, o, &hull);
    EXPECT_GT(st.clamped_steps, 0u);
    EXPECT_LE(max_abs_hull(box, hull), tol * (1 + 1e-6));
}
