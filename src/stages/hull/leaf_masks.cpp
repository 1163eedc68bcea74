#include "leaf_masks.h"

#include <tbb/parallel_for.h>

#include <unordered_map>

namespace cm::plausible {

namespace {

using Mask = LeafMask;

// One step of 6-neighbour dilation inside a leaf (offset x * 64 + y * 8 + z: word x, byte y,
// bit z).
Mask dilate_in_leaf(const Mask& m) {
    Mask d;
    for (int x = 0; x < 8; ++x) {
        const std::uint64_t w = m[std::size_t(x)];
        std::uint64_t v =
            w | ((w << 1) & 0xFEFEFEFEFEFEFEFEull) | ((w >> 1) & 0x7F7F7F7F7F7F7F7Full) | (w << 8) | (w >> 8);
        if (x > 0) v |= m[std::size_t(x - 1)];
        if (x < 7) v |= m[std::size_t(x + 1)];
        d[std::size_t(x)] = v;
    }
    return d;
}

// The voxels of a leaf next to the face of the leaf beside it in direction d (0: -x, 1: +x,
// 2: -y, 3: +y, 4: -z, 5: +z) that are next to the voxels `m` of that leaf.
Mask across_face(const Mask& m, int d) {
    Mask out{};
    switch (d) {
    case 0: out[0] = m[7]; break; // the -x leaf's x = 7 beside our x = 0
    case 1: out[7] = m[0]; break;
    case 2:
        for (int x = 0; x < 8; ++x) out[std::size_t(x)] = m[std::size_t(x)] >> 56; // its y = 7 to our y = 0
        break;
    case 3:
        for (int x = 0; x < 8; ++x) out[std::size_t(x)] = m[std::size_t(x)] << 56;
        break;
    case 4:
        for (int x = 0; x < 8; ++x) out[std::size_t(x)] = (m[std::size_t(x)] >> 7) & 0x0101010101010101ull;
        break;
    default:
        for (int x = 0; x < 8; ++x) out[std::size_t(x)] = (m[std::size_t(x)] << 7) & 0x8080808080808080ull;
        break;
    }
    return out;
}

constexpr Mask kFull = {~0ull, ~0ull, ~0ull, ~0ull, ~0ull, ~0ull, ~0ull, ~0ull};

} // namespace

namespace {
// Each leaf's LeafManager index by its origin's key.
std::unordered_map<std::uint64_t, std::uint32_t> leaf_index(
    const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves) {
    std::unordered_map<std::uint64_t, std::uint32_t> leaf_of;
    leaf_of.reserve(leaves.leafCount() * 2);
    for (std::size_t l = 0; l < leaves.leafCount(); ++l)
        leaf_of.emplace(leaf_key(leaves.leaf(l).origin()), std::uint32_t(l));
    return leaf_of;
}
} // namespace

std::vector<std::array<std::uint32_t, 6>> leaf_neighbours(const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves) {
    using Leaf = openvdb::BoolTree::LeafNodeType;
    const std::size_t nleaf = leaves.leafCount();
    const auto leaf_of = leaf_index(leaves);
    std::vector<std::array<std::uint32_t, 6>> nbr(nleaf);
    tbb::parallel_for(std::size_t(0), nleaf, [&](std::size_t l) {
        for (int d = 0; d < 6; ++d) {
            Coord o = leaves.leaf(l).origin();
            o[d / 2] += (d & 1) ? int(Leaf::DIM) : -int(Leaf::DIM);
            const auto it = leaf_of.find(leaf_key(o));
            nbr[l][std::size_t(d)] = it == leaf_of.end() ? kNoLeaf : it->second;
        }
    });
    return nbr;
}

std::vector<std::uint32_t> leaf_neighbourhoods(const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves) {
    const std::size_t nleaf = leaves.leafCount();
    const auto leaf_of = leaf_index(leaves);
    std::vector<std::uint32_t> around(nleaf * 27);
    tbb::parallel_for(std::size_t(0), nleaf, [&](std::size_t l) {
        for (int k = 0; k < 27; ++k) {
            const Coord o = leaves.leaf(l).origin().offsetBy(8 * (k % 3 - 1), 8 * (k / 3 % 3 - 1), 8 * (k / 9 - 1));
            const auto it = leaf_of.find(leaf_key(o));
            around[l * 27 + std::size_t(k)] = it == leaf_of.end() ? kNoLeaf : it->second;
        }
    });
    return around;
}

Mask neighbour_in(const Mask& own, const Mask* next, int d) {
    Mask r = next ? across_face(*next, d) : Mask{};
    for (int x = 0; x < 8; ++x) {
        const std::uint64_t w = own[std::size_t(x)];
        switch (d) {
        case 0: r[std::size_t(x)] |= x > 0 ? own[std::size_t(x - 1)] : 0; break;
        case 1: r[std::size_t(x)] |= x < 7 ? own[std::size_t(x + 1)] : 0; break;
        case 2: r[std::size_t(x)] |= w << 8; break;
        case 3: r[std::size_t(x)] |= w >> 8; break;
        case 4: r[std::size_t(x)] |= (w << 1) & 0xFEFEFEFEFEFEFEFEull; break;
        default: r[std::size_t(x)] |= (w >> 1) & 0x7F7F7F7F7F7F7F7Full; break;
        }
    }
    return r;
}

std::vector<LeafMask> flood(const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves,
                            const std::vector<LeafMask>& seed, const std::vector<LeafMask>& through,
                            bool missing_is_seed) {
    return flood(leaf_neighbours(leaves), seed, through, missing_is_seed);
}

std::vector<LeafMask> flood(const std::vector<std::array<std::uint32_t, 6>>& nbr, const std::vector<LeafMask>& seed,
                            const std::vector<LeafMask>& through, bool missing_is_seed) {
    const std::size_t nleaf = through.size();
    auto any = [](const Mask& m) {
        std::uint64_t a = 0;
        for (const std::uint64_t w : m) a |= w;
        return a != 0;
    };
    std::vector<Mask> reached(nleaf, Mask{});
    std::vector<std::uint32_t> work;
    for (std::size_t l = 0; l < nleaf; ++l)
        if (any(through[l])) work.push_back(std::uint32_t(l));
    if (work.empty()) return reached;
    constexpr std::uint32_t none = kNoLeaf;
    auto neighbour = [&](std::size_t l, int d) { return nbr[l][std::size_t(d)]; };
    // The seeds of each leaf the flood may enter: its own, and those beside it across its faces.
    std::vector<char> queued(nleaf, 0);
    for (const std::uint32_t l : work) {
        Mask s = seed[l];
        for (int d = 0; d < 6; ++d) {
            const std::uint32_t nb = neighbour(l, d);
            if (nb == none && !missing_is_seed) continue;
            const Mask t = across_face(nb == none ? kFull : seed[nb], d);
            for (int w = 0; w < 8; ++w) s[std::size_t(w)] |= t[std::size_t(w)] & through[l][std::size_t(w)];
        }
        reached[l] = s;
        queued[l] = 1;
    }
    // To a fixed point: each leaf's reach grown inside it, then handed across its faces.
    while (!work.empty()) {
        const std::uint32_t l = work.back();
        work.pop_back();
        queued[l] = 0;
        Mask& s = reached[l];
        for (;;) {
            const Mask d = dilate_in_leaf(s);
            bool grew = false;
            for (int w = 0; w < 8; ++w) {
                const std::uint64_t v = s[std::size_t(w)] | (d[std::size_t(w)] & through[l][std::size_t(w)]);
                grew = grew || v != s[std::size_t(w)];
                s[std::size_t(w)] = v;
            }
            if (!grew) break;
        }
        for (int d = 0; d < 6; ++d) {
            const std::uint32_t nb = neighbour(l, d);
            if (nb == none) continue;
            // Our face, seen from the neighbour: the direction back is d ^ 1.
            const Mask t = across_face(s, d ^ 1);
            bool grew = false;
            for (int w = 0; w < 8; ++w) {
                const std::uint64_t add =
                    t[std::size_t(w)] & through[nb][std::size_t(w)] & ~reached[nb][std::size_t(w)];
                if (add) reached[nb][std::size_t(w)] |= add, grew = true;
            }
            if (grew && !queued[nb]) queued[nb] = 1, work.push_back(nb);
        }
    }
    for (std::size_t l = 0; l < nleaf; ++l)
        for (int w = 0; w < 8; ++w) reached[l][std::size_t(w)] &= through[l][std::size_t(w)];
    return reached;
}

namespace {

// The piece of `through` that holds voxel `offset` of leaf `leaf` (which must be in it),
// moved out of `through` into `piece` (empty on every leaf it reaches before the call);
// `touched` gets the leaves it reaches.
void flood_piece(const std::vector<std::array<std::uint32_t, 6>>& nbr, std::uint32_t leaf, openvdb::Index offset,
                 std::vector<LeafMask>& through, std::vector<LeafMask>& piece, std::vector<std::uint32_t>& touched) {
    touched.assign(1, leaf);
    piece[leaf][offset >> 6] = std::uint64_t(1) << (offset & 63);
    through[leaf][offset >> 6] &= ~piece[leaf][offset >> 6];
    std::vector<std::uint32_t> work(1, leaf);
    auto any = [](const Mask& m) {
        std::uint64_t a = 0;
        for (const std::uint64_t w : m) a |= w;
        return a != 0;
    };
    // Each leaf's share grown inside it to a fixed point, then handed across its faces.
    while (!work.empty()) {
        const std::uint32_t l = work.back();
        work.pop_back();
        Mask& s = piece[l];
        for (;;) {
            const Mask d = dilate_in_leaf(s);
            Mask g;
            for (int w = 0; w < 8; ++w) g[std::size_t(w)] = d[std::size_t(w)] & through[l][std::size_t(w)];
            if (!any(g)) break;
            for (int w = 0; w < 8; ++w)
                s[std::size_t(w)] |= g[std::size_t(w)], through[l][std::size_t(w)] &= ~g[std::size_t(w)];
        }
        for (int d = 0; d < 6; ++d) {
            const std::uint32_t nb = nbr[l][std::size_t(d)];
            if (nb == kNoLeaf) continue;
            const Mask t = across_face(s, d ^ 1);
            Mask g;
            for (int w = 0; w < 8; ++w) g[std::size_t(w)] = t[std::size_t(w)] & through[nb][std::size_t(w)];
            if (!any(g)) continue;
            if (!any(piece[nb])) touched.push_back(nb);
            for (int w = 0; w < 8; ++w)
                piece[nb][std::size_t(w)] |= g[std::size_t(w)], through[nb][std::size_t(w)] &= ~g[std::size_t(w)];
            work.push_back(nb);
        }
    }
}

} // namespace

void for_each_piece(
    const std::vector<std::array<std::uint32_t, 6>>& nbr, std::vector<LeafMask>& masks,
    const std::function<void(const std::vector<LeafMask>& piece, const std::vector<std::uint32_t>& leaves)>& fn) {
    std::vector<std::uint32_t> holding;
    for (std::size_t l = 0; l < masks.size(); ++l) {
        std::uint64_t a = 0;
        for (const std::uint64_t w : masks[l]) a |= w;
        if (a) holding.push_back(std::uint32_t(l));
    }
    if (holding.empty()) return;
    std::vector<LeafMask> piece(masks.size(), LeafMask{});
    std::vector<std::uint32_t> leaves;
    for (const std::uint32_t l0 : holding)
        for (int w0 = 0; w0 < 8; ++w0)
            while (masks[l0][std::size_t(w0)]) {
                const auto off = openvdb::Index(w0 * 64 + __builtin_ctzll(masks[l0][std::size_t(w0)]));
                flood_piece(nbr, l0, off, masks, piece, leaves);
                fn(piece, leaves);
                for (const std::uint32_t l : leaves) piece[l] = LeafMask{};
            }
}

namespace {

std::size_t count(const Mask& m) {
    std::size_t c = 0;
    for (const std::uint64_t w : m) c += std::size_t(__builtin_popcountll(w));
    return c;
}

bool bit(const Mask& m, int off) { return (m[std::size_t(off >> 6)] >> (off & 63) & 1) != 0; }

// The steps of bridges(): the main body, the pieces apart from it, and for each piece
// breadth-first layers through the removed voxels out of it until a layer touches the main
// body; the bridge runs from there down the layers to the piece. (Layers out of the piece, not
// out of the body: the body's first layer alone is its whole surface, a piece's layers stay
// about the piece.)
class Bridges {
public:
    Bridges(const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves,
            const std::vector<std::array<std::uint32_t, 6>>& nbr, const std::vector<Mask>& hull,
            const std::vector<Mask>& kept, int max_steps)
        : leaves_(leaves), nbr_(nbr), hull_(hull), kept_(kept), max_steps_(max_steps), nleaf_(leaves.leafCount()) {}

