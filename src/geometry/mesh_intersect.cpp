#include "geometry/mesh_intersect.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <mutex>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include "core/error.h"

namespace cm {

namespace {

// Does the segment [p, q] cross triangle (a, b, c) at a point strictly inside both?
bool segment_crosses(const Vec3d& p, const Vec3d& q, const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    const Vec3d d = q - p, e1 = b - a, e2 = c - a;
    const Vec3d h = cross(d, e2);
    const double det = dot(e1, h);
    const double scale = length(d) * length(e1) * length(e2);
    if (std::fabs(det) <= 1e-12 * scale) return false; // parallel or coplanar
    const double inv = 1.0 / det;
    const Vec3d s = p - a;
    const double u = dot(s, h) * inv;
    if (u <= 1e-9 || u >= 1 - 1e-9) return false;
    const Vec3d qv = cross(s, e1);
    const double v = dot(d, qv) * inv;
    if (v <= 1e-9 || u + v >= 1 - 1e-9) return false;
    const double t = dot(e2, qv) * inv;
    return t > 1e-9 && t < 1 - 1e-9;
}

} // namespace

namespace {

using Box = SelfIntersectionIndex::Box;

Box face_box(const std::vector<Vec3f>& p, const std::array<std::uint32_t, 3>& t) {
    const Vec3f &a = p[t[0]], &b = p[t[1]], &c = p[t[2]];
    return {vmin(a, vmin(b, c)), vmax(a, vmax(b, c))};
}

bool overlap(const Box& a, const Box& b) {
    return !(a.lo.x > b.hi.x || b.lo.x > a.hi.x || a.lo.y > b.hi.y || b.lo.y > a.hi.y || a.lo.z > b.hi.z ||
             b.lo.z > a.hi.z);
}

} // namespace

bool triangles_cross(const std::vector<Vec3f>& p, const std::array<std::uint32_t, 3>& ta,
                     const std::array<std::uint32_t, 3>& tb) {
    int shared = 0, sa = -1, sb = -1;
    for (int x = 0; x < 3; ++x)
        for (int y = 0; y < 3; ++y)
            if (ta[x] == tb[y]) {
                ++shared;
                sa = x;
                sb = y;
            }
    if (shared >= 2) return false;
    const Vec3d A[3] = {Vec3d(p[ta[0]]), Vec3d(p[ta[1]]), Vec3d(p[ta[2]])};
    const Vec3d B[3] = {Vec3d(p[tb[0]]), Vec3d(p[tb[1]]), Vec3d(p[tb[2]])};
    // Early out: the other triangle's (unshared) corners all strictly on one side of a plane.
    auto one_side = [](const Vec3d(&T)[3], const Vec3d(&U)[3], int skip) {
        const Vec3d n = cross(T[1] - T[0], T[2] - T[0]);
        bool pos = false, neg = false;
        for (int i = 0; i < 3; ++i) {
            if (i == skip) continue;
            const double d = dot(n, U[i] - T[0]);
            pos |= d >= 0;
            neg |= d <= 0;
        }
        return !(pos && neg);
    };
    if (one_side(A, B, sb) || one_side(B, A, sa)) return false;
    for (int e = 0; e < 3; ++e) {
        // With a shared vertex, only the edges away from it can cross properly.
        if (!(shared == 1 && (e == sa || (e + 1) % 3 == sa)) && segment_crosses(A[e], A[(e + 1) % 3], B[0], B[1], B[2]))
            return true;
        if (!(shared == 1 && (e == sb || (e + 1) % 3 == sb)) && segment_crosses(B[e], B[(e + 1) % 3], A[0], A[1], A[2]))
            return true;
    }
    return false;
}

SelfIntersectionIndex::SelfIntersectionIndex(const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                             const std::vector<Vec3f>& a, const std::vector<Vec3f>* b)
    : triangles_(triangles), a_(a), b_(b) {
    // Nothing per face is stored but the (cell, face) keys: on machines where fresh pages are
    // expensive, arrays of boxes cost more to allocate than the boxes cost to recompute.
    const std::size_t nf = triangles.size();
    if (nf == 0) return;
    struct Sum {
        Box box;
        double diag = 0;
    };
    const Sum total = tbb::parallel_deterministic_reduce(
        tbb::blocked_range<std::size_t>(0, nf, 8192), Sum{box(0), 0.0},
        [&](const tbb::blocked_range<std::size_t>& r, Sum s) {
            for (std::size_t f = r.begin(); f != r.end(); ++f) {
                const Box x = box(std::uint32_t(f));
                s.box = {vmin(s.box.lo, x.lo), vmax(s.box.hi, x.hi)};
                s.diag += double(length(x.hi - x.lo));
            }
            return s;
        },
        [](Sum x, const Sum& y) {
            x.box = {vmin(x.box.lo, y.box.lo), vmax(x.box.hi, y.box.hi)};
            x.diag += y.diag;
            return x;
        });
    origin_ = Vec3d(total.box.lo);
    const Vec3d extent = Vec3d(total.box.hi) - origin_;
    if (!std::isfinite(extent.x + extent.y + extent.z + origin_.x + origin_.y + origin_.z) ||
        !std::isfinite(total.diag))
        throw Error("the mesh has vertices with infinite or NaN coordinates");
    const double largest = std::max({extent.x, extent.y, extent.z, 1e-30});
    // Cells of about two mean face sizes; grown while large faces would fill too many
    // cells or the cells would not fit the 32 bits of a key.
    cell_ = std::max(2.0 * total.diag / double(nf), largest * 1e-6);
    inv_cell_ = 1.0 / cell_;
    low_bits_ = nf <= kFaceMask;
    // The entries sorted without a second array of them: each chunk of faces counts its
    // entries per bucket (a range of consecutive cell keys), the counts give every (bucket,
    // chunk) its place, the chunks write their entries there side by side, and each bucket
    // is sorted on its own, in the caches. The result is the fully sorted array.
    const std::size_t chunk = std::max<std::size_t>(std::size_t(1) << 16, (nf + 31) / 32);
    const std::size_t chunks = (nf + chunk - 1) / chunk;
    auto for_cells = [&](const Range& r, std::uint32_t f, auto&& emit) {
        for (auto i = r.lo[0]; i <= r.hi[0]; ++i)
            for (auto j = r.lo[1]; j <= r.hi[1]; ++j)
                for (auto k = r.lo[2]; k <= r.hi[2]; ++k) {
                    const std::uint64_t first =
                        low_bits_ ? std::uint64_t((i == r.lo[0]) | (j == r.lo[1]) << 1 | (k == r.lo[2]) << 2) : 0;
                    emit(key(i, j, k), (first << kFaceBits) | f);
                }
    };
    constexpr int kBucketBits = 16;
    int shift = 0;
    std::size_t buckets = 1;
    std::vector<std::uint64_t> place; // per (chunk, bucket): counts, then where each writes next
    for (;;) {
        for (int x = 0; x < 3; ++x) dims_[std::size_t(x)] = std::uint64_t(std::floor(extent[x] / cell_)) + 1;
        if (dims_[0] * dims_[1] * dims_[2] >= (std::uint64_t(1) << 32)) {
            cell_ *= 2;
            inv_cell_ = 1.0 / cell_;
            continue;
        }
        const std::uint64_t top_key = dims_[0] * dims_[1] * dims_[2] - 1;
        shift = std::max(0, int(std::bit_width(top_key)) - kBucketBits);
        buckets = std::size_t(top_key >> shift) + 1;
        place.assign(chunks * buckets, 0);
        // Each face's cells counted from its range first (no face can make a chunk enumerate
        // past the limit): over the limit, the cells are too small for the faces.
        const std::uint64_t limit = 16 * std::uint64_t(nf) + 1024;
        std::atomic<std::uint64_t> total{0};
        std::atomic<bool> over{false};
        tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
            std::uint64_t* count = place.data() + c * buckets;
            std::uint64_t mine = 0;
            for (std::size_t f = c * chunk, e = std::min(nf, f + chunk); f < e; ++f) {
                const Range r = cells(box(std::uint32_t(f)));
                mine += (r.hi[0] - r.lo[0] + 1) * (r.hi[1] - r.lo[1] + 1) * (r.hi[2] - r.lo[2] + 1);
                if (mine > limit || over.load(std::memory_order_relaxed)) {
                    over = true;
                    return;
                }
                for_cells(r, std::uint32_t(f), [&](std::uint64_t cell, std::uint64_t) { ++count[cell >> shift]; });
            }
            if (total.fetch_add(mine) + mine > limit) over = true;
        });
        if (!over) break;
        cell_ *= 2;
        inv_cell_ = 1.0 / cell_;
    }
    std::vector<std::uint64_t> bucket_start(buckets + 1, 0);
    std::uint64_t at = 0;
    for (std::size_t b = 0; b < buckets; ++b) {
        bucket_start[b] = at;
        for (std::size_t c = 0; c < chunks; ++c) {
            const std::uint64_t n = place[c * buckets + b];
            place[c * buckets + b] = at;
            at += n;
        }
    }
    bucket_start[buckets] = at;
    entries_.resize(at);
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
        std::uint64_t* next = place.data() + c * buckets;
        for (std::size_t f = c * chunk, e = std::min(nf, f + chunk); f < e; ++f)
            for_cells(cells(box(std::uint32_t(f))), std::uint32_t(f), [&](std::uint64_t cell, std::uint64_t low) {
                entries_[next[cell >> shift]++] = (cell << 32) | low;
            });
    });
    std::vector<std::uint64_t>().swap(place);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, buckets, 64), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t b = r.begin(); b != r.end(); ++b)
            std::sort(entries_.begin() + std::ptrdiff_t(bucket_start[b]),
                      entries_.begin() + std::ptrdiff_t(bucket_start[b + 1]));
    });
    // The runs of one cell, found per bucket (a cell lies in one bucket) side by side.
    std::vector<std::size_t> runs_before(buckets + 1, 0);
    auto starts_run = [&](std::size_t i) { return i == 0 || (entries_[i] >> 32) != (entries_[i - 1] >> 32); };
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, buckets, 64), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t b = r.begin(); b != r.end(); ++b)
            for (std::size_t i = bucket_start[b]; i < bucket_start[b + 1]; ++i) runs_before[b + 1] += starts_run(i);
    });
    for (std::size_t b = 0; b < buckets; ++b) runs_before[b + 1] += runs_before[b];
    runs_.resize(runs_before[buckets] + 1);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, buckets, 64), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t b = r.begin(); b != r.end(); ++b) {
            std::size_t at_run = runs_before[b];
            for (std::size_t i = bucket_start[b]; i < bucket_start[b + 1]; ++i)
                if (starts_run(i)) runs_[at_run++] = i;
        }
    });
    runs_.back() = entries_.size();
}

