// A file output stream that reports its progress per chunk and can be stopped between
// chunks: the writers (OpenMesh's, tinygltf's, our own) hand their bytes to it, and a stop
// asked for while a large file is written takes effect within a chunk, not at the end.
#pragma once
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <ostream>
#include <vector>

namespace cm {

/// Called per chunk with the fraction done in [0, 1]; it may throw (cm::Cancelled) to stop.
using ChunkProgress = std::function<void(double)>;

/// @brief An ostream to a file, written in chunks of 1 MB; after each chunk `progress` is
/// called with bytes written / `expected_bytes` (capped below 1). When `progress` throws,
/// the stream fails at once (every later write is refused cheaply, so the library writing
/// through it returns soon) and finish() rethrows the exception.
class ProgressFileStream : public std::ostream {
public:
    ProgressFileStream(const std::filesystem::path& file, std::uint64_t expected_bytes, ChunkProgress progress);
    ~ProgressFileStream() override;
    bool is_open() const { return buf_.file.is_open(); }
    /// Flushes and closes; rethrows what `progress` threw; false when a write failed.
    bool finish();

private:
    struct Buf : std::streambuf {
        std::filebuf file;
        std::vector<char> chunk;
        std::uint64_t written = 0, expected = 1;
        ChunkProgress progress;
        std::exception_ptr stopped;
        void start();
        bool flush_chunk();
        int_type overflow(int_type c) override;
        std::streamsize xsputn(const char* s, std::streamsize n) override;
        int sync() override;
    } buf_;
};

/// Calls `progress` with fractions of [lo, hi]: a part of a larger job.
ChunkProgress progress_part(const ChunkProgress& progress, double lo, double hi);

} // namespace cm
