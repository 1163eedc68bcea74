// The paper's reduction of large meshes (reduce_blocked, mesh_decimate_internal.h): rounds
// over spatial blocks reduced in parallel, then one queue over the whole, now much lighter,
// mesh.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "mesh_decimate_internal.h"
#include "util/chunked_scatter.h"
#include "util/uninit_vector.h"

namespace cm::decimate {

namespace {

// Faces per block of reduce_blocked (a block's lists and samples stay in the caches: 16 k
// faces measured faster than 64 k, docs/results/speed.md), the size from which a mesh is
// cut in blocks, and the size down to which the rounds go on (the last queue is one
// thread's: the less it is left, the sooner the run ends; 64 k rather than 128 k measured
// 8 % faster on man at 512, where a round more takes 91 k faces to 62 k, with faces within
// 0.3 % and the silhouette error within 0.01 points, docs/results/speed.md).
constexpr std::size_t kBlockFaces = std::size_t(1) << 14;
constexpr std::size_t kBlockedFrom = std::size_t(1) << 18;
constexpr std::size_t kRoundsDownTo = std::size_t(1) << 16;
// The share of the starting candidates (by importance) a round's blocks may remove.
// 0.9 measured against one queue over the whole mesh (docs/results/speed.md): the same
// face count within 0.2 % and the same silhouette error (blocks run as queues then; swept,
// against those: faces within 0.5 %, silhouette error within 0.01 points). 0.5 leaves too
// much to the last queue; 0.95 measured 0.7 % more faces.
constexpr double kBlockQuantile = 0.9;

// The blocks of reduce_blocked: the cells of a k x k x k grid over the mesh's bounding box
// holding at least one vertex, with k the smallest giving about one occupied cell per
// kBlockFaces faces. Returns k; `cell` is each vertex's cell.
int block_cells(const Mesh& mesh, float shift, std::vector<std::uint32_t>& cell) {
    Vec3f lo, hi;
    mesh.bounds(lo, hi);
    const Vec3f ext = vmax(hi - lo, Vec3f(1e-30f, 1e-30f, 1e-30f));
    const std::size_t want = mesh.face_count() / kBlockFaces;
    auto cell_of = [&](const Vec3f& p, int k) {
        auto axis = [&](float x, float l, float e) {
            return std::uint32_t(std::clamp(int((x - l) / e * float(k) + shift), 0, k));
        };
        const std::uint32_t n = std::uint32_t(k) + 1; // a shifted grid has one more cell per axis
        return (axis(p.z, lo.z, ext.z) * n + axis(p.y, lo.y, ext.y)) * n + axis(p.x, lo.x, ext.x);
    };
    int k = 2;
    for (; k < 64; ++k) { // occupancy from every 64th vertex: the surface, not the box, decides
        std::vector<char> used(std::size_t(k + 1) * (k + 1) * (k + 1), 0);
        std::size_t occupied = 0;
        for (std::size_t v = 0; v < mesh.positions.size(); v += 64) {
            char& u = used[cell_of(mesh.positions[v], k)];
            occupied += !u;
            u = 1;
        }
        if (occupied >= want) break;
    }
    cell.resize(mesh.positions.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cell.size(), 1 << 14), [&](const auto& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v) cell[v] = cell_of(mesh.positions[v], k);
    });
    return k;
}

// `local_ids` of a round: per thread, an array of at least the mesh's vertex count, all kNone
// (and left so), kept by the caller from round to round (filling one anew each round cost as
// much as the blocks' starting scores).
using LocalIds = tbb::enumerable_thread_specific<std::vector<std::uint32_t>>;

// One round of reduce_blocked: the mesh is cut into spatial blocks (each face goes with
// its first vertex's cell) and every block is reduced on its own, in parallel, in one sweep
// (run_sweep) removing only the vertices less important than the q-quantile of the starting
// importances (in that range the order hardly matters). A vertex with faces in two blocks is
// on the open border of both, so it stays. The blocks' faces then make one mesh over the
// vertices they still use (in input order, attributes kept: surviving vertices do not move);
// `frozen` follows.
class BlockRound {
public:
    BlockRound(const Mesh& mesh, const ReduceOptions& opt, std::vector<char>* frozen, LocalIds& local_ids)
        : mesh_(mesh),
          opt_(opt),
          frozen_(frozen),
          local_ids_(local_ids),
          nv_(mesh.positions.size()),
          limit_(opt.max_angle_deg * kPi / 180.0),
          straight_(opt.crease_straightness_deg * kPi / 180.0) {}

