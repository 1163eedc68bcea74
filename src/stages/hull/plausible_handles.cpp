// The handle cut of plausible_handles.h: the grid distance to the outside, the growth, the
// coarse grid's cuts (the bit grid: plausible_handle_bits.h).
#include "plausible_handles.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <numeric>

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "plausible_genus.h"
#include "plausible_handle_bits.h"

namespace cm::plausible {

namespace {

using namespace handles;

// The grown pieces about a voxel (the lowest bit of each) and whether the outside about it is
// one piece (removal_keeps_outside()), by its neighbourhood, remembered: a growing front meets
// the same few neighbourhoods again and again.
class Neighbourhoods {
public:
    unsigned pieces(unsigned nb, bool& keeps) {
        std::uint64_t& s = slot_[std::size_t((std::uint64_t(nb) * 0x9E3779B97F4A7C15ull) >> 48)];
        if (s >> 32 != nb) {
            std::array<unsigned, 26> piece;
            unsigned reps = 0;
            for (int k = 0, n = kept_pieces(nb, piece); k < n; ++k)
                reps |= piece[std::size_t(k)] & -piece[std::size_t(k)];
            s = std::uint64_t(nb) << 32 | std::uint64_t(removal_keeps_outside(nb)) << 31 | reps;
        }
        keeps = (s >> 31 & 1) != 0;
        return unsigned(s & 0x7FFFFFFu);
    }

private:
    std::vector<std::uint64_t> slot_ = std::vector<std::uint64_t>(std::size_t(1) << 16, ~std::uint64_t(0));
};

// The growth of plausible_handles.h over the kept voxels `kept`.
class Growth {
public:
    Growth(const Bits& kept, const std::vector<RayRaster>& rays, int most, const Bits* seed = nullptr)
        : kept_(kept), grown_(kept), rays_(rays), queued_(kept), touched_(kept), most_(most), core_(kept) {
        std::fill(core_.w.begin(), core_.w.end(), 0);
        // The rank of a kept voxel: the kept voxels before its word, and before it in the word.
        first_.resize(kept.w.size() + 1);
        std::uint32_t n = 0;
        for (std::size_t k = 0; k < kept.w.size(); ++k)
            first_[k] = n, n += std::uint32_t(__builtin_popcountll(kept.w[k]));
        first_.back() = n;
        n_ = n;
        for (int d = 0; d < 27; ++d) {
            const long dx = d % 3 - 1, dy = d / 3 % 3 - 1, dz = d / 9 - 1;
            step_[std::size_t(d)] = (dx * long(kept.ny) + dy) * long(kept.nz) + dz;
            if (d < 9) row_step_[std::size_t(d)] = step_[std::size_t(d)] + 1;
        }
        depths(seed);
    }

    /// Grows the kept voxels, the `forced` ones first; returns the voxels of lines of sight
    /// the cut empties, one per such line.
    std::vector<std::uint32_t> grow(const std::vector<std::uint32_t>& forced) {
        grow_from(forced);
        if (kept_.w == grown_.w) return {};
        if (on_ray_.empty()) lines_of_sight();
        return bare();
    }

