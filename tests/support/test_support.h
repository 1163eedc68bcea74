// Helpers shared by the tests: temporary folders, running the command, files. Shapes
// built in code are in support/shapes.h.
#pragma once
#include <filesystem>
#include <string>


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

} // namespace cm::test