    /// 1. The blocks: the faces by cell of the grid (block_cells), shifted by `shift` cells.
    void cut(float shift);
    /// 2. Where the blocks stop: the q-quantile of the starting importances of a sample of
    /// the blocks (their scores are kept for the sweep).
    float stop_key(double q);
    /// 3. Every block reduced on its own, in parallel, in one sweep up to `stop_key`; returns
    /// the collapses made.
    std::size_t reduce(float stop_key, const Progress& progress);
    /// 4. The blocks' faces as one mesh over the input vertices they still use, into `out`
    /// (which may be the round's input: nothing reads it after).
    void merge(Mesh& out);

private:
    // A block: its faces and vertices as a mesh of their own (positions only: the surviving
    // vertices keep their input positions and attributes). A block's mesh and collapser are
    // built twice, once for its starting scores and once to reduce it, so that no more of
    // them are held at a time than there are threads (all of them at once were the
    // reduction's peak: on 16 M faces about as much memory as the mesh again).
    struct Block {
        Mesh mesh;
        std::vector<std::uint32_t> input; ///< input vertex of each block vertex
        std::vector<char> frozen;
        std::vector<char> locks; ///< the collapser's locks, found on the first build
        std::unique_ptr<Collapser> collapser;
        StartScores start;       ///< the candidates and their importance
        std::vector<float> keys; ///< starting importance of a sample of the candidates
    };
    void build(std::size_t i, Block& blk) const;
    static void let_go(Block& blk);
    void score(Block& blk) const;
    /// The input vertices the blocks' faces use, numbered in input order: `order` per input
    /// vertex (kNone: not used), `input_of` per vertex of the result.
    void number_used(UninitVector<std::uint32_t>& order, std::vector<std::uint32_t>& input_of) const;

    const Mesh& mesh_;
    const ReduceOptions& opt_;
    std::vector<char>* frozen_;
    LocalIds& local_ids_;
    const std::size_t nv_;
    const double limit_, straight_;
    std::vector<std::uint32_t> start_, faces_; ///< the faces by cell (CSR over the cells)
    std::vector<std::uint32_t> blocks_;        ///< the cells holding faces
    std::vector<std::unique_ptr<Block>> parts_;
    std::vector<std::vector<std::array<std::uint32_t, 3>>> kept_; ///< each block's faces left, on input vertices
};

void BlockRound::cut(float shift) {
    std::vector<std::uint32_t> cell;
    const int k = block_cells(mesh_, shift, cell);
    const std::size_t ncells = std::size_t(k + 1) * (k + 1) * (k + 1);
    // Faces by block (counting sort, faces in input order within a block).
    chunked_scatter(
        mesh_.face_count(), ncells,
        [&](std::size_t f, auto&& emit) { emit(cell[mesh_.triangles[f][0]], std::uint32_t(f)); }, start_, faces_);
    for (std::size_t b = 0; b < ncells; ++b)
        if (start_[b + 1] > start_[b]) blocks_.push_back(std::uint32_t(b));
}

void BlockRound::build(std::size_t i, Block& blk) const {
    auto& local = local_ids_.local();
    if (local.size() < nv_) local.assign(nv_, kNone);
    const std::uint32_t b = blocks_[i];
    Mesh& sub = blk.mesh;
    auto& global = blk.input;
    sub.triangles.reserve(start_[b + 1] - start_[b]);
    for (std::uint32_t j = start_[b]; j < start_[b + 1]; ++j) {
        std::array<std::uint32_t, 3> t = mesh_.triangles[faces_[j]];
        for (auto& x : t) {
            if (local[x] == kNone) {
                local[x] = std::uint32_t(global.size());
                global.push_back(x);
            }
            x = local[x];
        }
        sub.triangles.push_back(t);
    }
    sub.positions.reserve(global.size());
    for (auto g : global) sub.positions.push_back(mesh_.positions[g]);
    if (frozen_)
        for (auto g : global) blk.frozen.push_back((*frozen_)[g]);
    for (auto g : global) local[g] = kNone;
    blk.collapser =
        std::make_unique<Collapser>(sub, frozen_ ? &blk.frozen : nullptr, blk.locks.empty() ? nullptr : &blk.locks);
}

void BlockRound::let_go(Block& blk) {
    blk.collapser.reset();
    blk.mesh = Mesh();
    std::vector<std::uint32_t>().swap(blk.input);
    std::vector<char>().swap(blk.frozen);
}

