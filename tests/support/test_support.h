// Helpers shared by the tests: temporary folders, running the command, files. Shapes
// built in code are in support/shapes.h.
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

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

/// What cm::Error `f` throws, or "(no error)".
std::string error_of(const std::function<void()>& f);

void write_text(const std::filesystem::path& file, const std::string& text);
/// Writes an SVG drawing: the <svg> element's `attributes` (its size, its viewBox) around
/// `shapes`.
void write_svg(const std::filesystem::path& file, const std::string& attributes, const std::string& shapes);
std::string read_text(const std::filesystem::path& file);

/// Every file and folder below `dir`, as paths relative to it, sorted.
std::vector<std::string> listing(const std::filesystem::path& dir);

/// Expects `part` within `text` (a message, an output), and shows `text` when it is not.
#define EXPECT_HAS(text, part) EXPECT_NE(std::string(text).find(part), std::string::npos) << (text)

std::filesystem::path shared_dir(); ///< ../shared beside the checkout, or $CONCEPTMESH_SHARED_DIR

/// Skips the calling test with a message naming what is missing when `needed` (under
/// ../shared) does not exist: a clone without ../shared beside it passes its own tests.
#define CM_SKIP_WITHOUT(needed)                                        \
    if (!std::filesystem::exists(needed))                              \
    GTEST_SKIP() << "needs " << std::filesystem::path(needed).string() \
                 << " (the shared data beside the checkout), which is missing"
std::filesystem::path source_dir();

} // namespace cm::test
