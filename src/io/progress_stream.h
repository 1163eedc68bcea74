// A file output stream that reports its progress per chunk and can be stopped between
// chunks: the writers (OpenMesh's, tinygltf's, our own) hand their bytes to it, and a stop
// asked for while a large file is written takes effect within a chunk, not at the end.
#pragma once
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <string_view>
#include <vector>

#include "core/progress.h"

namespace cm {

/// @brief An ostream to a file, written in chunks of 1 MB; after each chunk `progress`
/// reports bytes written / `expected_bytes` (capped below 1). When it throws (cm::Cancelled),
/// the stream fails at once (every later write is refused cheaply, so the library writing
/// through it returns soon) and finish() rethrows the exception.
class ProgressFileStream : public std::ostream {
public:
    ProgressFileStream(const std::filesystem::path& file, std::uint64_t expected_bytes, Progress progress);
    ~ProgressFileStream() override;
    bool is_open() const { return buf_.file.is_open(); }
    /// Flushes and closes; rethrows what `progress` threw; false when a write failed.
    bool finish();

private:
    struct Buf : std::streambuf {
        std::filebuf file;
        std::vector<char> chunk;
        std::uint64_t written = 0, expected = 1;
        Progress progress;
        std::exception_ptr stopped;
        void start();
        bool flush_chunk();
        int_type overflow(int_type c) override;
        std::streamsize xsputn(const char* s, std::streamsize n) override;
        int sync() override;
    } buf_;
};

/// Writes `bytes` to `file` through a ProgressFileStream: `progress` per chunk, and a stop it
/// throws leaves a partial file for the caller (who wrote to a temporary name) to remove.
/// @throw cm::Error naming the file when it cannot be written.
void write_file_bytes(const std::filesystem::path& file, std::string_view bytes, Progress progress = {});

} // namespace cm
