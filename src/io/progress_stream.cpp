#include "io/progress_stream.h"

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "core/error.h"

namespace cm {

namespace {
constexpr std::size_t kChunk = std::size_t(1) << 20;
}

ProgressFileStream::ProgressFileStream(const std::filesystem::path& file, std::uint64_t expected_bytes,
                                       Progress progress)
    : std::ostream(nullptr) {
    buf_.start();
    buf_.expected = std::max<std::uint64_t>(expected_bytes, 1);
    buf_.progress = std::move(progress);
    buf_.file.open(file, std::ios::out | std::ios::binary | std::ios::trunc);
    rdbuf(&buf_);
    if (!buf_.file.is_open()) setstate(std::ios::badbit);
}

ProgressFileStream::~ProgressFileStream() = default;

void ProgressFileStream::Buf::start() {
    chunk.resize(kChunk);
    setp(chunk.data(), chunk.data() + chunk.size());
}

bool ProgressFileStream::Buf::flush_chunk() {
    if (stopped) return false;
    const std::streamsize n = pptr() - pbase();
    if (n > 0 && file.sputn(pbase(), n) != n) return false;
    setp(chunk.data(), chunk.data() + chunk.size());
    written += std::uint64_t(n);
    if (progress && n > 0) try {
            progress(std::min(0.999, double(written) / double(expected)));
        } catch (...) {
            stopped = std::current_exception();
            return false;
        }
    return true;
}

ProgressFileStream::Buf::int_type ProgressFileStream::Buf::overflow(int_type c) {
    if (!flush_chunk()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
        *pptr() = traits_type::to_char_type(c);
        pbump(1);
    }
    return traits_type::not_eof(c);
}

// Large blocks (a glTF buffer) go through in chunks, so they too can be stopped.
std::streamsize ProgressFileStream::Buf::xsputn(const char* s, std::streamsize n) {
    std::streamsize done = 0;
    while (done < n) {
        if (stopped) return done;
        if (pptr() == epptr() && !flush_chunk()) return done;
        const std::streamsize k = std::min<std::streamsize>(n - done, epptr() - pptr());
        std::memcpy(pptr(), s + done, std::size_t(k));
        pbump(int(k));
        done += k;
    }
    return done;
}

int ProgressFileStream::Buf::sync() { return flush_chunk() && file.pubsync() == 0 ? 0 : -1; }

bool ProgressFileStream::finish() {
    const bool flushed = buf_.flush_chunk();
    const bool closed = buf_.file.close() != nullptr;
    if (buf_.stopped) std::rethrow_exception(buf_.stopped);
    return flushed && closed && !bad() && !fail();
}

void write_file_bytes(const std::filesystem::path& file, std::string_view bytes, Progress progress) {
    ProgressFileStream out(file, bytes.size(), std::move(progress));
    out.write(bytes.data(), std::streamsize(bytes.size()));
    if (!out.finish()) throw Error("cannot write \"" + file.string() + "\": " + std::strerror(errno));
}

} // namespace cm
