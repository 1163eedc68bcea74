// The broad phase of mesh_intersect.h (SelfIntersectionIndex): a grid of the faces' boxes,
// and the crossing pairs it finds, at once or about a few faces.
#include "geometry/mesh_intersect.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
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

// The index built in named steps over the state they share. Nothing per face is stored but
// the (cell, face) keys: on machines where fresh pages are expensive, arrays of boxes cost more
// to allocate than the boxes cost to recompute. The entries are sorted without a second array
// of them: each chunk of faces counts its entries per bucket (a range of consecutive cell
// keys), the counts give every (bucket, chunk) its place, the chunks write their entries there
// side by side, and each bucket is sorted on its own, in the caches. The result is the fully
// sorted array.
class SelfIntersectionIndex::Builder {
public:
    explicit Builder(SelfIntersectionIndex& index)
        : ix_(index),
          nf_(index.triangles_.size()),
          chunk_(std::max<std::size_t>(std::size_t(1) << 16, (nf_ + 31) / 32)),
          chunks_((nf_ + chunk_ - 1) / chunk_) {}

    void run() {
        const Vec3d extent = size_cells();
        count_entries(extent);
        place_entries();
        write_entries();
        sort_buckets();
        find_runs();
    }

private:
    // The grid's origin and first cell size, from the box of all faces and their mean size.
    // Returns the grid's extent.
    Vec3d size_cells() {
        struct Sum {
            Box box;
            double diag = 0;
        };
        const Sum total = tbb::parallel_deterministic_reduce(
            tbb::blocked_range<std::size_t>(0, nf_, 8192), Sum{ix_.box(0), 0.0},
            [&](const tbb::blocked_range<std::size_t>& r, Sum s) {
                for (std::size_t f = r.begin(); f != r.end(); ++f) {
                    const Box x = ix_.box(std::uint32_t(f));
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
        ix_.origin_ = Vec3d(total.box.lo);
        const Vec3d extent = Vec3d(total.box.hi) - ix_.origin_;
        if (!std::isfinite(extent.x + extent.y + extent.z + ix_.origin_.x + ix_.origin_.y + ix_.origin_.z) ||
            !std::isfinite(total.diag))
            throw Error("the mesh has vertices with infinite or NaN coordinates");
        const double largest = std::max({extent.x, extent.y, extent.z, 1e-30});
        // Cells of about two mean face sizes; grown while large faces would fill too many
        // cells or the cells would not fit the 32 bits of a key.
        ix_.cell_ = std::max(2.0 * total.diag / double(nf_), largest * 1e-6);
        ix_.inv_cell_ = 1.0 / ix_.cell_;
        ix_.low_bits_ = nf_ <= kFaceMask;
        return extent;
    }

    // Calls emit(cell key, entry's low word) for each cell of the range r of face f.
    template <typename Emit>
    void for_cells(const Range& r, std::uint32_t f, Emit&& emit) const {
        for (auto i = r.lo[0]; i <= r.hi[0]; ++i)
            for (auto j = r.lo[1]; j <= r.hi[1]; ++j)
                for (auto k = r.lo[2]; k <= r.hi[2]; ++k) {
                    const std::uint64_t first =
                        ix_.low_bits_ ? std::uint64_t((i == r.lo[0]) | (j == r.lo[1]) << 1 | (k == r.lo[2]) << 2) : 0;
                    emit(ix_.key(i, j, k), (first << kFaceBits) | f);
                }
    }

    // The grid's dimensions and each chunk's entries per bucket, the cells doubled until the
    // keys fit 32 bits and the entries stay under their limit.
    void count_entries(const Vec3d& extent) {
        constexpr int kBucketBits = 16;
        for (;;) {
            for (int x = 0; x < 3; ++x)
                ix_.dims_[std::size_t(x)] = std::uint64_t(std::floor(extent[x] / ix_.cell_)) + 1;
            if (ix_.dims_[0] * ix_.dims_[1] * ix_.dims_[2] >= (std::uint64_t(1) << 32)) {
                ix_.cell_ *= 2;
                ix_.inv_cell_ = 1.0 / ix_.cell_;
                continue;
            }
            const std::uint64_t top_key = ix_.dims_[0] * ix_.dims_[1] * ix_.dims_[2] - 1;
            shift_ = std::max(0, int(std::bit_width(top_key)) - kBucketBits);
            buckets_ = std::size_t(top_key >> shift_) + 1;
            place_.assign(chunks_ * buckets_, 0);
            if (count_fits()) break;
            ix_.cell_ *= 2;
            ix_.inv_cell_ = 1.0 / ix_.cell_;
        }
    }

    // Each chunk's entries per bucket at the present cell size, or false when they are too
    // many. Each face's cells are counted from its range first (no face can make a chunk
    // enumerate past the limit): over the limit, the cells are too small for the faces.
    bool count_fits() {
        const std::uint64_t limit = 16 * std::uint64_t(nf_) + 1024;
        std::atomic<std::uint64_t> total{0};
        std::atomic<bool> over{false};
        tbb::parallel_for(std::size_t(0), chunks_, [&](std::size_t c) {
            std::uint64_t* count = place_.data() + c * buckets_;
            std::uint64_t mine = 0;
            for (std::size_t f = c * chunk_, e = std::min(nf_, f + chunk_); f < e; ++f) {
                const Range r = ix_.cells(ix_.box(std::uint32_t(f)));
                mine += (r.hi[0] - r.lo[0] + 1) * (r.hi[1] - r.lo[1] + 1) * (r.hi[2] - r.lo[2] + 1);
                if (mine > limit || over.load(std::memory_order_relaxed)) {
                    over = true;
                    return;
                }
                for_cells(r, std::uint32_t(f), [&](std::uint64_t cell, std::uint64_t) { ++count[cell >> shift_]; });
            }
            if (total.fetch_add(mine) + mine > limit) over = true;
        });
        return !over;
    }

    // The counts turned into where each (chunk, bucket) writes, and where each bucket starts.
    void place_entries() {
        bucket_start_.assign(buckets_ + 1, 0);
        std::uint64_t at = 0;
        for (std::size_t b = 0; b < buckets_; ++b) {
            bucket_start_[b] = at;
            for (std::size_t c = 0; c < chunks_; ++c) {
                const std::uint64_t n = place_[c * buckets_ + b];
                place_[c * buckets_ + b] = at;
                at += n;
            }
        }
        bucket_start_[buckets_] = at;
        ix_.entries_.resize(at);
    }

    void write_entries() {
        tbb::parallel_for(std::size_t(0), chunks_, [&](std::size_t c) {
            std::uint64_t* next = place_.data() + c * buckets_;
            for (std::size_t f = c * chunk_, e = std::min(nf_, f + chunk_); f < e; ++f)
                for_cells(ix_.cells(ix_.box(std::uint32_t(f))), std::uint32_t(f),
                          [&](std::uint64_t cell, std::uint64_t low) {
                              ix_.entries_[next[cell >> shift_]++] = (cell << 32) | low;
                          });
        });
        std::vector<std::uint64_t>().swap(place_);
    }

    void sort_buckets() {
        auto& entries = ix_.entries_;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, buckets_, 64),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t b = r.begin(); b != r.end(); ++b)
                                  std::sort(entries.begin() + std::ptrdiff_t(bucket_start_[b]),
                                            entries.begin() + std::ptrdiff_t(bucket_start_[b + 1]));
                          });
    }

    // The runs of one cell, found per bucket (a cell lies in one bucket) side by side.
    void find_runs() {
        const auto& entries = ix_.entries_;
        auto& runs = ix_.runs_;
        std::vector<std::size_t> runs_before(buckets_ + 1, 0);
        auto starts_run = [&](std::size_t i) { return i == 0 || (entries[i] >> 32) != (entries[i - 1] >> 32); };
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, buckets_, 64),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t b = r.begin(); b != r.end(); ++b)
                                  for (std::size_t i = bucket_start_[b]; i < bucket_start_[b + 1]; ++i)
                                      runs_before[b + 1] += starts_run(i);
                          });
        for (std::size_t b = 0; b < buckets_; ++b) runs_before[b + 1] += runs_before[b];
        runs.resize(runs_before[buckets_] + 1);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, buckets_, 64),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t b = r.begin(); b != r.end(); ++b) {
                                  std::size_t at_run = runs_before[b];
                                  for (std::size_t i = bucket_start_[b]; i < bucket_start_[b + 1]; ++i)
                                      if (starts_run(i)) runs[at_run++] = i;
                              }
                          });
        runs.back() = entries.size();
    }

    SelfIntersectionIndex& ix_;
    const std::size_t nf_;
    const std::size_t chunk_, chunks_; ///< faces per chunk, and chunks
    int shift_ = 0;                    ///< a cell key's bucket is key >> shift_
    std::size_t buckets_ = 1;
    std::vector<std::uint64_t> place_;        ///< per (chunk, bucket): counts, then where each writes next
    std::vector<std::uint64_t> bucket_start_; ///< per bucket, then the entries' count
};

SelfIntersectionIndex::SelfIntersectionIndex(const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                             const std::vector<Vec3f>& a, const std::vector<Vec3f>* b)
    : triangles_(triangles), a_(a), b_(b) {
    if (!triangles.empty()) Builder(*this).run();
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

std::vector<FacePair> SelfIntersectionIndex::all(const std::vector<Vec3f>& p, Progress progress,
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
    return merged_pairs(found);
}

} // namespace cm