    /// The main body: what is kept connected to the fullest leaf. False when nothing is kept.
    bool find_main();
    /// The kept voxels apart from the main body. False when there are none.
    bool find_pieces();
    /// Each piece, in leaf order, joined to the main body by a shortest bridge when one of at
    /// most max_steps voxels exists; returns the bridges' voxels and counts the pieces joined.
    std::vector<Coord> join(std::size_t* pieces);

private:
    // next = the voxels of `into`, not visited, next to `front` (given on the leaves `from`).
    void grow(const std::vector<std::uint32_t>& from, const std::vector<Mask>& into,
              std::vector<std::uint32_t>& touched);
    // The leaf and offset of the neighbour of (l, off) in direction d, if the tree has it.
    bool step(std::uint32_t l, int off, int d, std::uint32_t* nl, int* noff) const;
    Coord voxel_at(std::uint32_t l, int off) const { return leaves_.leaf(l).offsetToGlobalCoord(openvdb::Index(off)); }
    // The layers out of the piece on the leaves `piece` (its voxels in front_), until one
    // touches the main body; the bridge appended to `out`. False when none within max_steps.
    bool bridge(const std::vector<std::uint32_t>& piece, std::vector<Coord>& out);
    // The first voxel of layer `next_` (on the leaves `touched`) with a face neighbour in the
    // main body, as leaf * 512 + offset; -1 when none.
    std::int64_t touching_main(const std::vector<std::uint32_t>& touched) const;
    // The bridge from voxel (l, off) of layer `layer` down the layers to the piece.
    void bridge_down(std::uint32_t l, int off, int layer, std::vector<Coord>& out) const;

