// Helpers shared by the tests: temporary folders, running the command, shapes.
#pragma once
#include <filesystem>
#include <string>

#include "core/mesh.h"
#include "core/views.h"

namespace cm::test {

/// A fresh empty folder under the build tree, removed when the object dies.
class TempDir {
public:
    explicit TempDir(const std::string& name);
    ~TempDir();
    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path operator/(const std::string& f) const { return path_ / f; }

private:
    std::filesystem::path path_;
};

struct CommandResult {
    int exit_code = 0;
    std::string out, err;
};
/// Runs the built conceptmesh command with `args` (shell-quoted by the caller) in `cwd`.
CommandResult run_cli(const std::string& args, const std::filesystem::path& cwd = std::filesystem::current_path());

void write_text(const std::filesystem::path& file, const std::string& text);
std::string read_text(const std::filesystem::path& file);

std::filesystem::path shared_dir();     ///< ../shared beside the checkout
std::filesystem::path source_dir();

/// Closed, outward triangle meshes built in code.
Mesh make_box(Vec3f lo, Vec3f hi);
Mesh make_sphere(Vec3f centre, float radius, int subdivisions = 4);   ///< icosphere
/// Appends `part`'s vertices and triangles to `into` (turned inside out when `flip`).
void append_mesh(Mesh& into, const Mesh& part, bool flip = false);
/// Two boxes that overlap: closed and 2-manifold, but their faces cross.
Mesh make_crossing_boxes();
/// A sphere with a box on its shoulder: lopsided, so a wrong axis or a mirror shows.
Mesh make_lopsided();

} // namespace cm::test