    /// The kept voxels on each line of sight of each view, counted.
    void lines_of_sight() {
        on_ray_.resize(rays_.size());
        for (std::size_t v = 0; v < rays_.size(); ++v) {
            on_ray_[v].assign(std::size_t(rays_[v].w) * std::size_t(rays_[v].h), 0);
            std::uint32_t* count = on_ray_[v].data();
            const RayRaster& ray = rays_[v];
            const auto& m = ray.m;
            // A view along x or y: a line of sight's cell depends on the other two: the voxels
            // are tallied per z along a row of the grid and the tallies added to their cells.
            const bool along_x = ray.ortho && m[0] == 0 && m[4] == 0, along_y = ray.ortho && m[1] == 0 && m[5] == 0;
            if ((along_x || along_y) && !(m[2] == 0 && m[6] == 0)) {
                tbb::parallel_for(std::size_t(0), along_x ? kept_.ny : kept_.nx, [&](std::size_t a) {
                    std::vector<std::uint32_t> tally(kept_.nz, 0);
                    for (std::size_t b = 0, nb = along_x ? kept_.nx : kept_.ny; b < nb; ++b) {
                        const std::uint64_t* r = along_x ? kept_.row(b, a) : kept_.row(a, b);
                        for (std::size_t k = 0; k < kept_.rw; ++k)
                            for (std::uint64_t c = r[k]; c; c &= c - 1)
                                ++tally[k * 64 + std::size_t(__builtin_ctzll(c))];
                    }
                    const Coord o = along_x ? kept_.lo.offsetBy(0, int(a), 0) : kept_.lo.offsetBy(int(a), 0, 0);
                    const double px0 = m[0] * o.x() + m[1] * o.y() + m[3], py0 = m[4] * o.x() + m[5] * o.y() + m[7];
                    for (std::size_t k = 0; k < kept_.nz; ++k) {
                        if (!tally[k]) continue;
                        const int z = o.z() + int(k);
                        __atomic_fetch_add(count + ray.cell_at(px0 + m[2] * z, py0 + m[6] * z), tally[k],
                                           __ATOMIC_RELAXED);
                    }
                });
                continue;
            }
            tbb::parallel_for(std::size_t(0), kept_.nx, [&](std::size_t x) {
                for (std::size_t y = 0; y < kept_.ny; ++y) {
                    const std::uint64_t* r = kept_.row(x, y);
                    const Coord o = kept_.lo.offsetBy(int(x), int(y), 0);
                    if (ray.ortho && m[2] == 0 && m[6] == 0) {
                        // A view along the rows: a row is one line of sight.
                        std::uint32_t n = 0;
                        for (std::size_t k = 0; k < kept_.rw; ++k) n += std::uint32_t(__builtin_popcountll(r[k]));
                        if (n) __atomic_fetch_add(count + ray.cell(o), n, __ATOMIC_RELAXED);
                        continue;
                    }
                    // Along a row the raster point moves by a constant step (orthographic).
                    const double px0 = m[0] * o.x() + m[1] * o.y() + m[3], py0 = m[4] * o.x() + m[5] * o.y() + m[7];
                    for (std::size_t k = 0; k < kept_.rw; ++k)
                        for (std::uint64_t c = r[k]; c; c &= c - 1) {
                            const int z = o.z() + int(k * 64) + __builtin_ctzll(c);
                            const std::uint32_t cell = ray.ortho ? ray.cell_at(px0 + m[2] * z, py0 + m[6] * z)
                                                                 : ray.cell(Coord(o.x(), o.y(), z));
                            __atomic_fetch_add(count + cell, 1u, __ATOMIC_RELAXED);
                        }
                }
            });
        }
    }

