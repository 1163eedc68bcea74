// All of a run's outputs or none: a commit that fails half-way, an output path that is a
// folder, a report that cannot be written, a second Ctrl-C. Nothing of the run may remain.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <chrono>
#include <initializer_list>
#include <thread>

#include "core/error.h"
#include "io/file_commit.h"
#include "support/test_support.h"
#include "testkit_cli.h"

using namespace cm;
namespace fs = std::filesystem;
using test::cli_with_testkit;
using test::kFixtures;

using test::listing;

namespace {

// A box written to `path`, and a preview-like second output at `second`.
std::string two_outputs(const std::string& path, const std::string& second) {
    return "nodes:\n"
           "  - {id: box, stage: test.box}\n"
           "  - {id: write, stage: mesh.write, inputs: {mesh: box}, params: {path: " +
           path +
           "}}\n"
           "  - {id: write2, stage: mesh.write, inputs: {mesh: box}, params: {path: " +
           second + "}}\n";
}

} // namespace

TEST(Outputs, ACommitThatFailsHalfWayPutsBackWhatItReplaced) {
    test::TempDir dir("outputs_rollback");
    test::write_text(dir / "a.txt", "old");
    {
        FileCommit files;
        test::write_text(files.stage(dir / "a.txt"), "new");
        const fs::path b = files.stage(dir / "b.txt");
        test::write_text(b, "b");
        fs::remove(b); // the second move will fail
        try {
            files.commit();
            FAIL() << "expected the commit to fail";
        } catch (const Error& e) {
            EXPECT_HAS(e.what(), "b.txt");
            EXPECT_HAS(e.what(), "No such file or directory"); // the cause, not the clean-up's "Success"
        }
    }
    EXPECT_EQ(test::read_text(dir / "a.txt"), "old");
    EXPECT_EQ(listing(dir.path()), std::vector<std::string>{"a.txt"});
}

TEST(Outputs, AFolderInTheWayMovesNothing) {
    test::TempDir dir("outputs_folder");
    fs::create_directory(dir / "b.txt");
    {
        FileCommit files;
        test::write_text(files.stage(dir / "a.txt"), "a");
        test::write_text(files.stage(dir / "b.txt"), "b");
        try {
            files.commit();
            FAIL() << "expected the commit to fail";
        } catch (const Error& e) {
            EXPECT_HAS(e.what(), "b.txt\": it is a folder");
        }
    }
    EXPECT_EQ(listing(dir.path()), std::vector<std::string>{"b.txt"});
}

TEST(Outputs, FoldersMadeForAFailedRunGoAgain) {
    test::TempDir dir("outputs_made_dirs");
    {
        FileCommit files;
        test::write_text(files.stage(dir / "new" / "deeper" / "x.obj"), "x");
        EXPECT_TRUE(fs::is_directory(dir / "new" / "deeper"));
        files.discard();
    }
    EXPECT_TRUE(listing(dir.path()).empty());
    {
        FileCommit files;
        test::write_text(files.stage(dir / "kept" / "x.obj"), "x");
        files.commit();
    }
    EXPECT_EQ(listing(dir.path()), (std::vector<std::string>{"kept", "kept/x.obj"}));
}

TEST(Outputs, TheSignalPathRemovesWhatIsUncommitted) {
    test::TempDir dir("outputs_signal_path");
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        FileCommit* files = new FileCommit; // never destroyed: the process ends without unwinding
        test::write_text(files->stage(dir / "made" / "x.obj"), "x");
        remove_uncommitted_files_now();
        ::_exit(0);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    EXPECT_TRUE(WIFEXITED(status));
    EXPECT_TRUE(listing(dir.path()).empty());
}

TEST(Outputs, AnOutputPathThatIsAFolderIsRefusedBeforeTheRun) {
    test::TempDir dir("outputs_cli_folder");
    fs::create_directory(dir / "second.obj");
    test::write_text(dir / "p.yaml", two_outputs("first.obj", "second.obj"));
    const auto r = cli_with_testkit("run p.yaml", dir.path());
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_HAS(r.err, "second.obj\" is a folder");
    EXPECT_EQ(listing(dir.path()), (std::vector<std::string>{"p.yaml", "second.obj"}));
}