void BlockRound::score(Block& blk) const {
    const Collapser& c = *blk.collapser;
    blk.start = start_scores(c, blk.input.size(), [&](std::uint32_t v, auto&, float& key) {
        return importance(c, v, limit_, straight_, key);
    });
}

float BlockRound::stop_key(double q) {
    parts_.resize(blocks_.size());
    // The blocks whose starting scores set where the blocks stop: every eighth of many (spread
    // over the mesh in cell order: 64 blocks or more, enough for a quantile; fewer measured
    // a worse silhouette error), every one of fewer. The others are built once, in the pass
    // that reduces them.
    const std::size_t sample_every = blocks_.size() >= 512 ? 8 : 1;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks_.size(), 1), [&](const auto& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            auto blk = std::make_unique<Block>();
            if (i % sample_every == 0) {
                build(i, *blk);
                // The queue's starting scores, computed here once: a sample of them (every
                // fourth vertex) sets where the blocks stop.
                score(*blk);
                for (std::uint32_t v = 0; v < blk->input.size(); v += 4)
                    if (blk->start.cand[v]) blk->keys.push_back(blk->start.keys[v]);
                blk->locks = blk->collapser->locks();
                let_go(*blk);
            }
            parts_[i] = std::move(blk);
        }
    });
    // The blocks remove only the least important vertices (below a quantile of the
    // starting importances): in that range the order hardly matters, and the rest goes
    // in one queue, in the order of the paper, seams included.
    std::vector<float> all_keys;
    for (const auto& blk : parts_) all_keys.insert(all_keys.end(), blk->keys.begin(), blk->keys.end());
    if (all_keys.empty()) return HUGE_VALF;
    const std::size_t at = std::min(all_keys.size() - 1, std::size_t(q * double(all_keys.size())));
    std::nth_element(all_keys.begin(), all_keys.begin() + std::ptrdiff_t(at), all_keys.end());
    return all_keys[at];
}

std::size_t BlockRound::reduce(float stop_key, const Progress& progress) {
    kept_.resize(blocks_.size());
    std::vector<std::size_t> collapses(blocks_.size(), 0);
    std::mutex progress_mutex;
    std::size_t done = 0;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks_.size(), 1), [&](const auto& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            Block& blk = *parts_[i];
            const bool scored = !blk.start.keys.empty();
            build(i, blk);
            if (!scored) score(blk);
            collapses[i] =
                reduce_queue(*blk.collapser, blk.mesh.positions.size(), opt_, 0, stop_key, {}, &blk.start, true);
            auto& out = kept_[i];
            for (const auto& t : blk.mesh.triangles)
                if (t[0] != kNone) out.push_back({blk.input[t[0]], blk.input[t[1]], blk.input[t[2]]});
            parts_[i].reset();
            if (progress) { // from one thread at a time; may throw to cancel
                std::lock_guard<std::mutex> lock(progress_mutex);
                progress(double(++done) / double(blocks_.size()));
            }
        }
    });
    std::size_t n = 0;
    for (auto c : collapses) n += c;
    return n;
}

void BlockRound::number_used(UninitVector<std::uint32_t>& order, std::vector<std::uint32_t>& input_of) const {
    // (the large arrays written first side by side: a fill on one thread would map their pages there)
    UninitVector<char> used(nv_);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv_, 1 << 16), [&](const auto& r) {
        std::fill(used.begin() + std::ptrdiff_t(r.begin()), used.begin() + std::ptrdiff_t(r.end()), char(0));
    });
    tbb::parallel_for(std::size_t(0), kept_.size(), [&](std::size_t i) {
        for (const auto& t : kept_[i])
            for (auto x : t) std::atomic_ref<char>(used[x]).store(1, std::memory_order_relaxed);
    });
    // Counted per chunk, then numbered from each chunk's start.
    constexpr std::size_t kChunk = std::size_t(1) << 16;
    const std::size_t nchunks = (nv_ + kChunk - 1) / kChunk;
    std::vector<std::size_t> chunk_start(nchunks + 1, 0);
    tbb::parallel_for(std::size_t(0), nchunks, [&](std::size_t c) {
        chunk_start[c + 1] =
            std::size_t(std::count(used.begin() + std::ptrdiff_t(c * kChunk),
                                   used.begin() + std::ptrdiff_t(std::min(nv_, (c + 1) * kChunk)), char(1)));
    });
    for (std::size_t c = 0; c < nchunks; ++c) chunk_start[c + 1] += chunk_start[c];
    order.resize(nv_);
    input_of.resize(chunk_start[nchunks]);
    tbb::parallel_for(std::size_t(0), nchunks, [&](std::size_t c) {
        std::size_t at = chunk_start[c];
        for (std::size_t v = c * kChunk, e = std::min(nv_, (c + 1) * kChunk); v < e; ++v)
            if (used[v]) {
                order[v] = std::uint32_t(at);
                input_of[at++] = std::uint32_t(v);
            } else {
                order[v] = kNone;
            }
    });
}

