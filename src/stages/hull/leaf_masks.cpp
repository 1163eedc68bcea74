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
    const std::size_t nleaf = leaves.leafCount();
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
    const auto nbr = leaf_neighbours(leaves);
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

std::size_t count(const Mask& m) {
    std::size_t c = 0;
    for (const std::uint64_t w : m) c += std::size_t(__builtin_popcountll(w));
    return c;
}

bool bit(const Mask& m, int off) { return (m[std::size_t(off >> 6)] >> (off & 63) & 1) != 0; }

// The steps of bridges(): the main body, the pieces apart from it, and breadth-first layers
// through the removed voxels out of the main body; a piece next to a layer is joined by a
// bridge down the layers.
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
    /// Layer by layer out of the main body until every piece is joined; returns the bridges'
    /// voxels and counts the pieces joined.
    std::vector<Coord> join(std::size_t* pieces);

private:
    // next = the voxels of `into`, not visited, next to `front` (given on the leaves `from`).
    void grow(const std::vector<std::uint32_t>& from, const std::vector<Mask>& front, const std::vector<Mask>& into,
              std::vector<Mask>& next, std::vector<std::uint32_t>& touched) const;
    // The leaf and offset of the neighbour of (l, off) in direction d, if the tree has it.
    bool step(std::uint32_t l, int off, int d, std::uint32_t* nl, int* noff) const;
    Coord voxel_at(std::uint32_t l, int off) const { return leaves_.leaf(l).offsetToGlobalCoord(openvdb::Index(off)); }
    // Joins the pieces next to the voxels of layer `layer` (`next`, on the leaves `touched`).
    void join_next_to(int layer, const std::vector<std::uint32_t>& touched, std::vector<Coord>& out,
                      std::size_t* pieces);
    // The bridge from voxel (l, off) of layer `layer` down the layers to the main body.
    void bridge_down(std::uint32_t l, int off, int layer, std::vector<Coord>& out) const;
    // The piece holding voxel (pl, poff) joins the main body: it is no piece any more.
    void joined(std::uint32_t pl, int poff);

    const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves_;
    const std::vector<std::array<std::uint32_t, 6>>& nbr_;
    const std::vector<Mask>& hull_;
    const std::vector<Mask>& kept_;
    const int max_steps_;
    const std::size_t nleaf_;
    std::vector<Mask> main_, piece_, removed_, visited_, front_, next_;
    std::size_t remaining_ = 0;                                   // voxels of pieces not joined yet
    std::vector<std::unordered_map<std::uint32_t, Mask>> layers_; // per layer: leaf -> its voxels there
};

bool Bridges::find_main() {
    std::size_t best = 0, most = 0;
    for (std::size_t l = 0; l < nleaf_; ++l)
        if (const std::size_t c = count(kept_[l]); c > most) most = c, best = l;
    if (most == 0) return false;
    std::vector<Mask> seed(nleaf_, Mask{});
    seed[best] = kept_[best];
    main_ = flood(leaves_, seed, kept_, false);
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
    if (!any_piece) return false;
    for (const Mask& m : piece_) remaining_ += count(m);
    return true;
}