    /// The growth itself.
    void grow_from(const std::vector<std::uint32_t>& forced) {
        grown_.w = core_.w;
        touched_.w = core_.w;
        std::fill(queued_.w.begin(), queued_.w.end(), 0);
        roots_.up.resize(n_);
        std::iota(roots_.up.begin(), roots_.up.end(), 0u);
        for (auto& q : queue_) q.clear();
        head_.assign(queue_.size(), 0);
        top_ = 0;
        if (has_core_) grow_core();
        else add(by_depth_.front());
        for (const std::uint32_t f : forced) {
            if (grown_.test(f)) continue;
            add(f);
            for (int d = 0; d < 27; ++d)
                if (d != 13 && grown_.test(f + std::size_t(step_[std::size_t(d)])))
                    roots_.join(rank(f), rank(f + std::size_t(step_[std::size_t(d)])));
        }
        std::size_t next_seed = 0;
        for (;;) {
            while (top_ > 0 && head_[top_] == queue_[top_].size()) queue_[top_].clear(), head_[top_] = 0, --top_;
            if (top_ == 0) {
                // A piece not reached yet: its deepest voxel.
                while (next_seed < by_depth_.size() && touched_.test(by_depth_[next_seed])) ++next_seed;
                if (next_seed == by_depth_.size()) break;
                add(by_depth_[next_seed]);
                continue;
            }
            const std::uint32_t p = queue_[top_][head_[top_]++];
            if (grown_.test(p)) continue;
            queued_.reset(p);
            const std::uint32_t rp = rank(p);
            const unsigned nb = around(p);
            // Enclosed by face neighbours: growing it fills a pocket and joins what is about it.
            const bool pocket = (nb & kFaces) == kFaces;
            // The outside about it in pieces: growing it closes a tunnel of the grown voxels
            // (the last voxel of a hole through a plate: kept, so no hole of the drawings) or
            // seals a pocket of them, which only gives back what is kept. Where it also joins
            // pieces about it, it waits for a neighbour.
            bool keeps = false;
            const unsigned reps = shapes_.pieces(nb, keeps);
            const bool split = !pocket && !keeps;
            const int np = __builtin_popcount(reps);
            if (split && np != 1) continue;
            std::array<std::uint32_t, 26> root;
            // Grown from one voxel, every grown voxel is one piece: two pieces about a voxel
            // are one ring. Grown from the core's pieces and forced voxels, pieces apart meet.
            const bool one = forced.empty() && !has_core_;
            bool apart = np == 1 || !one;
            if (one) {
                if (apart || pocket) add(p);
                continue;
            }
            unsigned r = reps;
            for (int k = 0; k < np; ++k, r &= r - 1) {
                const int bit = __builtin_ctz(r);
                root[std::size_t(k)] = roots_.find(rank(p + std::size_t(step_[std::size_t(bit)])));
                for (int j = 0; j < k; ++j) apart = apart && root[std::size_t(j)] != root[std::size_t(k)];
            }
            if (!apart && !pocket) continue; // closes a ring: waits
            add(p);
            for (int k = 0; k < np; ++k) roots_.join(rp, root[std::size_t(k)]);
        }
    }

    /// The voxels of lines of sight the cut empties, one per line.
    std::vector<std::uint32_t> bare() {
        // The cut voxels and their cells, and the cut voxels on each line.
        std::vector<std::uint32_t> cut;
        for (std::size_t k = 0; k < kept_.w.size(); ++k)
            for (std::uint64_t c = kept_.w[k] & ~grown_.w[k]; c; c &= c - 1)
                cut.push_back(std::uint32_t(k * 64 + std::size_t(__builtin_ctzll(c))));
        const std::size_t nv = rays_.size();
        std::vector<std::uint32_t> cells(cut.size() * nv);
        std::vector<std::vector<std::uint32_t>> taken(nv);
        for (std::size_t v = 0; v < nv; ++v) {
            taken[v].assign(on_ray_[v].size(), 0);
            for (std::size_t j = 0; j < cut.size(); ++j)
                ++taken[v][cells[j * nv + v] = rays_[v].cell(kept_.coord(cut[j]))];
        }
        std::vector<std::uint32_t> bare;
        for (std::size_t j = 0; j < cut.size(); ++j) {
            bool needed = false;
            for (std::size_t v = 0; v < nv; ++v) {
                std::uint32_t& t = taken[v][cells[j * nv + v]];
                // Every kept voxel of the line is cut: this one is grown first next time.
                if (t == on_ray_[v][cells[j * nv + v]]) needed = true, t = 0;
            }
            if (needed) bare.push_back(cut[j]);
        }
        return bare;
    }

