// The handle cut of plausible_handles.h: a bit grid over the kept voxels' box, its Euler
// characteristic and pieces, the grid distance to the outside, and the growth.
#include "plausible_handles.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <numeric>

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "plausible_genus.h"

namespace cm::plausible {

namespace {

using openvdb::Coord;
using openvdb::CoordBBox;
using LeafT = openvdb::BoolTree::LeafNodeType;

// The voxels of a box as bits, z fastest: a row (x, y) is nz / 64 words. The box has an
// empty layer on every side (rows x = 0 and y = 0 and their last ones, and the first and last
// bits of every row), so a shift or a neighbour never leaves it, and z starts on a leaf's
// boundary, so a leaf's row of 8 voxels is one byte.
struct Bits {
    Coord lo;
    std::size_t nx = 0, ny = 0, nz = 0, rw = 0; // rw: words per row
    std::vector<std::uint64_t> w;

    explicit Bits(const CoordBBox& box) {
        const int z0 = (box.min().z() & ~7) - 8;
        lo = Coord(box.min().x() - 1, box.min().y() - 1, z0);
        nx = std::size_t(box.max().x() - lo.x() + 2);
        ny = std::size_t(box.max().y() - lo.y() + 2);
        nz = (std::size_t(box.max().z() - z0 + 2) + 63) / 64 * 64;
        rw = nz / 64;
        w.assign(nx * ny * rw, 0);
    }
    std::size_t size() const { return nx * ny * nz; }
    std::size_t index(const Coord& c) const {
        return (std::size_t(c.x() - lo.x()) * ny + std::size_t(c.y() - lo.y())) * nz + std::size_t(c.z() - lo.z());
    }
    Coord coord(std::size_t i) const {
        const std::size_t z = i % nz, xy = i / nz;
        return Coord(lo.x() + int(xy / ny), lo.y() + int(xy % ny), lo.z() + int(z));
    }
    bool test(std::size_t i) const { return (w[i >> 6] >> (i & 63) & 1) != 0; }
    void set(std::size_t i) { w[i >> 6] |= std::uint64_t(1) << (i & 63); }
    void reset(std::size_t i) { w[i >> 6] &= ~(std::uint64_t(1) << (i & 63)); }
    const std::uint64_t* row(std::size_t x, std::size_t y) const { return w.data() + (x * ny + y) * rw; }
    template <typename Body>
    void for_each(Body&& body) const {
        for (std::size_t k = 0; k < w.size(); ++k)
            for (std::uint64_t v = w[k]; v; v &= v - 1) body(k * 64 + std::size_t(__builtin_ctzll(v)));
    }
};

Bits bits_of(const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves, const CoordBBox& box) {
    Bits b(box);
    auto* bytes = reinterpret_cast<std::uint8_t*>(b.w.data());
    tbb::parallel_for(std::size_t(0), leaves.leafCount(), [&](std::size_t l) {
        const LeafT& leaf = leaves.leaf(l);
        const Coord o = leaf.origin();
        for (int x = 0; x < 8; ++x) {
            const std::uint64_t word = leaf.getValueMask().getWord<std::uint64_t>(openvdb::Index(x));
            if (!word) continue;
            for (int y = 0; y < 8; ++y) {
                const auto byte = std::uint8_t(word >> (8 * y));
                if (byte) bytes[b.index(o.offsetBy(x, y, 0)) >> 3] = byte;
            }
        }
    });
    return b;
}

// The bits of a row dilated by one towards +z (the top bit of the row's previous word carried).
struct ZDilate {
    std::uint64_t carry = 0;
    std::uint64_t operator()(std::uint64_t v) {
        const std::uint64_t d = v | v << 1 | carry;
        carry = v >> 63;
        return d;
    }
};

// V - E + F - C of the union of the closed voxel cubes: a lattice cell is there when one of
// the voxels about it is, so each kind of cell is the voxels dilated towards + along the axes
// the cell spans no length of, counted row by row.
long euler_of(const Bits& b) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(1, b.nx), 0L,
        [&](const tbb::blocked_range<std::size_t>& r, long sum) {
            for (std::size_t x = r.begin(); x != r.end(); ++x)
                for (std::size_t y = 1; y < b.ny; ++y) {
                    const std::uint64_t *r00 = b.row(x, y), *r01 = b.row(x, y - 1), *r10 = b.row(x - 1, y),
                                        *r11 = b.row(x - 1, y - 1);
                    ZDilate z, zy, zx, zxy;
                    for (std::size_t k = 0; k < b.rw; ++k) {
                        const std::uint64_t c = r00[k], y1 = c | r01[k], x1 = c | r10[k], xy = y1 | x1 | r11[k];
                        if (!xy && !z.carry && !zy.carry && !zx.carry && !zxy.carry) continue;
                        sum += __builtin_popcountll(zxy(xy)) - __builtin_popcountll(zy(y1)) -
                               __builtin_popcountll(zx(x1)) - __builtin_popcountll(xy) + __builtin_popcountll(x1) +
                               __builtin_popcountll(y1) + __builtin_popcountll(z(c)) - __builtin_popcountll(c);
                    }
                }
            return sum;
        },
        std::plus<long>());
}

