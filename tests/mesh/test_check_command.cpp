// conceptmesh check: the table, the JSON, and the exit code a script gates on.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "io/mesh_io.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;

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
