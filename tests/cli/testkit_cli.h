// What the command's tests that load the fixture plugins share (their targets define
// CM_FIXTURE_ROOT: conceptmesh_uses_fixtures in tests/CMakeLists.txt).
#pragma once
#include <cstdlib>
#include <filesystem>
#include <string>

#include "support/test_support.h"

namespace cm::test {

/// The folder of the fixture plugins, one subfolder per case (tests/plugins/CMakeLists.txt).
inline const std::filesystem::path kFixtures = CM_FIXTURE_ROOT;

/// Runs the command with the test-kit plugin (the `good` fixture) on the plugin path.
inline CommandResult cli_with_testkit(const std::string& args, const std::filesystem::path& cwd) {
    ::setenv("CONCEPTMESH_PLUGIN_PATH", (kFixtures / "good").c_str(), 1);
    auto r = run_cli(args, cwd);
    ::unsetenv("CONCEPTMESH_PLUGIN_PATH");
    return r;
}

} // namespace cm::test