// Union-find with path halving.
struct Roots {
    std::vector<std::uint32_t> up;
    std::uint32_t find(std::uint32_t a) {
        while (up[a] != a) a = up[a] = up[up[a]];
        return a;
    }
    bool join(std::uint32_t a, std::uint32_t b) {
        a = find(a), b = find(b);
        if (a == b) return false;
        up[std::max(a, b)] = std::min(a, b);
        return true;
    }
};

// The runs of on bits of every row (offsets along z within the row), the rows in order.
struct Runs {
    struct Run {
        std::uint32_t a, e; // [a, e]
    };
    std::vector<Run> runs;
    std::vector<std::size_t> start; // the first run of each row (x * ny + y), and the end

    explicit Runs(const Bits& b) : start(b.nx * b.ny + 1, 0) {
        for (std::size_t x = 0; x < b.nx; ++x)
            for (std::size_t y = 0; y < b.ny; ++y) {
                start[x * b.ny + y] = runs.size();
                const std::uint64_t* r = b.row(x, y);
                bool in = false;
                std::uint32_t a = 0;
                for (std::size_t k = 0; k < b.rw; ++k) {
                    const std::uint64_t v = r[k];
                    if ((!in && !v) || (in && v == ~std::uint64_t(0))) continue;
                    int bit = 0;
                    while (bit < 64) {
                        const std::uint64_t t = (in ? ~v : v) >> bit;
                        if (!t) break;
                        bit += __builtin_ctzll(t);
                        const auto at = std::uint32_t(k * 64 + std::size_t(bit));
                        if (!in) a = at;
                        else runs.push_back({a, at - 1});
                        in = !in;
                    }
                }
            }
        start.back() = runs.size();
    }
    /// touched(i, j) for every two runs of neighbouring rows that touch (a run touches another
    /// reaching within one of it: 26-connected), each pair once.
    template <typename Touched>
    void for_touching(const Bits& b, Touched&& touched) const {
        const auto touch = [&](std::size_t r1, std::size_t r2) {
            std::size_t i = start[r1], j = start[r2];
            const std::size_t ie = start[r1 + 1], je = start[r2 + 1];
            while (i < ie && j < je) {
                const Run &p = runs[i], &q = runs[j];
                if (p.a <= q.e + 1 && q.a <= p.e + 1) touched(i, j);
                if (p.e < q.e) ++i;
                else ++j;
            }
        };
        for (std::size_t x = 1; x + 1 < b.nx; ++x)
            for (std::size_t y = 1; y + 1 < b.ny; ++y) {
                const std::size_t r = x * b.ny + y;
                if (start[r] == start[r + 1]) continue;
                touch(r, r - 1);
                touch(r, r - b.ny - 1);
                touch(r, r - b.ny);
                touch(r, r - b.ny + 1);
            }
    }
};

// The 26-connected pieces: the runs of every row joined to the runs they touch.
long pieces_of(const Bits& b) {
    const Runs runs(b);
    Roots roots;
    roots.up.resize(runs.runs.size());
    std::iota(roots.up.begin(), roots.up.end(), 0u);
    long pieces = long(runs.runs.size());
    runs.for_touching(b, [&](std::size_t i, std::size_t j) {
        if (roots.join(std::uint32_t(i), std::uint32_t(j))) --pieces;
    });
    return pieces;
}

VoxelTopology topology_of(const Bits& b) { return {euler_of(b), pieces_of(b)}; }

