// find_self_intersections() of mesh_intersect.h, and the answers it keeps by a fingerprint of
// the mesh asked about.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <utility>
#include <vector>

#include <tbb/parallel_for.h>

#include "geometry/mesh_intersect.h"

namespace cm {

namespace {

// A 128-bit fingerprint of a mesh's positions and triangles (their bytes, and their counts):
// two independent 64-bit lanes, each word mixed by a 128-bit multiply with the lane's key and
// its place, chunks side by side and combined in order (the same value on any thread count).
struct Fingerprint {
    std::uint64_t a = 0, b = 0;
    bool operator==(const Fingerprint&) const = default;
};

__extension__ typedef unsigned __int128 U128; // GCC and Clang on 64-bit targets

std::uint64_t mum(std::uint64_t x, std::uint64_t y) {
    const U128 r = static_cast<U128>(x) * y;
    return std::uint64_t(r) ^ std::uint64_t(r >> 64);
}

Fingerprint fingerprint_of(const Mesh& m) {
    auto words = [](const auto& v) {
        return std::pair<const unsigned char*, std::size_t>(reinterpret_cast<const unsigned char*>(v.data()),
                                                            v.size() * sizeof(v[0]));
    };
    Fingerprint f{mum(m.positions.size() ^ 0x9E3779B97F4A7C15ull, 0xD6E8FEB86659FD93ull),
                  mum(m.triangles.size() ^ 0xC2B2AE3D27D4EB4Full, 0x165667B19E3779F9ull)};
    for (const auto& span : {words(m.positions), words(m.triangles)}) {
        const unsigned char* data = span.first; // (named, not bound: a lambda below reads them)
        const std::size_t bytes = span.second;
        constexpr std::size_t kChunk = 1 << 15; // words per chunk
        const std::size_t nwords = (bytes + 7) / 8, nchunks = (nwords + kChunk - 1) / kChunk;
        std::vector<Fingerprint> part(nchunks);
        tbb::parallel_for(std::size_t(0), nchunks, [&](std::size_t c) {
            Fingerprint h{c * 0xA0761D6478BD642Full + 1, c * 0xE7037ED1A0B428DBull + 2};
            for (std::size_t w = c * kChunk, e = std::min(nwords, (c + 1) * kChunk); w < e; ++w) {
                std::uint64_t x = 0;
                std::memcpy(&x, data + 8 * w, std::min<std::size_t>(8, bytes - 8 * w));
                h.a = mum(h.a ^ x ^ 0x8EBC6AF09C88C6E3ull, 0x589965CC75374CC3ull + w);
                h.b = mum(h.b + x + 0x1D8E4E27C47D124Full, 0xEB44ACCAB455D165ull ^ (w << 1));
            }
            part[c] = h;
        });
        for (const Fingerprint& h : part) {
            f.a = mum(f.a ^ h.a, 0x9FB21C651E98DF25ull);
            f.b = mum(f.b + h.b, 0xBF58476D1CE4E5B9ull);
        }
    }
    return f;
}

// The last few answers, by fingerprint: a mesh is often checked twice as it is (mesh.reduce
// checks its result, mesh.write checks what it writes), and the second check of 50 k faces
// costs a quarter of the write. Asked by content, an answer cannot go stale.
class CrossingMemo {
public:
    bool find(const Fingerprint& f, std::vector<FacePair>& out) {
        std::lock_guard<std::mutex> lock(mutex_);
        for (const auto& [key, pairs] : items_)
            if (key == f) {
                out = pairs;
                return true;
            }
        return false;
    }
    void keep(const Fingerprint& f, const std::vector<FacePair>& pairs) {
        std::lock_guard<std::mutex> lock(mutex_);
        items_[next_++ % items_.size()] = {f, pairs};
    }

private:
    std::mutex mutex_;
    std::array<std::pair<Fingerprint, std::vector<FacePair>>, 4> items_{};
    std::size_t next_ = 0;
};

CrossingMemo& crossing_memo() {
    static CrossingMemo memo;
    return memo;
}

} // namespace

std::vector<FacePair> find_self_intersections(const Mesh& m, Progress progress) {
    if (m.triangles.empty()) return {};
    const Fingerprint f = fingerprint_of(m);
    std::vector<FacePair> pairs;
    if (crossing_memo().find(f, pairs)) {
        progress(1.0);
        return pairs;
    }
    const std::vector<char> fans = embedded_fans(m.triangles, m.positions);
    pairs = SelfIntersectionIndex(m.triangles, m.positions).all(m.positions, progress, &fans);
    crossing_memo().keep(f, pairs);
    return pairs;
}

std::size_t count_self_intersections(const Mesh& m) { return find_self_intersections(m).size(); }

} // namespace cm
