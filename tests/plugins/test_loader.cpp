// The plugin loader against deliberately broken plugins: each is refused with
// its own clear message and the host keeps working.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/error.h"
#include "plugins/registry.h"

using namespace cm;
namespace fs = std::filesystem;

namespace {
const fs::path kRoot = CM_FIXTURE_ROOT;

std::string only_diagnostic(const Registry& r) {
    EXPECT_EQ(r.diagnostics().size(), 1u);
    return r.diagnostics().empty() ? "" : r.diagnostics()[0];
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }
} // namespace

TEST(Loader, LoadsAGoodPlugin) {
    Registry r;
    r.load_directories({kRoot / "good"});
    EXPECT_TRUE(r.diagnostics().empty());
    ASSERT_NE(r.find("test.box"), nullptr);
    EXPECT_EQ(r.find("test.box")->plugin, "testkit");
    EXPECT_EQ(r.create("test.box")->info().name, "test.box");
}

TEST(Loader, NoEntrySymbol) {
    Registry r;
    EXPECT_FALSE(r.load_library(kRoot / "no_entry/libcm_no_entry.so"));
    const std::string d = only_diagnostic(r);
    EXPECT_TRUE(contains(d, "libcm_no_entry.so")) << d;
    EXPECT_TRUE(contains(d, "no conceptmesh_plugin_entry symbol")) << d;
}

TEST(Loader, WrongPluginAbi) {
    Registry r;
    EXPECT_FALSE(r.load_library(kRoot / "wrong_abi/libcm_wrong_abi.so"));
    const std::string d = only_diagnostic(r);
    EXPECT_TRUE(contains(d, "libcm_wrong_abi.so")) << d;
    EXPECT_TRUE(contains(d, "plugin ABI 101")) << d;
    EXPECT_TRUE(contains(d, "rebuild the plugin")) << d;
    EXPECT_EQ(r.find("test.wrong_abi"), nullptr);
}

TEST(Loader, WrongOpenVdbAbi) {
    Registry r;
    EXPECT_FALSE(r.load_library(kRoot / "wrong_vdb/libcm_wrong_vdb.so"));
    const std::string d = only_diagnostic(r);
    EXPECT_TRUE(contains(d, "OpenVDB ABI 11")) << d;
    EXPECT_TRUE(contains(d, "OpenVDB ABI 10")) << d;
}

TEST(Loader, LibraryThatFailsToLoad) {
    Registry r;
    EXPECT_FALSE(r.load_library(kRoot / "unresolved/libcm_unresolved.so"));
    std::string d = only_diagnostic(r);
    EXPECT_TRUE(contains(d, "could not be loaded")) << d;
    EXPECT_TRUE(contains(d, "conceptmesh_symbol_that_does_not_exist")) << d;

    Registry g;
    EXPECT_FALSE(g.load_library(kRoot / "garbage/libcm_garbage.so"));
    d = only_diagnostic(g);
    EXPECT_TRUE(contains(d, "libcm_garbage.so")) << d;
    EXPECT_TRUE(contains(d, "could not be loaded")) << d;
}

TEST(Loader, DuplicateStageKeepsTheFirstAndNamesBothFiles) {
    Registry r;
    r.load_directories({kRoot / "duplicate"});
    const std::string d = only_diagnostic(r);
    EXPECT_TRUE(contains(d, "\"test.box\"")) << d;
    EXPECT_TRUE(contains(d, "libcm_a_testkit.so")) << d;
    EXPECT_TRUE(contains(d, "libcm_b_duplicate.so")) << d;
    EXPECT_TRUE(contains(d, "using the first")) << d;
    ASSERT_NE(r.find("test.box"), nullptr);
    EXPECT_EQ(r.find("test.box")->library.filename(), "libcm_a_testkit.so");
    // The first one is really the one used: test.box makes a box (the duplicate's would fail).
    EXPECT_EQ(r.create("test.box")->info().summary, "A closed box mesh of the given size");
}

TEST(Loader, FactoryThatThrows) {
    Registry r;
    EXPECT_TRUE(r.load_library(kRoot / "throwing/libcm_throwing.so"));
    try {
        r.create("test.throwing_factory");
        FAIL() << "expected an error";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_TRUE(contains(m, "test.throwing_factory")) << m;
        EXPECT_TRUE(contains(m, "libcm_throwing.so")) << m;
        EXPECT_TRUE(contains(m, "factory exploded")) << m;
    }
}

TEST(Loader, EntryPointThatThrows) {
    Registry r;
    EXPECT_FALSE(r.load_library(kRoot / "throwing_entry/libcm_throwing_entry.so"));
    const std::string d = only_diagnostic(r);
    EXPECT_TRUE(contains(d, "entry exploded")) << d;
}

TEST(Loader, HostKeepsWorkingAfterEveryFailure) {
    Registry r;
    r.load_directories({kRoot / "no_entry", kRoot / "wrong_abi", kRoot / "wrong_vdb", kRoot / "unresolved",
                        kRoot / "garbage", kRoot / "throwing_entry", kRoot / "good"});
    EXPECT_EQ(r.diagnostics().size(), 6u);
    ASSERT_NE(r.find("test.box"), nullptr);
    EXPECT_NO_THROW(r.create("test.box"));
    EXPECT_THROW(r.create("no.such.stage"), Error);
}

TEST(Loader, DefaultSearchPathFindsTheBuiltPluginsAndHonoursTheEnvironment) {
    ::setenv("CONCEPTMESH_PLUGIN_PATH", (kRoot / "good").c_str(), 1);
    const auto dirs = Registry::default_dirs();
    ::unsetenv("CONCEPTMESH_PLUGIN_PATH");
    ASSERT_EQ(dirs.size(), 2u);
    EXPECT_TRUE(fs::exists(dirs[0] / "libcm_write.so")) << dirs[0];
    EXPECT_EQ(dirs[1], kRoot / "good");
    Registry r;
    r.load_directories(dirs);
    EXPECT_NE(r.find("mesh.write"), nullptr);
    EXPECT_NE(r.find("views.load"), nullptr);
    EXPECT_NE(r.find("test.box"), nullptr);
}