    /// The cut voxels of the lines of sight `bare` lies on, grown back.
    void give_back(const std::vector<std::uint32_t>& bare) {
        for (std::size_t v = 0; v < rays_.size(); ++v) {
            std::vector<char> empty(on_ray_[v].size(), 0);
            for (const std::uint32_t b : bare) empty[rays_[v].cell(kept_.coord(b))] = 1;
            for (std::size_t k = 0; k < kept_.w.size(); ++k)
                for (std::uint64_t c = kept_.w[k] & ~grown_.w[k]; c; c &= c - 1) {
                    const std::size_t i = k * 64 + std::size_t(__builtin_ctzll(c));
                    if (empty[rays_[v].cell(kept_.coord(i))]) grown_.set(i);
                }
        }
    }

    /// The grown voxels a cut left joined to the rest of their part by an edge or a corner
    /// alone: every face-connected piece of the grown voxels but the largest of each
    /// face-connected piece of the kept ones. Marching Cubes gives them a surface of their own.
    std::vector<std::uint32_t> stranded() const {
        const Runs kr(kept_), gr(grown_);
        const std::vector<std::uint32_t> kp = kr.pieces(kept_, true), gp = gr.pieces(grown_, true);
        std::vector<std::size_t> size(gr.runs.size(), 0);
        std::vector<std::uint32_t> part(gr.runs.size(), 0); // a grown piece's kept piece
        for (std::size_t r = 0; r + 1 < gr.start.size(); ++r) {
            std::size_t j = kr.start[r];
            for (std::size_t i = gr.start[r]; i < gr.start[r + 1]; ++i) {
                while (kr.runs[j].e < gr.runs[i].a) ++j; // a grown run lies in a kept one
                size[gp[i]] += gr.runs[i].e - gr.runs[i].a + 1;
                part[gp[i]] = kp[j];
            }
        }
        std::vector<std::uint32_t> largest(kr.runs.size(), std::uint32_t(-1));
        for (std::uint32_t g = 0; g < gr.runs.size(); ++g)
            if (gp[g] == g) {
                std::uint32_t& l = largest[part[g]];
                if (l == std::uint32_t(-1) || size[g] > size[l]) l = g;
            }
        std::vector<std::uint32_t> out;
        for (std::size_t r = 0; r + 1 < gr.start.size(); ++r)
            for (std::size_t i = gr.start[r]; i < gr.start[r + 1]; ++i)
                if (largest[part[gp[i]]] != gp[i])
                    for (std::uint32_t z = gr.runs[i].a; z <= gr.runs[i].e; ++z)
                        out.push_back(std::uint32_t(r * grown_.nz + z));
        return out;
    }
    /// `voxels` taken out (cut too), or put back.
    void take_out(const std::vector<std::uint32_t>& voxels) {
        for (const std::uint32_t i : voxels) grown_.reset(i);
    }
    void put_back(const std::vector<std::uint32_t>& voxels) {
        for (const std::uint32_t i : voxels) grown_.set(i);
    }
    /// The cut voxels about `voxels` grown back.
    void rejoin(const std::vector<std::uint32_t>& voxels) {
        for (const std::uint32_t i : voxels)
            for (int d = 0; d < 27; ++d) {
                const std::size_t q = i + std::size_t(step_[std::size_t(d)]);
                if (kept_.test(q)) grown_.set(q);
            }
    }

    const Bits& grown() const { return grown_; }

private:
    // The six face neighbours of the centre of a neighbourhood.
    static constexpr unsigned kFaces = 1u << 4 | 1u << 10 | 1u << 12 | 1u << 14 | 1u << 16 | 1u << 22;