SelfIntersectionIndex::Box SelfIntersectionIndex::box(std::uint32_t f) const {
    Box x = face_box(a_, triangles_[f]);
    if (b_) {
        const Box y = face_box(*b_, triangles_[f]);
        x = {vmin(x.lo, y.lo), vmax(x.hi, y.hi)};
    }
    return x;
}

SelfIntersectionIndex::Range SelfIntersectionIndex::cells(const Box& b) const {
    Range r;
    for (int a = 0; a < 3; ++a) {
        const auto axis = std::size_t(a);
        const double top = double(dims_[axis] - 1);
        // NaN coordinates (a broken input) land in cell 0 instead of an undefined index.
        auto index = [&](float x) {
            const double i = std::floor((double(x) - origin_[a]) * inv_cell_);
            return std::uint64_t(i > 0 ? std::min(i, top) : 0.0);
        };
        r.lo[axis] = index(b.lo[a]);
        r.hi[axis] = index(b.hi[a]);
    }
    return r;
}

std::vector<FacePair> SelfIntersectionIndex::all(const std::vector<Vec3f>& p,
                                                 const std::function<void(double)>& progress,
                                                 const std::vector<char>* fans) const {
    if (fans && fans->size() != p.size()) fans = nullptr;
    tbb::enumerable_thread_specific<std::vector<FacePair>> found;
    if (runs_.size() < 2) return {};
    std::atomic<std::size_t> done{0};
    const std::size_t ncells = runs_.size() - 1;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, ncells, 256), [&](const tbb::blocked_range<std::size_t>& r) {
        if (progress) progress(double(done.fetch_add(r.size())) / double(ncells));
        auto& local = found.local();
        // Everything the pair tests read, gathered once per face of the cell (the faces of a
        // cell are scattered in memory; the pairs are many more than the faces).
        struct Item {
            Box now; ///< the face's box at p
            std::array<std::uint32_t, 3> tri;
            std::uint32_t face;
            unsigned first; ///< bit a: this cell is the first of the indexed box on axis a
            unsigned fan;   ///< bit k: tri[k]'s fan is embedded (read once per face, not per pair)
        };
        std::vector<Item> items;
        for (std::size_t run = r.begin(); run != r.end(); ++run) {
            const std::size_t b = runs_[run], e = runs_[run + 1];
            const std::uint64_t here = entries_[b] >> 32;
            // The cell's coordinates, for entries that do not carry their first bits.
            const std::uint64_t hk = here % dims_[2], hj = here / dims_[2] % dims_[1], hi = here / dims_[2] / dims_[1];
            items.clear();
            for (std::size_t x = b; x < e; ++x) {
                const std::uint32_t f = face_of(entries_[x]);
                const Box u = box(f);
                unsigned first;
                if (low_bits_) {
                    first = unsigned(entries_[x] >> kFaceBits) & 7u;
                } else {
                    const Range c = cells({u.lo, u.lo});
                    first = unsigned(c.lo[0] == hi) | unsigned(c.lo[1] == hj) << 1 | unsigned(c.lo[2] == hk) << 2;
                }
                const auto& t = triangles_[f];
                const unsigned fan = fans ? unsigned((*fans)[t[0]] != 0) | unsigned((*fans)[t[1]] != 0) << 1 |
                                                unsigned((*fans)[t[2]] != 0) << 2
                                          : 0u;
                items.push_back({b_ ? face_box(p, t) : u, t, f, first, fan});
            }
            // Sweep over the cell's faces, sorted by the low end of their boxes at p (only faces
            // whose boxes at p overlap can cross there; within the boxes of both poses, those
            // are fewer), along the axis the boxes spread most on: a piece of surface in a cell
            // lies across the axis it faces, and the boxes overlap least along the others.
            // The boxes' axes are put in that order (the sweep's first) for the pass below.
            if (items.size() > 2) {
                Vec3f lo = items[0].now.lo, hi = lo;
                for (const Item& it : items) {
                    lo = vmin(lo, it.now.lo);
                    hi = vmax(hi, it.now.lo);
                }
                const Vec3f spread = hi - lo;
                const int axis = spread.x >= spread.y ? (spread.x >= spread.z ? 0 : 2) : (spread.y >= spread.z ? 1 : 2);
                if (axis != 0)
                    for (Item& it : items) {
                        std::swap(it.now.lo.x, it.now.lo[axis]);
                        std::swap(it.now.hi.x, it.now.hi[axis]);
                    }
            }
            std::sort(items.begin(), items.end(), [](const Item& u, const Item& v) { return u.now.lo.x < v.now.lo.x; });
            for (std::size_t x = 0; x < items.size(); ++x) {
                const Item& ia = items[x];
                for (std::size_t y = x + 1; y < items.size() && items[y].now.lo.x <= ia.now.hi.x; ++y) {
                    const Item& ib = items[y];
                    // Each pair once: in the cell holding the low corner of the boxes' overlap
                    // (the boxes the index holds, of both poses), whose cell is the larger of the
                    // two boxes' low cells on each axis. Both boxes reach this cell, so on each
                    // axis that is this cell's when it is the first of either box there.
                    if ((ia.first | ib.first) != 7u) continue;
                    if (ia.now.lo.y > ib.now.hi.y || ib.now.lo.y > ia.now.hi.y || ia.now.lo.z > ib.now.hi.z ||
                        ib.now.lo.z > ia.now.hi.z)
                        continue;
                    int shared = 0;
                    int common = 0; // the shared vertex's corner in ia
                    for (int c = 0; c < 3; ++c) {
                        const std::uint32_t u = ia.tri[std::size_t(c)];
                        const int k = (u == ib.tri[0]) + (u == ib.tri[1]) + (u == ib.tri[2]);
                        shared += k;
                        if (k) common = c;
                    }
                    if (shared >= 2) continue;                            // neighbours across an edge never cross
                    if (shared == 1 && (ia.fan >> common & 1u)) continue; // two sectors of an embedded fan
                    if (triangles_cross(p, ia.tri, ib.tri))
                        local.push_back({std::min(ia.face, ib.face), std::max(ia.face, ib.face)});
                }
            }
        }
    });
    std::vector<FacePair> pairs;
    for (auto& v : found) pairs.insert(pairs.end(), v.begin(), v.end());
    std::sort(pairs.begin(), pairs.end());
    return pairs;
}

