// conceptmesh check: the table, the JSON, and the exit code a script gates on.
#include <gtest/gtest.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "geometry/mesh_intersect.h"
#include "io/mesh_io.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;

namespace {

// The vertices with another within `tol`, by comparing every pair.
std::size_t coincident_by_brute_force(const Mesh& m, double tol) {
    std::size_t brute = 0;
    for (std::size_t i = 0; i < m.positions.size(); ++i)
        for (std::size_t k = 0; k < m.positions.size(); ++k) {
            const Vec3f d = m.positions[i] - m.positions[k];
            if (i != k && double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z <= tol * tol) {
                ++brute;
                break;
            }
        }
    return brute;
}

} // namespace

TEST(CheckCommand, CleanBoxPassesAndOverlappingBoxesFail) {
    test::TempDir dir("check_command");
    write_mesh(test::make_box({0, 0, 0}, {1, 1, 1}), dir / "box.obj");
    auto r = test::run_cli("check \"" + (dir / "box.obj").string() + "\"");
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("closed, 2-manifold, outward, clean"), std::string::npos) << r.out;

    const Mesh two = test::make_crossing_boxes();
    write_mesh(two, dir / "two.ply");
    r = test::run_cli("check --json \"" + (dir / "two.ply").string() + "\"");
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_FALSE(j["ok"].get<bool>());
    EXPECT_GT(j["self_intersections"].get<int>(), 0);
    EXPECT_EQ(j["boundary_edges"].get<int>(), 0);
    EXPECT_EQ(j["components"].get<int>(), 2);
    EXPECT_FALSE(j.contains("crossing_pairs"));

    // --list says where: face ids and centres of the first pairs.
    r = test::run_cli("check --json --list 2 \"" + (dir / "two.ply").string() + "\"");
    const auto listed = nlohmann::json::parse(r.out);
    ASSERT_EQ(listed["crossing_pairs"].size(), 2u);
    const auto& first = listed["crossing_pairs"][0];
    EXPECT_LT(first["faces"][0].get<int>(), first["faces"][1].get<int>());
    EXPECT_EQ(first["centres"][0].size(), 3u);
    r = test::run_cli("check --list 1 \"" + (dir / "two.ply").string() + "\"");
    EXPECT_NE(r.out.find("crossing: faces"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("more pairs"), std::string::npos) << r.out;

    // An open mesh: one face removed.
    Mesh open = test::make_box({0, 0, 0}, {1, 1, 1});
    open.triangles.pop_back();
    write_mesh(open, dir / "open.obj");
    r = test::run_cli("check \"" + (dir / "open.obj").string() + "\"");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.out.find("boundary edges"), std::string::npos);
    EXPECT_NE(r.out.find("FAIL"), std::string::npos);
}

TEST(CheckCommand, MissingFileIsOneLineError) {
    const auto r = test::run_cli("check /nonexistent/mesh.obj");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("/nonexistent/mesh.obj"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(CheckCommand, CoincidentVerticesAreReportedAsAnImporterWouldWeldThem) {
    // Two boxes touching at one corner through two distinct vertices at one position: each
    // closed and manifold, but merged by distance (as Blender and most engines import) the
    // corner becomes a non-manifold vertex.
    test::TempDir dir("check_coincident");
    Mesh two = test::make_box({0, 0, 0}, {1, 1, 1});
    const Mesh b = test::make_box({1, 1, 1}, {2, 2, 2});
    const auto base = std::uint32_t(two.positions.size());
    two.positions.insert(two.positions.end(), b.positions.begin(), b.positions.end());
    for (auto t : b.triangles) two.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    write_mesh(two, dir / "touching.obj");
    auto r = test::run_cli("check --json \"" + (dir / "touching.obj").string() + "\"");
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["coincident_vertices"].get<int>(), 2);
    EXPECT_EQ(j["boundary_edges"].get<int>(), 0);
    r = test::run_cli("check \"" + (dir / "touching.obj").string() + "\"");
    EXPECT_NE(r.out.find("coincident vertices"), std::string::npos) << r.out;

    // Apart by more than the tolerance (a millionth of the diagonal), they are two vertices.
    for (std::size_t i = base; i < two.positions.size(); ++i) two.positions[i].x += 1e-4f;
    write_mesh(two, dir / "apart.obj");
    r = test::run_cli("check --json \"" + (dir / "apart.obj").string() + "\"");
    EXPECT_EQ(nlohmann::json::parse(r.out)["coincident_vertices"].get<int>(), 0) << r.out;
}

TEST(CheckCommand, CoincidentVerticesAgreeWithTheBruteForceCount) {
    Mesh m;
    std::uint32_t seed = 7;
    auto next = [&] { return float((seed = seed * 1664525u + 1013904223u) >> 8) / float(1u << 24); };
    for (int i = 0; i < 3000; ++i) m.positions.push_back({next(), next(), next()});
    for (int i = 0; i < 200; ++i) { // near copies, some within the tolerance and some not
        const Vec3f p = m.positions[std::size_t(i) * 7];
        const float off = i % 2 ? 4e-4f : 2e-3f;
        m.positions.push_back({p.x + off * next(), p.y, p.z});
    }
    const double tol = 1e-3;
    const std::size_t brute = coincident_by_brute_force(m, tol);
    EXPECT_GT(brute, 100u);
    EXPECT_EQ(count_coincident_vertices(m, tol), brute);
}

TEST(CheckCommand, CoincidentVerticesAcrossCellSidesAreFound) {
    // Chains of vertices in every direction, spaced just under and just over the tolerance:
    // the search's cells are far larger than the tolerance, so most close pairs of a chain
    // that crosses a cell's side or corner lie in different cells.
    Mesh m;
    const double tol = 1e-3;
    const Vec3f dirs[] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 1, -1}, {1, -1, 1}, {-1, 1, 1}};
    for (int d = 0; d < 7; ++d)
        for (int chain = 0; chain < 2; ++chain) {
            const Vec3f dir = dirs[d] * float(1.0 / std::sqrt(double(dot(dirs[d], dirs[d]))));
            const float step = float(tol * (chain ? 1.02 : 0.98));
            const Vec3f start{0.5f * float(d), 0.5f * float(chain), 0.05f};
            for (int i = 0; i < 300; ++i) m.positions.push_back(start + dir * (step * float(i)));
        }
    const std::size_t brute = coincident_by_brute_force(m, tol);
    EXPECT_EQ(brute, 7u * 300u); // the close chains, every vertex of them
    EXPECT_EQ(count_coincident_vertices(m, tol), brute);
}

TEST(CheckCommand, FacesTheReaderCannotTakeAreAnErrorNotDroppedInSilence) {
    test::TempDir dir("check_dropped");
    const std::string tetra = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    test::write_text(dir / "range.obj", tetra + "f 1 2 9\n");
    auto r = test::run_cli("check \"" + (dir / "range.obj").string() + "\"");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find("range.obj\": line 9: face index 9 is out of range (the file has 4 vertices)"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    // An edge of three faces (a fin on the tetrahedron): the reader keeps the fin on copies
    // of its vertices, and the check says the mesh is not clean.
    test::write_text(dir / "fin.obj", tetra + "v 1 1 1\nf 1 2 5\n");
    r = test::run_cli("check \"" + (dir / "fin.obj").string() + "\"");
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    EXPECT_NE(r.out.find("FAIL"), std::string::npos) << r.out;
    test::write_text(dir / "whole.obj", tetra);
    EXPECT_EQ(test::run_cli("check \"" + (dir / "whole.obj").string() + "\"").exit_code, 0);
}