TEST(Outputs, AReportThatIsAFolderIsRefusedBeforeTheRun) {
    test::TempDir dir("outputs_cli_report");
    fs::create_directory(dir / "rep");
    test::write_text(dir / "p.yaml", two_outputs("out/first.obj", "out/second.obj"));
    const auto r = cli_with_testkit("run p.yaml --report rep", dir.path());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_HAS(r.err, "--report \"rep\" is a folder");
    EXPECT_EQ(listing(dir.path()), (std::vector<std::string>{"p.yaml", "rep"}));
}

TEST(Outputs, TheReportIsCommittedWithTheOutputs) {
    test::TempDir dir("outputs_cli_report_ok");
    test::write_text(dir / "p.yaml", two_outputs("out/first.obj", "out/second.obj"));
    const auto r = cli_with_testkit("run p.yaml --report run.json", dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(listing(dir.path()),
              (std::vector<std::string>{"out", "out/first.obj", "out/second.obj", "p.yaml", "run.json"}));
    EXPECT_HAS(test::read_text(dir / "run.json"), "first.obj");
}

namespace {

// Starts `conceptmesh run p.yaml` in `dir` with the test kit, waits until the run has
// staged out/m.obj, sends `signals` 100 ms apart, and returns the exit status.
int run_and_signal(const test::TempDir& dir, std::initializer_list<int> signals) {
    const pid_t pid = ::fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        ::setenv("CONCEPTMESH_PLUGIN_PATH", (kFixtures / "good").c_str(), 1);
        if (::chdir(dir.path().c_str()) != 0) ::_exit(99);
        if (!::freopen("/dev/null", "w", stderr)) ::_exit(97);
        ::execl(CM_EXE, CM_EXE, "run", "p.yaml", static_cast<char*>(nullptr));
        ::_exit(98);
    }
    bool staged = false;
    for (int i = 0; i < 500 && !staged; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        std::error_code ec;
        if (fs::is_directory(dir / "out", ec))
            for (const auto& e : fs::directory_iterator(dir / "out", ec))
                staged = staged || e.path().string().find(".part-") != std::string::npos;
    }
    EXPECT_TRUE(staged) << "the run never staged its mesh";
    for (int sig : signals) {
        ::kill(pid, sig);
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The mesh is staged at once; then a stage holds the run for `seconds`.
std::string held_run(bool ignore_cancel, int seconds = 30) {
    return "nodes:\n"
           "  - {id: box, stage: test.box}\n"
           "  - {id: write, stage: mesh.write, inputs: {mesh: box}, params: {path: out/m.obj}}\n"
           "  - {id: held, stage: test.sleep, inputs: {mesh: box}, params: {seconds: " +
           std::to_string(seconds) + ", ignore_cancel: " + (ignore_cancel ? "true" : "false") + "}}\n";
}

} // namespace

TEST(Outputs, ASecondCtrlCLeavesNothing) {
    // A stage that never looks at cancellation: only the second Ctrl-C ends the run.
    test::TempDir dir("outputs_ctrl_c");
    test::write_text(dir / "p.yaml", held_run(true));
    EXPECT_EQ(run_and_signal(dir, {SIGINT, SIGINT}), 130);
    EXPECT_EQ(listing(dir.path()), std::vector<std::string>{"p.yaml"});
}

TEST(Outputs, SigtermStopsTheRunWith143AndLeavesNothing) {
    test::TempDir dir("outputs_sigterm");
    test::write_text(dir / "p.yaml", held_run(false));
    EXPECT_EQ(run_and_signal(dir, {SIGTERM}), 143);
    EXPECT_EQ(listing(dir.path()), std::vector<std::string>{"p.yaml"});
}

TEST(Outputs, AStopAskedForDuringAStageThatDoesNotLookStillLeavesNothing) {
    // The held stage never looks and finishes on its own after a second: the run must still
    // end as cancelled, not commit.
    test::TempDir dir("outputs_late_cancel");
    test::write_text(dir / "p.yaml", held_run(true, 1));
    EXPECT_EQ(run_and_signal(dir, {SIGINT}), 130);
    EXPECT_EQ(listing(dir.path()), std::vector<std::string>{"p.yaml"});
}