void BlockRound::merge(Mesh& out) {
    UninitVector<std::uint32_t> order;
    std::vector<std::uint32_t> input_of;
    number_used(order, input_of);
    Mesh merged;
    auto pick = [&](const auto& from, auto& to) {
        if (from.size() != nv_) return;
        to.resize(input_of.size());
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, input_of.size(), 1 << 14), [&](const auto& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) to[i] = from[input_of[i]];
        });
    };
    pick(mesh_.positions, merged.positions);
    pick(mesh_.uvs, merged.uvs);
    pick(mesh_.colors, merged.colors);
    pick(mesh_.normals, merged.normals);
    std::vector<std::size_t> first(kept_.size() + 1, 0); // where each block's faces go
    for (std::size_t i = 0; i < kept_.size(); ++i) first[i + 1] = first[i] + kept_[i].size();
    merged.triangles.resize(first.back());
    tbb::parallel_for(std::size_t(0), kept_.size(), [&](std::size_t i) {
        auto* to = merged.triangles.data() + first[i];
        for (const auto& t : kept_[i]) *to++ = {order[t[0]], order[t[1]], order[t[2]]};
        std::vector<std::array<std::uint32_t, 3>>().swap(kept_[i]);
    });
    if (frozen_) {
        std::vector<char> f;
        f.reserve(input_of.size());
        for (auto v : input_of) f.push_back((*frozen_)[v]);
        *frozen_ = std::move(f);
    }
    out = std::move(merged); // `out` may be the round's input: nothing reads it from here
}

// One round (BlockRound) from `mesh` into `out`; returns the collapses made.
std::size_t reduce_round(const Mesh& mesh, Mesh& out, const ReduceOptions& opt, std::vector<char>* frozen, float shift,
                         double q, LocalIds& local_ids, const Progress& progress) {
    BlockRound round(mesh, opt, frozen, local_ids);
    round.cut(shift);
    const std::size_t collapses = round.reduce(round.stop_key(q), progress);
    round.merge(out);
    return collapses;
}

} // namespace

// Rounds of reduce_round (the first reading the input, not a copy of it), the grid shifted by
// half a block each time so that a round's block borders lie inside the next round's blocks,
// while the mesh is large and a round removes a good share of it; then one queue over the
// whole, now much lighter mesh, in the order of the paper, which takes whatever the rounds
// left (borders included) and runs until no vertex can go. So the rounds apply only without a
// face target.
DecimateStats reduce_blocked(const Mesh& input, Mesh& mesh, const ReduceOptions& opt, const std::vector<char>* frozen,
                             const Progress& progress) {
    const std::size_t nf = input.face_count();
    if (opt.target_faces > 0 || nf < kBlockedFrom) {
        mesh = input;
        return reduce_once(mesh, opt, frozen, progress);
    }
    std::vector<char> fz;
    if (frozen) fz = *frozen;
    std::size_t collapses = 0;
    LocalIds local_ids;
    // The first round reads the input itself (its blocks are copies already), the next ones
    // the mesh the round before made. The rounds report up to 0.8, the last queue the rest.
    for (int round = 0; (round == 0 ? input : mesh).face_count() >= kRoundsDownTo; ++round) {
        const Mesh& from = round == 0 ? input : mesh;
        const std::size_t before = from.face_count();
        const Progress part = progress.part(std::min(0.8, 0.4 * round), std::min(0.8, 0.4 * (round + 1)));
        collapses += reduce_round(from, mesh, opt, frozen ? &fz : nullptr, round % 2 ? 0.5f : 0.0f, kBlockQuantile,
                                  local_ids, part);
        if (mesh.face_count() > before - before / 8) break; // under an eighth: the rest in one queue
    }
    DecimateStats st = reduce_once(mesh, opt, frozen ? &fz : nullptr, progress.part(0.8, 1.0));
    st.faces_before = nf;
    st.collapses += collapses;
    return st;
}

} // namespace cm::decimate