void SelfIntersectionIndex::faces_near(const Vec3f& point, std::vector<std::uint32_t>& out) const {
    out.clear();
    if (entries_.empty()) return;
    const Range c = cells({point, point});
    const std::uint64_t cell = key(c.lo[0], c.lo[1], c.lo[2]);
    for (auto it = std::lower_bound(entries_.begin(), entries_.end(), cell << 32);
         it != entries_.end() && (*it >> 32) == cell; ++it)
        out.push_back(face_of(*it));
}

void SelfIntersectionIndex::candidates(const Box& b, std::vector<std::uint32_t>& out) const {
    out.clear();
    if (entries_.empty()) return;
    const Range c = cells(b);
    for (auto x = c.lo[0]; x <= c.hi[0]; ++x)
        for (auto y = c.lo[1]; y <= c.hi[1]; ++y)
            for (auto z = c.lo[2]; z <= c.hi[2]; ++z) {
                const std::uint64_t cell = key(x, y, z);
                for (auto it = std::lower_bound(entries_.begin(), entries_.end(), cell << 32);
                     it != entries_.end() && (*it >> 32) == cell; ++it)
                    out.push_back(face_of(*it));
            }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
}

std::vector<FacePair> SelfIntersectionIndex::involving(const std::vector<std::uint32_t>& faces,
                                                       const std::vector<Vec3f>& p) const {
    tbb::enumerable_thread_specific<std::vector<FacePair>> found;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, faces.size(), 64),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          auto& local = found.local();
                          std::vector<std::uint32_t> near;
                          for (std::size_t i = r.begin(); i != r.end(); ++i) {
                              const std::uint32_t fa = faces[i];
                              candidates(box(fa), near);
                              const Box ba = face_box(p, triangles_[fa]);
                              for (std::uint32_t fb : near)
                                  if (fb != fa && overlap(ba, face_box(p, triangles_[fb])) &&
                                      triangles_cross(p, triangles_[fa], triangles_[fb]))
                                      local.push_back({std::min(fa, fb), std::max(fa, fb)});
                          }
                      });
    std::vector<FacePair> pairs;
    for (auto& v : found) pairs.insert(pairs.end(), v.begin(), v.end());
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    return pairs;
}