    std::uint32_t rank(std::size_t i) const {
        const std::uint64_t below = kept_.w[i >> 6] & ((std::uint64_t(1) << (i & 63)) - 1);
        return first_[i >> 6] + std::uint32_t(__builtin_popcountll(below));
    }
    // The three bits z - 1, z, z + 1 of `b` about bit j (a row's first and last bits are
    // empty, so they never leave the row).
    static unsigned three(const Bits& b, std::size_t j) {
        const std::size_t a = j - 1, sh = a & 63;
        std::uint64_t v = b.w[a >> 6] >> sh;
        if (sh > 61) v |= b.w[(a >> 6) + 1] << (64 - sh);
        return unsigned(v & 7);
    }
    // The neighbourhood of bit i in `b` (bit x + 3 y + 9 z), from its nine rows.
    unsigned nine_rows(const Bits& b, std::size_t i) const {
        unsigned nb = 0;
        for (int r = 0; r < 9; ++r) {
            const unsigned t = three(b, i + std::size_t(row_step_[std::size_t(r)]));
            nb |= (t & 1u) << r | (t >> 1 & 1u) << (r + 9) | (t >> 2 & 1u) << (r + 18);
        }
        return nb;
    }
    unsigned around(std::size_t i) const { return nine_rows(grown_, i) & ~(1u << 13); }
    void add(std::size_t i) {
        grown_.set(i);
        touched_.set(i);
        for (int r = 0; r < 9; ++r) {
            const std::size_t j = i + std::size_t(row_step_[std::size_t(r)]);
            for (unsigned t = three(kept_, j) & ~three(grown_, j) & ~three(queued_, j); t; t &= t - 1)
                enqueue(j + std::size_t(__builtin_ctz(t)) - 1);
        }
    }
    // A kept voxel into the queue of its depth.
    void enqueue(std::size_t q) {
        queued_.set(q);
        touched_.set(q);
        const std::uint8_t dq = depth_[rank(q)];
        queue_[dq].push_back(std::uint32_t(q));
        top_ = std::max<std::size_t>(top_, dq);
    }
    // The core (the voxels deeper than a cut may reach) grown at once, its pieces by runs, and
    // the voxels about it queued.
    void grow_core() {
        const Runs runs(core_);
        std::vector<std::uint32_t> first(runs.runs.size());
        for (std::size_t r = 0; r + 1 < runs.start.size(); ++r)
            for (std::size_t i = runs.start[r]; i < runs.start[r + 1]; ++i) {
                const std::uint32_t r0 = rank(r * core_.nz + runs.runs[i].a);
                first[i] = r0;
                for (std::uint32_t t = 1; t <= runs.runs[i].e - runs.runs[i].a; ++t) roots_.up[r0 + t] = r0;
            }
        runs.for_touching(core_, [&](std::size_t i, std::size_t j) { roots_.join(first[i], first[j]); });
        const std::size_t row = core_.rw, slab = core_.ny * core_.rw;
        const auto& c = core_.w;
        for (std::size_t k = slab + row + 1; k + slab + row + 1 < c.size(); ++k) {
            std::uint64_t near = 0;
            for (const std::size_t m : {k - slab - row, k - slab, k - slab + row, k - row, k, k + row, k + slab - row,
                                        k + slab, k + slab + row})
                near |= c[m] | c[m] << 1 | c[m - 1] >> 63 | c[m] >> 1 | c[m + 1] << 63;
            for (std::uint64_t b = near & kept_.w[k] & ~c[k]; b; b &= b - 1)
                enqueue(k * 64 + std::size_t(__builtin_ctzll(b)));
        }
    }