void Bridges::grow(const std::vector<std::uint32_t>& from, const std::vector<Mask>& front,
                   const std::vector<Mask>& into, std::vector<Mask>& next, std::vector<std::uint32_t>& touched) const {
    std::vector<char> seen(nleaf_, 0);
    auto add = [&](std::uint32_t l, const Mask& m) {
        Mask a;
        bool any = false;
        for (int w = 0; w < 8; ++w) {
            a[std::size_t(w)] = m[std::size_t(w)] & into[l][std::size_t(w)] & ~visited_[l][std::size_t(w)];
            any = any || a[std::size_t(w)];
        }
        if (!any) return;
        if (!seen[l]) seen[l] = 1, touched.push_back(l), next[l] = Mask{};
        for (int w = 0; w < 8; ++w) next[l][std::size_t(w)] |= a[std::size_t(w)];
    };
    for (const std::uint32_t l : from) {
        add(l, dilate_in_leaf(front[l]));
        for (int d = 0; d < 6; ++d)
            if (const std::uint32_t nb = nbr_[l][std::size_t(d)]; nb != kNoLeaf) add(nb, across_face(front[l], d ^ 1));
    }
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
    // Breadth-first layers through the removed voxels (hull, not kept) out of the main body;
    // each voxel's layer kept by leaf and offset.
    removed_.resize(nleaf_);
    for (std::size_t l = 0; l < nleaf_; ++l)
        for (int w = 0; w < 8; ++w) removed_[l][std::size_t(w)] = hull_[l][std::size_t(w)] & ~kept_[l][std::size_t(w)];
    visited_ = main_;
    layers_.resize(std::size_t(max_steps_) + 1);
    std::vector<std::uint32_t> from;
    for (std::size_t l = 0; l < nleaf_; ++l)
        if (count(main_[l])) from.push_back(std::uint32_t(l));
    front_ = main_;
    next_.resize(nleaf_);
    for (int layer = 1; layer <= max_steps_ && !from.empty() && remaining_ > 0; ++layer) {
        std::vector<std::uint32_t> touched;
        grow(from, front_, removed_, next_, touched);
        for (const std::uint32_t l : touched) {
            for (int w = 0; w < 8; ++w) visited_[l][std::size_t(w)] |= next_[l][std::size_t(w)];
            layers_[std::size_t(layer)].emplace(l, next_[l]);
        }
        join_next_to(layer, touched, out, pieces);
        from = std::move(touched);
        std::swap(front_, next_);
    }
    return out;
}

// A bridge down the layers from the first voxel found next to a piece, then the whole piece
// joins the main body (its other voxels need no bridge of their own).
void Bridges::join_next_to(int layer, const std::vector<std::uint32_t>& touched, std::vector<Coord>& out,
                           std::size_t* pieces) {
    for (const std::uint32_t l : touched)
        for (int w = 0; w < 8; ++w)
            for (std::uint64_t b = next_[l][std::size_t(w)]; b; b &= b - 1) {
                const int off = w * 64 + __builtin_ctzll(b);
                for (int d = 0; d < 6; ++d) {
                    std::uint32_t pl;
                    int poff;
                    if (!step(l, off, d, &pl, &poff) || !bit(piece_[pl], poff)) continue;
                    bridge_down(l, off, layer, out);
                    joined(pl, poff);
                    if (pieces) ++*pieces;
                }
            }
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

void Bridges::joined(std::uint32_t pl, int poff) {
    std::vector<Mask> s1(nleaf_, Mask{});
    s1[pl][std::size_t(poff >> 6)] = std::uint64_t(1) << (poff & 63);
    const std::vector<Mask> reached = flood(leaves_, s1, piece_, false);
    for (std::size_t k = 0; k < nleaf_; ++k) {
        remaining_ -= count(reached[k]);
        for (int x = 0; x < 8; ++x) piece_[k][std::size_t(x)] &= ~reached[k][std::size_t(x)];
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

std::vector<LeafMask> sealed_pockets(const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves,
                                     const std::vector<LeafMask>& hull, const std::vector<LeafMask>& removed) {
    std::vector<Mask> outside(hull.size());
    for (std::size_t l = 0; l < hull.size(); ++l)
        for (int w = 0; w < 8; ++w) outside[l][std::size_t(w)] = ~hull[l][std::size_t(w)];
    std::vector<Mask> pockets = flood(leaves, outside, removed, /*missing_is_seed=*/true);
    for (std::size_t l = 0; l < hull.size(); ++l)
        for (int w = 0; w < 8; ++w)
            pockets[l][std::size_t(w)] = removed[l][std::size_t(w)] & ~pockets[l][std::size_t(w)];
    return pockets;
}

} // namespace cm::plausible