std::vector<char> embedded_fans(const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                const std::vector<Vec3f>& p) {
    const std::size_t nv = p.size(), nf = triangles.size();
    std::vector<char> embedded(nv, 0);
    // Sums per vertex over its faces, with no lists of faces: each task owns a range of the
    // vertices and goes through every face, adding what the faces' corners in its range give
    // (no two tasks write one vertex). Any axis would do for the test below as long as every
    // face is judged against the same one; the sum of the face normals is the natural one,
    // and float is enough for it.
    std::vector<Vec3f> axis(nv, Vec3f(0, 0, 0));
    std::vector<std::uint64_t> balance(nv, 0); // each neighbour as often before v as after it: closed cycles
    std::vector<float> turn(nv, 0.0f);
    std::vector<std::uint8_t> count(nv, 0); // faces, up to 255
    const std::size_t tasks =
        nf < (std::size_t(1) << 16) ? 1 : std::size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
    const std::size_t per = (nv + tasks - 1) / tasks;
    auto mix = [](std::uint64_t y) { return (y + 1) * 0x9E3779B97F4A7C15ull ^ (y >> 7) * 0xC2B2AE3D27D4EB4Full; };
    std::atomic<bool> bad_index{false}; // a face names a vertex that does not exist
    // face(t, corners, P, n): the face's corners in the task's range (bit c: corner c), its
    // corners' positions and its normal (the cross product of its sides from any corner).
    auto over_faces = [&](auto&& face) {
        tbb::parallel_for(std::size_t(0), tasks, [&](std::size_t k) {
            const std::uint32_t lo = std::uint32_t(k * per), hi = std::uint32_t(std::min(nv, (k + 1) * per));
            for (std::size_t f = 0; f < nf; ++f) {
                const auto& t = triangles[f];
                if (t[0] >= nv || t[1] >= nv || t[2] >= nv) {
                    bad_index.store(true, std::memory_order_relaxed);
                    continue;
                }
                const unsigned mine = unsigned(t[0] >= lo && t[0] < hi) | unsigned(t[1] >= lo && t[1] < hi) << 1 |
                                      unsigned(t[2] >= lo && t[2] < hi) << 2;
                if (!mine) continue;
                const Vec3d P[3] = {Vec3d(p[t[0]]), Vec3d(p[t[1]]), Vec3d(p[t[2]])};
                face(t, mine, P, cross(P[1] - P[0], P[2] - P[0]));
            }
        });
    };
    over_faces([&](const std::array<std::uint32_t, 3>& t, unsigned mine, const Vec3d(&)[3], const Vec3d& n) {
        const bool degenerate = t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
        for (int c = 0; c < 3; ++c) {
            if (!((mine >> c) & 1u)) continue;
            const std::uint32_t v = t[std::size_t(c)];
            axis[v] += Vec3f(n);
            balance[v] += mix(t[std::size_t((c + 1) % 3)]) - mix(t[std::size_t((c + 2) % 3)]);
            count[v] = degenerate ? 255 : std::uint8_t(std::min(255, count[v] + 1));
        }
    });
    if (bad_index) return embedded; // a fan could miss a face: none is vouched for
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 1 << 14), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            const Vec3d n(axis[v]);
            const double len = length(n);
            if (count[v] < 3 || count[v] > 64 || balance[v] != 0 || !(len > 0) || !std::isfinite(len)) {
                turn[v] = HUGE_VALF; // not vouched for
                continue;
            }
            axis[v] = Vec3f(n * (1.0 / len));
        }
    });
    // Each face's angle at v seen along the axis is theta, with sin and cos from the projected
    // sides; (pi/2)(1 - cos) + sin bounds it from above on [0, pi] (no arc function per face).
    // One cycle winding once adds up to 2 pi; any more, to 4 pi.
    constexpr double kHalfPi = 1.57079632679489661923;
    over_faces([&](const std::array<std::uint32_t, 3>& t, unsigned mine, const Vec3d(&P)[3], const Vec3d& n) {
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t v = t[std::size_t(c)];
            if (!((mine >> c) & 1u) || turn[v] == HUGE_VALF) continue;
            const Vec3d ax(axis[v]);
            const Vec3d u = P[(c + 1) % 3] - P[c], w = P[(c + 2) % 3] - P[c];
            const double sine = dot(n, ax); // the projected sides' cross product
            // Turning the fan's way, by a margin.
            if (!(sine > 0 && sine * sine > 1e-18 * dot(n, n))) {
                turn[v] = HUGE_VALF;
                continue;
            }
            const double cosine = dot(u, w) - dot(u, ax) * dot(w, ax); // of the projected sides
            const double r = std::sqrt(sine * sine + cosine * cosine);
            turn[v] += float(kHalfPi * (1 - cosine / r) + sine / r);
        }
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 1 << 14), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v) embedded[v] = turn[v] < float(8 * kHalfPi - 1e-2);
    });
    return embedded;
}

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

std::vector<FacePair> find_self_intersections(const Mesh& m, const std::function<void(double)>& progress) {
    if (m.triangles.empty()) return {};
    const Fingerprint f = fingerprint_of(m);
    std::vector<FacePair> pairs;
    if (crossing_memo().find(f, pairs)) {
        if (progress) progress(1.0);
        return pairs;
    }
    const std::vector<char> fans = embedded_fans(m.triangles, m.positions);
    pairs = SelfIntersectionIndex(m.triangles, m.positions).all(m.positions, progress, &fans);
    crossing_memo().keep(f, pairs);
    return pairs;
}

std::size_t count_self_intersections(const Mesh& m) { return find_self_intersections(m).size(); }

} // namespace cm