    // The grid distance to the outside (1 on the surface; face steps) of each kept voxel no
    // deeper than a cut may reach and not in `seed`, those voxels deepest first, and the core:
    // the voxels deeper, with `seed`'s.
    //
    // With a seed, only the box of the words holding the other kept voxels, `most_` + 1 cells
    // wider each way, is eroded: what the box's edge gets wrong (nothing outside it is eroded)
    // reaches `most_` cells in, where every kept voxel is the seed's (no depth taken, and in
    // the core either way).
    void depths(const Bits* seed) {
        depth_.assign(n_, 0);
        Bits left = kept_;
        std::vector<std::vector<std::uint32_t>> layers;
        std::vector<std::uint64_t> next = seed ? left.w : std::vector<std::uint64_t>(left.w.size(), 0);
        const std::size_t slab = kept_.ny * kept_.rw;
        std::size_t x0 = 1, x1 = kept_.nx - 2, y0 = 0, y1 = kept_.ny - 1, k0 = 0, k1 = kept_.rw - 1;
        if (seed) {
            x0 = kept_.nx, x1 = 0, y0 = kept_.ny, y1 = 0, k0 = kept_.rw, k1 = 0;
            for (std::size_t k = 0; k < kept_.w.size(); ++k)
                if (kept_.w[k] & ~seed->w[k]) {
                    const std::size_t x = k / slab, y = k / kept_.rw % kept_.ny, kz = k % kept_.rw;
                    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
                    k0 = std::min(k0, kz), k1 = std::max(k1, kz);
                }
            const std::size_t m = std::size_t(most_) + 1, mk = (m + 63) / 64;
            if (x0 <= x1) {
                x0 = std::max<std::size_t>(1, x0 > m ? x0 - m : 0), x1 = std::min(kept_.nx - 2, x1 + m);
                y0 = y0 > m ? y0 - m : 0, y1 = std::min(kept_.ny - 1, y1 + m);
                k0 = k0 > mk ? k0 - mk : 0, k1 = std::min(kept_.rw - 1, k1 + mk);
            }
        }
        const auto slab_words = [&](std::size_t x, auto&& body) { // the box's words of slab x, in order
            for (std::size_t y = y0; y <= y1; ++y)
                for (std::size_t k = (x * kept_.ny + y) * kept_.rw + k0, e = k + (k1 - k0); k <= e; ++k) body(k);
        };
        for (int d = 1; d <= most_ && x0 <= x1; ++d) {
            tbb::parallel_for(x0, x1 + 1, [&](std::size_t x) {
                slab_words(x, [&](std::size_t k) { next[k] = eroded_by_faces(left, k); });
            });
            std::vector<std::uint32_t> layer;
            for (std::size_t x = x0; x <= x1; ++x)
                slab_words(x, [&](std::size_t k) {
                    for (std::uint64_t c = left.w[k] & ~next[k] & (seed ? ~seed->w[k] : ~std::uint64_t(0)); c;
                         c &= c - 1) {
                        const std::size_t i = k * 64 + std::size_t(__builtin_ctzll(c));
                        depth_[rank(i)] = std::uint8_t(d);
                        layer.push_back(std::uint32_t(i));
                    }
                });
            layers.push_back(std::move(layer));
            left.w.swap(next);
        }
        core_.w.swap(left.w);
        if (seed)
            for (std::size_t k = 0; k < core_.w.size(); ++k) core_.w[k] |= seed->w[k];
        has_core_ = std::any_of(core_.w.begin(), core_.w.end(), [](std::uint64_t v) { return v != 0; });
        queue_.resize(std::size_t(most_) + 1);
        for (auto it = layers.rbegin(); it != layers.rend(); ++it)
            by_depth_.insert(by_depth_.end(), it->begin(), it->end());
    }