    const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves_;
    const std::vector<std::array<std::uint32_t, 6>>& nbr_;
    const std::vector<Mask>& hull_;
    const std::vector<Mask>& kept_;
    const int max_steps_;
    const std::size_t nleaf_;
    std::vector<Mask> main_, piece_, removed_, visited_, front_, next_;
    std::vector<char> seen_;                                      // grow()'s leaves of this layer
    std::vector<std::unordered_map<std::uint32_t, Mask>> layers_; // per layer: leaf -> its voxels there
};

bool Bridges::find_main() {
    std::size_t best = 0, most = 0;
    for (std::size_t l = 0; l < nleaf_; ++l)
        if (const std::size_t c = count(kept_[l]); c > most) most = c, best = l;
    if (most == 0) return false;
    std::vector<Mask> seed(nleaf_, Mask{});
    seed[best] = kept_[best];
    main_ = flood(nbr_, seed, kept_, false);
    return true;
}

bool Bridges::find_pieces() {
    piece_.resize(nleaf_);
    bool any_piece = false;
    for (std::size_t l = 0; l < nleaf_; ++l)
        for (int w = 0; w < 8; ++w) {
            piece_[l][std::size_t(w)] = kept_[l][std::size_t(w)] & ~main_[l][std::size_t(w)];
            any_piece = any_piece || piece_[l][std::size_t(w)];
        }
    return any_piece;
}

void Bridges::grow(const std::vector<std::uint32_t>& from, const std::vector<Mask>& into,
                   std::vector<std::uint32_t>& touched) {
    auto add = [&](std::uint32_t l, const Mask& m) {
        Mask a;
        bool any = false;
        for (int w = 0; w < 8; ++w) {
            a[std::size_t(w)] = m[std::size_t(w)] & into[l][std::size_t(w)] & ~visited_[l][std::size_t(w)];
            any = any || a[std::size_t(w)];
        }
        if (!any) return;
        if (!seen_[l]) seen_[l] = 1, touched.push_back(l), next_[l] = Mask{};
        for (int w = 0; w < 8; ++w) next_[l][std::size_t(w)] |= a[std::size_t(w)];
    };
    for (const std::uint32_t l : from) {
        add(l, dilate_in_leaf(front_[l]));
        for (int d = 0; d < 6; ++d)
            if (const std::uint32_t nb = nbr_[l][std::size_t(d)]; nb != kNoLeaf) add(nb, across_face(front_[l], d ^ 1));
    }
    for (const std::uint32_t l : touched) seen_[l] = 0;
}

bool Bridges::step(std::uint32_t l, int off, int d, std::uint32_t* nl, int* noff) const {
    static constexpr int kStride[3] = {64, 8, 1};
    const int a = d / 2, dir = (d & 1) ? 1 : -1, loc = (a == 0 ? off >> 6 : a == 1 ? (off >> 3) & 7 : off & 7);
    if (loc + dir >= 0 && loc + dir <= 7) {
        *nl = l, *noff = off + dir * kStride[a];
        return true;
    }
    *nl = nbr_[l][std::size_t(d)], *noff = off - dir * 7 * kStride[a];
    return *nl != kNoLeaf;
}

std::vector<Coord> Bridges::join(std::size_t* pieces) {
    std::vector<Coord> out;
    // Breadth-first layers through the removed voxels (hull, not kept).
    removed_.resize(nleaf_);
    for (std::size_t l = 0; l < nleaf_; ++l)
        for (int w = 0; w < 8; ++w) removed_[l][std::size_t(w)] = hull_[l][std::size_t(w)] & ~kept_[l][std::size_t(w)];
    visited_.assign(nleaf_, Mask{});
    front_.assign(nleaf_, Mask{});
    next_.assign(nleaf_, Mask{});
    seen_.assign(nleaf_, 0);
    for_each_piece(nbr_, piece_, [&](const std::vector<Mask>& piece, const std::vector<std::uint32_t>& leaves) {
        for (const std::uint32_t l : leaves) front_[l] = piece[l];
        if (bridge(leaves, out) && pieces) ++*pieces;
    });
    return out;
}

bool Bridges::bridge(const std::vector<std::uint32_t>& piece, std::vector<Coord>& out) {
    // Every leaf whose visited_, front_ or next_ this piece's layers set, cleared at the end.
    std::vector<std::uint32_t> used = piece;
    for (const std::uint32_t l : piece) visited_[l] = front_[l];
    std::vector<std::uint32_t> from = piece;
    bool joined = false;
    int layer = 1;
    for (; layer <= max_steps_ && !from.empty(); ++layer) {
        std::vector<std::uint32_t> touched;
        grow(from, removed_, touched);
        if (layers_.size() <= std::size_t(layer)) layers_.resize(std::size_t(layer) + 1);
        for (const std::uint32_t l : touched) {
            for (int w = 0; w < 8; ++w) visited_[l][std::size_t(w)] |= next_[l][std::size_t(w)];
            layers_[std::size_t(layer)].emplace(l, next_[l]);
        }
        used.insert(used.end(), touched.begin(), touched.end());
        if (const std::int64_t first = touching_main(touched); first >= 0) {
            bridge_down(std::uint32_t(first / 512), int(first % 512), layer, out);
            joined = true;
            break;
        }
        for (const std::uint32_t l : from) front_[l] = Mask{};
        from = std::move(touched);
        std::swap(front_, next_);
    }
    for (const std::uint32_t l : used) visited_[l] = front_[l] = next_[l] = Mask{};
    for (int k = 1; k <= std::min(layer, max_steps_) && std::size_t(k) < layers_.size(); ++k)
        layers_[std::size_t(k)].clear();
    return joined;
}

std::int64_t Bridges::touching_main(const std::vector<std::uint32_t>& touched) const {
    for (const std::uint32_t l : touched) {
        Mask near{};
        for (int d = 0; d < 6; ++d) {
            const std::uint32_t k = nbr_[l][std::size_t(d)];
            const Mask m = neighbour_in(main_[l], k != kNoLeaf ? &main_[k] : nullptr, d);
            for (int w = 0; w < 8; ++w) near[std::size_t(w)] |= m[std::size_t(w)];
        }
        for (int w = 0; w < 8; ++w)
            if (const std::uint64_t b = next_[l][std::size_t(w)] & near[std::size_t(w)])
                return std::int64_t(l) * 512 + w * 64 + __builtin_ctzll(b);
    }
    return -1;
}

void Bridges::bridge_down(std::uint32_t l, int off, int layer, std::vector<Coord>& out) const {
    std::uint32_t cl = l;
    int coff = off, cur = layer;
    out.push_back(voxel_at(cl, coff));
    while (cur > 1) {
        bool moved = false;
        for (int e = 0; e < 6 && !moved; ++e) {
            std::uint32_t ql;
            int qoff;
            if (!step(cl, coff, e, &ql, &qoff)) continue;
            const auto& below = layers_[std::size_t(cur - 1)];
            const auto it = below.find(ql);
            if (it == below.end() || !bit(it->second, qoff)) continue;
            cl = ql, coff = qoff, --cur, moved = true;
            out.push_back(voxel_at(cl, coff));
        }
        if (!moved) break; // (cannot happen: a layer-k voxel has a layer k-1 neighbour)
    }
}

} // namespace

std::vector<Coord> bridges(const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves,
                           const std::vector<std::array<std::uint32_t, 6>>& nbr, const std::vector<Mask>& hull,
                           const std::vector<Mask>& kept, int max_steps, std::size_t* pieces) {
    if (pieces) *pieces = 0;
    Bridges b(leaves, nbr, hull, kept, max_steps);
    if (!b.find_main() || !b.find_pieces()) return {};
    return b.join(pieces);
}

std::vector<LeafMask> sealed_pockets(const std::vector<std::array<std::uint32_t, 6>>& nbr,
                                     const std::vector<LeafMask>& hull, const std::vector<LeafMask>& removed) {
    std::vector<Mask> outside(hull.size());
    for (std::size_t l = 0; l < hull.size(); ++l)
        for (int w = 0; w < 8; ++w) outside[l][std::size_t(w)] = ~hull[l][std::size_t(w)];
    std::vector<Mask> pockets = flood(nbr, outside, removed, /*missing_is_seed=*/true);
    for (std::size_t l = 0; l < hull.size(); ++l)
        for (int w = 0; w < 8; ++w)
            pockets[l][std::size_t(w)] = removed[l][std::size_t(w)] & ~pockets[l][std::size_t(w)];
    return pockets;
}

} // namespace cm::plausible
