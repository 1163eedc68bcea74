// Output files appear whole or not at all. A run writes each file under a unique
// temporary name in the file's own folder (so the final rename is atomic), and the
// commit moves every one into place once the whole run succeeded; anything that
// fails on the way removes the temporaries that are left.
#pragma once
#include <filesystem>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "core/data.h" // temporary_path()

namespace cm {

/// The files of one run, staged under temporary names. Thread-safe.
class FileCommit {
public:
    FileCommit() = default;
    FileCommit(const FileCommit&) = delete;
    FileCommit& operator=(const FileCommit&) = delete;
    /// Removes the temporaries unless commit() succeeded.
    ~FileCommit();

    /// Records that `tmp` is to become `final_path`.
    void add(const std::filesystem::path& tmp, const std::filesystem::path& final_path);
    /// A new temporary name for `final_path`, recorded as by add().
    std::filesystem::path stage(const std::filesystem::path& final_path);
    /// Moves every staged file into place, in the order staged; returns the final paths.
    /// When a move fails, the temporaries left are removed and cm::Error names the file.
    std::vector<std::filesystem::path> commit();
    /// Removes every temporary (a failed or cancelled run).
    void discard();

private:
    std::mutex mutex_;
    std::vector<std::pair<std::filesystem::path, std::filesystem::path>> staged_; ///< tmp -> final
    bool done_ = false;
};

/// Writes `bytes` to `path` through a temporary file and a rename; throws cm::Error
/// naming `path` (never the temporary).
void write_file_atomic(const std::filesystem::path& path, const std::string& bytes);

} // namespace cm