    const Bits& kept_;
    Bits grown_;
    const std::vector<RayRaster>& rays_;
    std::vector<std::uint32_t> first_;
    std::uint32_t n_ = 0;
    std::array<long, 27> step_{};
    std::array<long, 9> row_step_{}; // the rows about a voxel's: (x + 3 y) of the neighbourhood
    std::vector<std::uint8_t> depth_;
    // Voxels in the queue now, and ever reached (queued or grown).
    Bits queued_, touched_;
    const int most_;
    // The voxels deeper than `most_`: no cut reaches them, they are grown at once.
    Bits core_;
    bool has_core_ = false;
    std::vector<std::uint32_t> by_depth_;
    std::vector<std::vector<std::uint32_t>> queue_;
    std::vector<std::size_t> head_;
    std::size_t top_ = 0;
    Roots roots_;
    Neighbourhoods shapes_;
    std::vector<std::vector<std::uint32_t>> on_ray_; // per view, per cell: kept voxels
};

// The growths of a Growth: each after the first with the voxels whose lines of sight the cut
// before emptied grown first (up to four), what is still emptied then given back. Returns the
// growths run.
int grow_out(Growth& growth) {
    std::vector<std::uint32_t> forced, bare;
    int growths = 0;
    while (growths < 4) {
        bare = growth.grow(forced);
        ++growths;
        if (bare.empty()) break;
        forced.insert(forced.end(), bare.begin(), bare.end());
    }
    if (!bare.empty()) growth.give_back(bare);
    return growths;
}

// The kept voxels two by two by two: a coarse voxel is on when one of its eight is.
Bits coarse_of(const Bits& fine) {
    const auto half = [](int v) { return v >> 1; };
    const Coord f0 = fine.lo.offsetBy(1), f1 = fine.lo.offsetBy(int(fine.nx) - 2, int(fine.ny) - 2, int(fine.nz) - 2);
    Bits c(CoordBBox(Coord(half(f0.x()), half(f0.y()), half(f0.z())), Coord(half(f1.x()), half(f1.y()), half(f1.z()))));
    // fine.lo.z() is a multiple of 8: fine bit b of word k is at coarse z lo.z / 2 + 32 k + b / 2.
    const std::size_t z0 = std::size_t(fine.lo.z() / 2 - c.lo.z());
    for (std::size_t x = 0; x < fine.nx; ++x)
        for (std::size_t y = 0; y < fine.ny; ++y) {
            const std::uint64_t* r = fine.row(x, y);
            const std::size_t cx = std::size_t(half(fine.lo.x() + int(x)) - c.lo.x());
            const std::size_t cy = std::size_t(half(fine.lo.y() + int(y)) - c.lo.y());
            std::uint64_t* cr = c.w.data() + (cx * c.ny + cy) * c.rw;
            for (std::size_t k = 0; k < fine.rw; ++k) {
                if (!r[k]) continue;
                // The pairs of bits or'ed, their even bits packed into 32.
                std::uint64_t v = (r[k] | r[k] >> 1) & 0x5555555555555555ull;
                v = (v | v >> 1) & 0x3333333333333333ull;
                v = (v | v >> 2) & 0x0F0F0F0F0F0F0F0Full;
                v = (v | v >> 4) & 0x00FF00FF00FF00FFull;
                v = (v | v >> 8) & 0x0000FFFF0000FFFFull;
                v = (v | v >> 16) & 0x00000000FFFFFFFFull;
                const std::size_t at = z0 + 32 * k, word = at >> 6, bit = at & 63;
                cr[word] |= v << bit;
                if (bit > 32) cr[word + 1] |= v >> (64 - bit);
            }
        }
    return c;
}

// A view's raster for the coarse grid: a coarse voxel's cell is its eight's centre's.
RayRaster coarse_ray(RayRaster r) {
    for (std::size_t row = 0; row < 3; ++row) {
        double* m = r.m.data() + 4 * row;
        m[3] += 0.5 * (m[0] + m[1] + m[2]);
        m[0] *= 2, m[1] *= 2, m[2] *= 2;
    }
    return r;
}

// The kept voxels away from every cut the coarse grid finds: the voxels of its cut voxels'
// eight and all within `reach` face steps of them out. None (an empty grid) when the coarse
// grid has no cut.
Bits away_from_coarse_cuts(const Bits& kept, const std::vector<RayRaster>& rays, int most, int reach) {
    const Bits coarse = coarse_of(kept);
    if (topology_of(coarse).handles() <= 0) return {};
    std::vector<RayRaster> coarse_rays;
    for (const RayRaster& r : rays) coarse_rays.push_back(coarse_ray(r));
    Growth growth(coarse, coarse_rays, std::max(2, (most + 1) / 2));
    grow_out(growth);
    Bits near = kept;
    std::fill(near.w.begin(), near.w.end(), 0);
    bool any = false;
    const Coord f0 = kept.lo.offsetBy(1), f1 = kept.lo.offsetBy(int(kept.nx) - 2, int(kept.ny) - 2, int(kept.nz) - 2);
    for (std::size_t k = 0; k < coarse.w.size(); ++k)
        for (std::uint64_t c = coarse.w[k] & ~growth.grown().w[k]; c; c &= c - 1) {
            const Coord q = coarse.coord(k * 64 + std::size_t(__builtin_ctzll(c)));
            for (int d = 0; d < 8; ++d) {
                const Coord f(2 * q.x() + (d & 1), 2 * q.y() + (d >> 1 & 1), 2 * q.z() + (d >> 2));
                if (f.x() < f0.x() || f.y() < f0.y() || f.z() < f0.z() || f.x() > f1.x() || f.y() > f1.y() ||
                    f.z() > f1.z())
                    continue;
                near.set(near.index(f));
                any = true;
            }
        }
    if (!any) return {};
    std::vector<std::uint64_t> next(near.w.size(), 0);
    for (int s = 0; s < reach; ++s) {
        dilate_by_faces(near, kept, next);
        near.w.swap(next);
    }
    Bits away = kept;
    for (std::size_t k = 0; k < away.w.size(); ++k) away.w[k] &= ~near.w[k];
    return away;
}

} // namespace

HandleCut cut_handles(openvdb::tree::LeafManager<openvdb::BoolTree>& leaves, const std::vector<RayRaster>& rays,
                      int most, const std::function<void(const Coord&)>& taken, int coarse_above) {
    HandleCut out;
    const CoordBBox box = box_of(leaves);
    if (box.empty()) return out;
    const Bits kept = bits_of(leaves, box);
    const VoxelTopology before = topology_of(kept);
    out.handles = out.handles_left = before.handles();
    // A grid of more bits than 32-bit indices number is not grown (over 1600 cells a side).
    if (out.handles <= 0 || kept.size() >= (std::size_t(1) << 32)) return out;
    // On a large grid the voxels away from the coarse grid's cuts are grown at once.
    Bits away;
    const bool coarse = std::max({box.dim().x(), box.dim().y(), box.dim().z()}) > coarse_above;
    if (coarse) {
        away = away_from_coarse_cuts(kept, rays, most, most + 4);
        if (away.w.empty() || away.w == kept.w) return out;
    }
    Growth growth(kept, rays, most, coarse ? &away : nullptr);
    out.growths = grow_out(growth);
    if (growth.grown().w == kept.w) return out;
    // What the cut left joined by an edge or a corner alone goes with it where every line of
    // sight keeps a voxel without it; else the cut about it is grown back.
    for (int pass = 0; pass < 4; ++pass) {
        const std::vector<std::uint32_t> stranded = growth.stranded();
        if (stranded.empty()) break;
        growth.take_out(stranded);
        if (growth.bare().empty()) continue;
        growth.put_back(stranded);
        growth.rejoin(stranded);
    }
    const Bits& grown = growth.grown();
    const VoxelTopology after = topology_of(grown);
    // A growth that left a piece apart (a voxel grown first that nothing joined) cuts nothing.
    if (after.pieces != before.pieces || after.handles() >= before.handles()) return out;
    out.handles_left = after.handles();
    std::vector<Coord> cut;
    for (std::size_t k = 0; k < kept.w.size(); ++k)
        for (std::uint64_t c = kept.w[k] & ~grown.w[k]; c; c &= c - 1)
            cut.push_back(kept.coord(k * 64 + std::size_t(__builtin_ctzll(c))));
    openvdb::tree::ValueAccessor<openvdb::BoolTree> acc(leaves.tree());
    for (const Coord& c : cut) {
        taken(c);
        acc.setValueOff(c, false);
    }
    out.voxels = cut.size();
    return out;
}

} // namespace cm::plausible