// The growth of plausible_handles.h over the kept voxels `kept`.
class Growth {
public:
    Growth(const Bits& kept, const std::vector<RayRaster>& rays, int most)
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
        }
        depths();
    }

    /// Grows the kept voxels, the `forced` ones first; returns the voxels of lines of sight
    /// the cut empties, one per such line.
    std::vector<std::uint32_t> grow(const std::vector<std::uint32_t>& forced) {
        grow_from(forced);
        if (kept_.w == grown_.w) return {};
        if (cells_.empty()) lines_of_sight();
        return bare();
    }

    /// The kept voxels on each line of sight of each view.
    void lines_of_sight() {
        cells_.resize(rays_.size());
        on_ray_.resize(rays_.size());
        for (std::size_t v = 0; v < rays_.size(); ++v) {
            on_ray_[v].assign(std::size_t(rays_[v].w) * std::size_t(rays_[v].h), 0);
            cells_[v].resize(n_);
        }
        kept_.for_each([&](std::size_t i) {
            const Coord c = kept_.coord(i);
            for (std::size_t v = 0; v < rays_.size(); ++v) {
                const std::uint32_t cell = rays_[v].cell(c);
                cells_[v][rank(i)] = cell;
                ++on_ray_[v][cell];
            }
        });
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
            if (!pocket && !removal_keeps_outside(nb)) continue; // waits for a neighbour
            std::array<unsigned, 26> piece;
            const int np = kept_pieces(nb, piece);
            std::array<std::uint32_t, 26> root;
            // Grown from one voxel, every grown voxel is one piece: two pieces about a voxel
            // are one ring. Grown from the core's pieces and forced voxels, pieces apart meet.
            const bool one = forced.empty() && !has_core_;
            bool apart = np == 1 || !one;
            if (one) {
                if (apart || pocket) add(p);
                continue;
            }
            for (int k = 0; k < np; ++k) {
                const int bit = __builtin_ctz(piece[std::size_t(k)]);
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
        std::vector<std::vector<std::uint32_t>> left(rays_.size());
        for (std::size_t v = 0; v < rays_.size(); ++v) left[v] = on_ray_[v];
        grown_.for_each([&](std::size_t i) {
            const std::uint32_t r = rank(i);
            for (std::size_t v = 0; v < rays_.size(); ++v) --left[v][cells_[v][r]];
        });
        std::vector<std::uint32_t> bare;
        for (std::size_t k = 0; k < kept_.w.size(); ++k)
            for (std::uint64_t c = kept_.w[k] & ~grown_.w[k]; c; c &= c - 1) {
                const std::uint32_t i = std::uint32_t(k * 64 + std::size_t(__builtin_ctzll(c)));
                bool needed = false;
                for (std::size_t v = 0; v < rays_.size(); ++v) {
                    std::uint32_t& l = left[v][cells_[v][rank(i)]];
                    // Every kept voxel of the line is cut: this one is grown first next time.
                    if (l == on_ray_[v][cells_[v][rank(i)]]) needed = true, l = 0;
                }
                if (needed) bare.push_back(i);
            }
        return bare;
    }

    /// The cut voxels of the lines of sight `bare` lies on, grown back.
    void give_back(const std::vector<std::uint32_t>& bare) {
        for (std::size_t v = 0; v < rays_.size(); ++v) {
            std::vector<char> empty(on_ray_[v].size(), 0);
            for (const std::uint32_t b : bare) empty[cells_[v][rank(b)]] = 1;
            for (std::size_t k = 0; k < kept_.w.size(); ++k)
                for (std::uint64_t c = kept_.w[k] & ~grown_.w[k]; c; c &= c - 1) {
                    const std::size_t i = k * 64 + std::size_t(__builtin_ctzll(c));
                    if (empty[cells_[v][rank(i)]]) grown_.set(i);
                }
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
    unsigned around(std::size_t i) const {
        unsigned nb = 0;
        for (int d = 0; d < 27; ++d)
            if (grown_.test(i + std::size_t(step_[std::size_t(d)]))) nb |= 1u << d;
        return nb & ~(1u << 13);
    }
    void add(std::size_t i) {
        grown_.set(i);
        touched_.set(i);
        for (int d = 0; d < 27; ++d) {
            const std::size_t q = i + std::size_t(step_[std::size_t(d)]);
            if (kept_.test(q) && !grown_.test(q) && !queued_.test(q)) enqueue(q);
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

    // The grid distance of each kept voxel to the outside (1 on the surface; face steps,
    // capped at 255), the voxels deepest first, and the core.
    void depths() {
        depth_.assign(n_, 0);
        Bits left = kept_;
        std::vector<std::vector<std::uint32_t>> layers;
        std::vector<std::uint64_t> next(left.w.size());
        const std::size_t row = kept_.rw, slab = kept_.ny * kept_.rw;
        for (std::uint8_t d = 1;; d = std::uint8_t(std::min(254, int(d)) + 1)) {
            bool any = false;
            tbb::parallel_for(tbb::blocked_range<std::size_t>(slab, left.w.size() - slab),
                              [&](const tbb::blocked_range<std::size_t>& r) {
                                  for (std::size_t k = r.begin(); k != r.end(); ++k) {
                                      const std::uint64_t v = left.w[k];
                                      if (!v) {
                                          next[k] = 0;
                                          continue;
                                      }
                                      // Rows start a word apart: the first and last bits of a
                                      // row are empty, so no bit crosses rows.
                                      const std::uint64_t up = v << 1 | left.w[k - 1] >> 63;
                                      const std::uint64_t down = v >> 1 | left.w[k + 1] << 63;
                                      next[k] = v & up & down & left.w[k - row] & left.w[k + row] & left.w[k - slab] &
                                                left.w[k + slab];
                                  }
                              });
            std::vector<std::uint32_t> layer;
            for (std::size_t k = slab; k < left.w.size() - slab; ++k)
                for (std::uint64_t c = left.w[k] & ~next[k]; c; c &= c - 1) {
                    const std::size_t i = k * 64 + std::size_t(__builtin_ctzll(c));
                    depth_[rank(i)] = d;
                    layer.push_back(std::uint32_t(i));
                    any = true;
                }
            layers.push_back(std::move(layer));
            for (std::size_t k = slab; k < left.w.size() - slab; ++k) left.w[k] = next[k];
            if (d == most_) {
                core_.w = left.w;
                has_core_ = std::any_of(left.w.begin(), left.w.end(), [](std::uint64_t v) { return v != 0; });
            }
            if (!any) break;
        }
        queue_.resize(256);
        for (auto it = layers.rbegin(); it != layers.rend(); ++it)
            by_depth_.insert(by_depth_.end(), it->begin(), it->end());
    }

    const Bits& kept_;
    Bits grown_;
    const std::vector<RayRaster>& rays_;
    std::vector<std::uint32_t> first_;
    std::uint32_t n_ = 0;
    std::array<long, 27> step_{};
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
    std::vector<std::vector<std::uint32_t>> cells_;  // per view, per kept voxel (rank)
    std::vector<std::vector<std::uint32_t>> on_ray_; // per view, per cell: kept voxels
};

CoordBBox box_of(const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves) {
    CoordBBox box;
    for (std::size_t l = 0; l < leaves.leafCount(); ++l) {
        CoordBBox b;
        if (leaves.leaf(l).getValueMask().isOff()) continue;
        leaves.leaf(l).evalActiveBoundingBox(b, false);
        box.expand(b);
    }
    return box;
}

} // namespace

VoxelTopology voxel_topology(const openvdb::BoolTree& tree) {
    openvdb::BoolTree copy(tree);
    copy.voxelizeActiveTiles();
    openvdb::tree::LeafManager<openvdb::BoolTree> leaves(copy);
    const CoordBBox box = box_of(leaves);
    if (box.empty()) return {};
    return topology_of(bits_of(leaves, box));
}

HandleCut cut_handles(openvdb::tree::LeafManager<openvdb::BoolTree>& leaves, const std::vector<RayRaster>& rays,
                      int most, const std::function<void(const Coord&)>& taken) {
    HandleCut out;
    const CoordBBox box = box_of(leaves);
    if (box.empty()) return out;
    const Bits kept = bits_of(leaves, box);
    const VoxelTopology before = topology_of(kept);
    out.handles = out.handles_left = before.handles();
    // A grid of more bits than 32-bit indices number is not grown (over 1600 cells a side).
    if (out.handles <= 0 || kept.size() >= (std::size_t(1) << 32)) return out;
    Growth growth(kept, rays, most);
    std::vector<std::uint32_t> forced;
    std::vector<std::uint32_t> bare;
    for (int g = 0; g < 4; ++g) {
        bare = growth.grow(forced);
        ++out.growths;
        if (bare.empty()) break;
        forced.insert(forced.end(), bare.begin(), bare.end());
    }
    if (!bare.empty()) growth.give_back(bare);
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
