// Output files appear whole or not at all, and all of a run's files or none. A run
// writes each file under a unique temporary name in the file's own folder (so each
// rename is atomic), and the commit moves every one into place once the whole run
// succeeded. A commit that fails half-way puts back what it replaced; a failed or
// cancelled run leaves neither temporaries nor the folders it made for its outputs.
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

    /// Records that `tmp` is to become `final_path`, and makes the folders on the way to
    /// it that are missing (removed again unless the commit succeeds).
    void add(const std::filesystem::path& tmp, const std::filesystem::path& final_path);
    /// A new temporary name for `final_path`, recorded as by add().
    std::filesystem::path stage(const std::filesystem::path& final_path);
    /// `text` (an error message) with every staged temporary named by its final path: the
    /// user knows the path they asked for, not "x.obj.part-4711-0.obj".
    std::string with_final_names(std::string text) const;
    /// The final paths staged so far, in the order staged.
    std::vector<std::filesystem::path> finals() const;
    /// Moves every staged file into place, in the order staged; returns the final paths.
    /// Nothing moves when a final path is a folder. When a move fails, the files already
    /// moved are taken back (files they replaced restored), everything staged is removed,
    /// and cm::Error names the file and the cause.
    std::vector<std::filesystem::path> commit();
    /// Removes every temporary and the folders made for them (a failed or cancelled run).
    void discard();

private:
    void discard_locked();
    mutable std::mutex mutex_;
    std::vector<std::pair<std::filesystem::path, std::filesystem::path>> staged_; ///< tmp -> final
    std::vector<std::filesystem::path> made_dirs_; ///< folders add() made, outermost first
    bool done_ = false;
};

/// Removes, at once, every temporary file and made folder of every FileCommit of the
/// process that has not been committed or discarded. Async-signal-safe (unlink and rmdir
/// only): for a signal handler that ends the process without unwinding.
void remove_uncommitted_files_now() noexcept;

/// Writes `bytes` to `path` through a temporary file and a rename; throws cm::Error
/// naming `path` (never the temporary).
void write_file_atomic(const std::filesystem::path& path, const std::string& bytes);

} // namespace cm
