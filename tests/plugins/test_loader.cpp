// The plugin loader against deliberately broken plugins: each is refused with
// its own clear message and the host keeps working.
#include <gtest/gtest.h>

#include <dlfcn.h>
#include <algorithm>
#include <filesystem>
#include <initializer_list>

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

// Loads one library that must be refused; every part must be in its one diagnostic.
static void expect_refused(Registry& r, const fs::path& file, std::initializer_list<const char*> parts) {
    EXPECT_FALSE(r.load_library(kRoot / file)) << file;
    const std::string d = only_diagnostic(r);
    for (const char* part : parts) EXPECT_TRUE(contains(d, part)) << d;
}

static void expect_refused(const fs::path& file, std::initializer_list<const char*> parts) {
    Registry r;
    expect_refused(r, file, parts);
}

TEST(Loader, NoEntrySymbol) {
    expect_refused("no_entry/libcm_no_entry.so", {"libcm_no_entry.so", "no conceptmesh_plugin_entry symbol"});
}

TEST(Loader, WrongPluginAbi) {
    Registry r;
    expect_refused(r, "wrong_abi/libcm_wrong_abi.so", {"libcm_wrong_abi.so", "plugin ABI 101", "rebuild the plugin"});
    EXPECT_EQ(r.find("test.wrong_abi"), nullptr);
}

TEST(Loader, WrongOpenVdbAbi) { expect_refused("wrong_vdb/libcm_wrong_vdb.so", {"OpenVDB ABI 11", "OpenVDB ABI 10"}); }

TEST(Loader, LibraryThatFailsToLoad) {
    expect_refused("unresolved/libcm_unresolved.so", {"could not be loaded", "conceptmesh_symbol_that_does_not_exist"});
    expect_refused("garbage/libcm_garbage.so", {"libcm_garbage.so", "could not be loaded"});
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

TEST(Loader, EntryPointThatThrows) { expect_refused("throwing_entry/libcm_throwing_entry.so", {"entry exploded"}); }

TEST(Loader, APluginStaysMappedAfterItsRegistryIsGone) {
    // A worker thread may still be returning through a plugin's task code when its
    // registry goes (at exit): the library must never be unmapped under it.
    const fs::path lib = kRoot / "good" / "libcm_testkit.so";
    {
        Registry r;
        ASSERT_TRUE(r.load_library(lib));
    }
    void* h = ::dlopen(lib.c_str(), RTLD_NOW | RTLD_NOLOAD);
    EXPECT_NE(h, nullptr) << lib << " was unmapped when its registry was destroyed";
    if (h) ::dlclose(h);
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

// A plugin its folder's index names is loaded when one of its stages is first asked for.
TEST(Loader, AnIndexedPluginLoadsOnFirstUse) {
    Registry r;
    r.load_directories({kRoot / "indexed"});
    EXPECT_TRUE(r.loaded_files().empty()) << "loaded before any stage was asked for";
    ASSERT_NE(r.find("test.box"), nullptr);
    ASSERT_EQ(r.loaded_files().size(), 1u);
    EXPECT_EQ(r.loaded_files()[0].filename(), "libcm_testkit.so");
    EXPECT_EQ(r.create("test.sleep")->info().name, "test.sleep");
    EXPECT_EQ(r.loaded_files().size(), 1u); // once
    EXPECT_TRUE(r.diagnostics().empty());
}

// An unknown stage may be in any plugin: every one is loaded before the answer is no.
TEST(Loader, AStageNoIndexNamesLoadsEveryPlugin) {
    Registry r;
    r.load_directories({kRoot / "indexed"});
    EXPECT_EQ(r.find("no.such.stage"), nullptr);
    EXPECT_EQ(r.loaded_files().size(), 1u);
    try {
        r.create("no.such.stage");
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_TRUE(contains(e.what(), "test.box")) << e.what(); // the known stages are listed
    }
}

// An index that names a stage its plugin lacks is reported, and then every plugin is
// loaded: a stale index costs time, never a stage. A line that is not a plugin is skipped.
TEST(Loader, AStaleIndexIsReportedAndEveryPluginIsLoaded) {
    Registry r;
    r.load_directories({kRoot / "stale_index"});
    ASSERT_EQ(r.diagnostics().size(), 1u);
    EXPECT_TRUE(contains(r.diagnostics()[0], "not-a-plugin.txt") || contains(r.diagnostics()[0], "line 2"))
        << r.diagnostics()[0];
    EXPECT_EQ(r.find("test.removed_stage"), nullptr);
    const auto d = r.diagnostics();
    ASSERT_EQ(d.size(), 2u);
    EXPECT_TRUE(contains(d[1], "plugins.index")) << d[1];
    EXPECT_TRUE(contains(d[1], "out of date")) << d[1];
    EXPECT_TRUE(contains(d[1], "test.removed_stage")) << d[1];
    // The stages the plugin does have are all there, the ones the index missed too.
    EXPECT_NE(r.find("test.box"), nullptr);
    EXPECT_NE(r.find("test.needs_views"), nullptr);
}

// A plugin the index names that cannot load is reported when its stage is asked for; a
// plugin the index does not name is loaded at once.
TEST(Loader, AnIndexedPluginThatFailsIsReportedWhenUsed) {
    Registry r;
    r.load_directories({kRoot / "indexed_broken"});
    ASSERT_EQ(r.loaded_files().size(), 1u);
    EXPECT_EQ(r.loaded_files()[0].filename(), "libcm_testkit.so");
    EXPECT_TRUE(r.diagnostics().empty());
    EXPECT_EQ(r.find("test.garbage"), nullptr);
    const auto d = r.diagnostics();
    ASSERT_GE(d.size(), 1u);
    EXPECT_TRUE(contains(d[0], "libcm_garbage.so")) << d[0];
    EXPECT_TRUE(contains(d[0], "could not be loaded")) << d[0];
}

// The built plugin folder has an index naming every plugin it holds, with the stages each
// really has: the index is the build's, never out of date.
TEST(Loader, TheBuiltPluginFolderIsIndexedRightly) {
    const fs::path dir = Registry::default_dirs()[0];
    ASSERT_TRUE(fs::exists(dir / Registry::kIndexFile)) << dir;
    Registry lazy;
    lazy.load_directories({dir});
    EXPECT_TRUE(lazy.loaded_files().empty()) << "a plugin of the built folder is missing from its index";
    ASSERT_NE(lazy.find("views.load"), nullptr);
    EXPECT_EQ(lazy.loaded_files().size(), 1u) << "views.load should need its own plugin only";
    const auto names = lazy.names(); // loads the rest, checking each against the index
    EXPECT_TRUE(lazy.diagnostics().empty()) << lazy.diagnostics()[0];
    EXPECT_NE(std::find(names.begin(), names.end(), "hull.carve"), names.end());
}
