#include "mesh_decimate.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "geometry/mesh_intersect.h"
#include "mesh_decimate_internal.h"
#include "outline_guard.h"
#include "util/chunked_scatter.h"
#include "util/uninit_vector.h"

namespace cm {

namespace {

using decimate::Collapser;
using decimate::kPi;
using decimate::run_queue;

// The paper's candidate test and importance of vertex v: theta = the largest angle between
// two face normals around v, under `limit`; I = theta * sum_j |V_j - V|. A small multiple of
// the perimeter orders the exactly flat vertices (theta = 0) shortest-edges first.
bool importance(const Collapser& c, std::uint32_t v, double limit, float& key) {
    constexpr int kMax = 64;
    // Raw storage: an array of Vec3f would be zeroed (768 bytes) on every call.
    float normals[kMax][3];
    int n = 0;
    double L = 0;
    const Vec3f p = c.point(v);
    bool many = false;
    c.for_faces(v, [&](std::uint32_t f) {
        if (n == kMax) {
            many = true;
            return;
        }
        const Vec3f fn = c.normal(f);
        normals[n][0] = fn.x;
        normals[n][1] = fn.y;
        normals[n][2] = fn.z;
        ++n;
        const auto& t = c.tri(f);
        const std::uint32_t next = t[0] == v ? t[1] : (t[1] == v ? t[2] : t[0]);
        L += length(c.point(next) - p);
    });
    if (many || n < 3) return false;
    float min_dot = 1.0f;
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j)
            min_dot = std::min(
                min_dot, normals[i][0] * normals[j][0] + normals[i][1] * normals[j][1] + normals[i][2] * normals[j][2]);
    const double theta = std::acos(std::clamp(double(min_dot), -1.0, 1.0));
    if (!(theta < limit)) return false;
    key = float(theta * L + 1e-4 * L);
    return true;
}

// The queue of one reduction run over the collapser's mesh (see reduce_mesh), down to
// `target_faces` (0: until no vertex can go) or to the first vertex more important than
// `stop_key`; returns the collapses made. With `sweep` (and `start`), a block's pass
// instead: decimate::run_sweep up to `stop_key` (no face target).
std::size_t reduce_queue(Collapser& c, std::size_t nv, const ReduceOptions& opt, std::size_t target_faces,
                         float stop_key, const std::function<void(double)>& progress,
                         decimate::StartScores* start = nullptr, bool sweep = false) {
    const double limit = opt.max_angle_deg * kPi / 180.0;
    const double cos_limit = std::cos(limit);
    auto score = [&](std::uint32_t v, std::vector<std::uint32_t>&, float& key) { return importance(c, v, limit, key); };
    // The target: among the neighbours whose collapse passes the geometric guards, the one
    // that turns the faces least (then the nearest); topology (and the outline guard, when
    // given) is checked in that order.
    struct Option {
        double cos, len;
        std::uint32_t w;
    };
    std::vector<Option> options;
    std::vector<Collapser::OldFace> old; // v's faces before the collapse, the same for every target
    std::optional<OutlineGuard::Samples> samples;
    if (opt.outline) samples.emplace(nv, opt.outline->view_count());
    constexpr double kTie = 1e-9; // cosines closer than this are a tie, which the nearer target wins
    auto before = [](const Option& a, const Option& b) {
        if (std::fabs(a.cos - b.cos) > kTie) return a.cos > b.cos;
        return a.len < b.len;
    };
    auto passes = [&](std::uint32_t v, std::uint32_t x, const std::vector<std::uint32_t>& rv) {
        return c.topology_ok(v, x, rv) && (!opt.outline || opt.outline->keeps(c, v, x, &*samples));
    };
    auto choose = [&](std::uint32_t v, const std::vector<std::uint32_t>& rv, std::uint32_t& w, float&) {
        const Vec3d p(c.point(v));
        c.old_faces(v, old);
        // The best target first, on its own: a target whose faces turn more than the best
        // found so far is given up at the first face that shows it. Most of the time the
        // best passes the topology and the outline guard, and it is the one taken.
        Option best{-2.0, 0.0, decimate::kNone};
        for (auto x : rv) {
            double mc;
            if (!c.usable(x) || !c.geometry_ok(v, x, cos_limit, opt.max_aspect_ratio, mc, old,
                                               best.w == decimate::kNone ? -2.0 : best.cos - kTie))
                continue;
            const Option o{mc, length(Vec3d(c.point(x)) - p), x};
            if (best.w == decimate::kNone || before(o, best)) best = o;
        }
        if (best.w == decimate::kNone) return false;
        if (passes(v, best.w, rv)) {
            w = best.w;
            return true;
        }
        // Otherwise every other valid target, in order.
        options.clear();
        for (auto x : rv) {
            double mc;
            if (x == best.w || !c.usable(x) || !c.geometry_ok(v, x, cos_limit, opt.max_aspect_ratio, mc, old)) continue;
            options.push_back({mc, length(Vec3d(c.point(x)) - p), x});
        }
        std::sort(options.begin(), options.end(), before);
        for (const auto& o : options)
            if (passes(v, o.w, rv)) {
                w = o.w;
                return true;
            }
        return false;
    };
    if (sweep && start) return decimate::run_sweep(c, *start, stop_key, score, choose);
    return run_queue(
        c, nv, target_faces, stop_key, progress, score, choose, [](std::uint32_t, std::uint32_t, float) {}, start);
}

// One reduction run over the whole mesh (see reduce_mesh).
DecimateStats reduce_once(Mesh& mesh, const ReduceOptions& opt, const std::vector<char>* frozen) {
    DecimateStats st;
    st.faces_before = mesh.face_count();
    Collapser c(mesh, frozen);
    st.locked_vertices = c.locked();
    st.collapses = reduce_queue(c, mesh.positions.size(), opt, opt.target_faces, HUGE_VALF, opt.progress);
    c.finish();
    st.faces_after = mesh.face_count();
    return st;
}

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

// One round of reduce_blocked: the mesh is cut into spatial blocks (each face goes with
// its first vertex's cell) and every block is reduced on its own, in parallel, in one sweep
// (decimate::run_sweep) removing only the vertices less important than the q-quantile of
// the starting importances (in that range the order hardly matters). A vertex with faces
// in two blocks is on the open border of both, so it stays. The blocks' faces then make `out` (which may be `mesh`), over
// the vertices they still use (in input order, attributes kept: surviving vertices do not
// move); `frozen` follows. Returns the collapses made.
// `local_ids`: per thread, an array of at least the mesh's vertex count, all kNone (and left
// so), kept by the caller from round to round (filling one anew each round cost as much as
// the blocks' starting scores).
using LocalIds = tbb::enumerable_thread_specific<std::vector<std::uint32_t>>;
std::size_t reduce_round(const Mesh& mesh, Mesh& out, const ReduceOptions& opt, std::vector<char>* frozen, float shift,
                         double q, LocalIds& local_ids) {
    const std::size_t nf = mesh.face_count(), nv = mesh.positions.size();
    std::vector<std::uint32_t> cell;
    const int k = block_cells(mesh, shift, cell);
    const std::size_t ncells = std::size_t(k + 1) * (k + 1) * (k + 1);
    // Faces by block (counting sort, faces in input order within a block).
    std::vector<std::uint32_t> start, faces;
    chunked_scatter(
        nf, ncells, [&](std::size_t f, auto&& emit) { emit(cell[mesh.triangles[f][0]], std::uint32_t(f)); }, start,
        faces);
    std::vector<std::uint32_t> blocks;
    for (std::size_t b = 0; b < ncells; ++b)
        if (start[b + 1] > start[b]) blocks.push_back(std::uint32_t(b));

    // Each block: its faces and vertices as a mesh of their own (positions only: the
    // surviving vertices keep their input positions and attributes). A block's mesh and
    // collapser are built twice, once for its starting scores and once to reduce it, so
    // that no more of them are held at a time than there are threads (all of them at once
    // were the reduction's peak: on 16 M faces about as much memory as the mesh again).
    struct Block {
        Mesh mesh;
        std::vector<std::uint32_t> input; ///< input vertex of each block vertex
        std::vector<char> frozen;
        std::vector<char> locks; ///< the collapser's locks, found on the first build
        std::unique_ptr<Collapser> collapser;
        decimate::StartScores start; ///< the candidates and their importance
        std::vector<float> keys;     ///< starting importance of a sample of the candidates
    };
    std::vector<std::unique_ptr<Block>> parts(blocks.size());
    const double limit = opt.max_angle_deg * kPi / 180.0;
    auto build = [&](std::size_t i, Block& blk) {
        auto& local = local_ids.local();
        if (local.size() < nv) local.assign(nv, decimate::kNone);
        const std::uint32_t b = blocks[i];
        Mesh& sub = blk.mesh;
        auto& global = blk.input;
        sub.triangles.reserve(start[b + 1] - start[b]);
        for (std::uint32_t j = start[b]; j < start[b + 1]; ++j) {
            std::array<std::uint32_t, 3> t = mesh.triangles[faces[j]];
            for (auto& x : t) {
                if (local[x] == decimate::kNone) {
                    local[x] = std::uint32_t(global.size());
                    global.push_back(x);
                }
                x = local[x];
            }
            sub.triangles.push_back(t);
        }
        sub.positions.reserve(global.size());
        for (auto g : global) sub.positions.push_back(mesh.positions[g]);
        if (frozen)
            for (auto g : global) blk.frozen.push_back((*frozen)[g]);
        for (auto g : global) local[g] = decimate::kNone;
        blk.collapser =
            std::make_unique<Collapser>(sub, frozen ? &blk.frozen : nullptr, blk.locks.empty() ? nullptr : &blk.locks);
    };
    auto let_go = [](Block& blk) {
        blk.collapser.reset();
        blk.mesh = Mesh();
        std::vector<std::uint32_t>().swap(blk.input);
        std::vector<char>().swap(blk.frozen);
    };
    // The blocks whose starting scores set where the blocks stop: every eighth of many (spread
    // over the mesh in cell order: 64 blocks or more, enough for a quantile; fewer measured
    // a worse silhouette error), every one of fewer. The others are built once, in the pass
    // that reduces them.
    const std::size_t sample_every = blocks.size() >= 512 ? 8 : 1;
    auto score_block = [&](Block& blk) {
        const Collapser& c = *blk.collapser;
        blk.start = decimate::start_scores(
            c, blk.input.size(), [&](std::uint32_t v, auto&, float& key) { return importance(c, v, limit, key); });
    };
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size(), 1), [&](const auto& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            auto blk = std::make_unique<Block>();
            if (i % sample_every == 0) {
                build(i, *blk);
                // The queue's starting scores, computed here once: a sample of them (every
                // fourth vertex) sets where the blocks stop.
                score_block(*blk);
                for (std::uint32_t v = 0; v < blk->input.size(); v += 4)
                    if (blk->start.cand[v]) blk->keys.push_back(blk->start.keys[v]);
                blk->locks = blk->collapser->locks();
                let_go(*blk);
            }
            parts[i] = std::move(blk);
        }
    });
    // The blocks remove only the least important vertices (below a quantile of the
    // starting importances): in that range the order hardly matters, and the rest goes
    // in one queue, in the order of the paper, seams included.
    std::vector<float> all_keys;
    for (const auto& blk : parts) all_keys.insert(all_keys.end(), blk->keys.begin(), blk->keys.end());
    float stop_key = HUGE_VALF;
    if (!all_keys.empty()) {
        const std::size_t at = std::min(all_keys.size() - 1, std::size_t(q * double(all_keys.size())));
        std::nth_element(all_keys.begin(), all_keys.begin() + std::ptrdiff_t(at), all_keys.end());
        stop_key = all_keys[at];
    }
    std::vector<std::vector<std::array<std::uint32_t, 3>>> kept(blocks.size());
    std::vector<std::size_t> collapses(blocks.size(), 0);
    std::mutex progress_mutex;
    std::size_t done = 0;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size(), 1), [&](const auto& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            Block& blk = *parts[i];
            const bool scored = !blk.start.keys.empty();
            build(i, blk);
            if (!scored) score_block(blk);
            collapses[i] =
                reduce_queue(*blk.collapser, blk.mesh.positions.size(), opt, 0, stop_key, nullptr, &blk.start, true);
            auto& out = kept[i];
            for (const auto& t : blk.mesh.triangles)
                if (t[0] != decimate::kNone) out.push_back({blk.input[t[0]], blk.input[t[1]], blk.input[t[2]]});
            parts[i].reset();
            if (opt.progress) { // from one thread at a time; may throw to cancel
                std::lock_guard<std::mutex> lock(progress_mutex);
                opt.progress(double(++done) / double(blocks.size()));
            }
        }
    });

    // The blocks' faces as one mesh over the input vertices they still use (in input
    // order), then the second pass over it.
    // (the large arrays written first side by side: a fill on one thread would map their pages there)
    UninitVector<char> used(nv);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 1 << 16), [&](const auto& r) {
        std::fill(used.begin() + std::ptrdiff_t(r.begin()), used.begin() + std::ptrdiff_t(r.end()), char(0));
    });
    tbb::parallel_for(std::size_t(0), kept.size(), [&](std::size_t i) {
        for (const auto& t : kept[i])
            for (auto x : t) std::atomic_ref<char>(used[x]).store(1, std::memory_order_relaxed);
    });
    // The used vertices numbered in input order: counted per chunk, then numbered from each
    // chunk's start.
    constexpr std::size_t kChunk = std::size_t(1) << 16;
    const std::size_t nchunks = (nv + kChunk - 1) / kChunk;
    std::vector<std::size_t> chunk_start(nchunks + 1, 0);
    tbb::parallel_for(std::size_t(0), nchunks, [&](std::size_t c) {
        chunk_start[c + 1] =
            std::size_t(std::count(used.begin() + std::ptrdiff_t(c * kChunk),
                                   used.begin() + std::ptrdiff_t(std::min(nv, (c + 1) * kChunk)), char(1)));
    });
    for (std::size_t c = 0; c < nchunks; ++c) chunk_start[c + 1] += chunk_start[c];
    UninitVector<std::uint32_t> order(nv);
    std::vector<std::uint32_t> input_of(chunk_start[nchunks]);
    tbb::parallel_for(std::size_t(0), nchunks, [&](std::size_t c) {
        std::size_t at = chunk_start[c];
        for (std::size_t v = c * kChunk, e = std::min(nv, (c + 1) * kChunk); v < e; ++v)
            if (used[v]) {
                order[v] = std::uint32_t(at);
                input_of[at++] = std::uint32_t(v);
            } else {
                order[v] = decimate::kNone;
            }
    });
    UninitVector<char>().swap(used);
    Mesh merged;
    auto pick = [&](const auto& from, auto& to) {
        if (from.size() != nv) return;
        to.resize(input_of.size());
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, input_of.size(), 1 << 14), [&](const auto& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) to[i] = from[input_of[i]];
        });
    };
    pick(mesh.positions, merged.positions);
    pick(mesh.uvs, merged.uvs);
    pick(mesh.colors, merged.colors);
    pick(mesh.normals, merged.normals);
    std::vector<std::size_t> first(kept.size() + 1, 0); // where each block's faces go
    for (std::size_t i = 0; i < kept.size(); ++i) first[i + 1] = first[i] + kept[i].size();
    merged.triangles.resize(first.back());
    tbb::parallel_for(std::size_t(0), kept.size(), [&](std::size_t i) {
        auto* to = merged.triangles.data() + first[i];
        for (const auto& t : kept[i]) *to++ = {order[t[0]], order[t[1]], order[t[2]]};
        std::vector<std::array<std::uint32_t, 3>>().swap(kept[i]);
    });
    if (frozen) {
        std::vector<char> f;
        f.reserve(input_of.size());
        for (auto v : input_of) f.push_back((*frozen)[v]);
        *frozen = std::move(f);
    }
    out = std::move(merged); // `out` may be `mesh`: nothing reads it from here
    std::size_t n = 0;
    for (auto c : collapses) n += c;
    return n;
}

// reduce_once for large meshes, from `input` into `mesh`: rounds of reduce_round (the first
// reading the input, not a copy of it), the grid shifted by half a block each time so that
// a round's block borders lie inside the next round's blocks, while the mesh is large and a
// round removes a good share of it; then one queue over the whole, now much lighter mesh, in
// the order of the paper, which takes whatever the rounds left (borders included) and runs
// until no vertex can go. So the rounds apply only without a face target.
DecimateStats reduce_blocked(const Mesh& input, Mesh& mesh, const ReduceOptions& opt, const std::vector<char>* frozen) {
    const std::size_t nf = input.face_count();
    if (opt.target_faces > 0 || nf < kBlockedFrom) {
        mesh = input;
        return reduce_once(mesh, opt, frozen);
    }
    std::vector<char> fz;
    if (frozen) fz = *frozen;
    std::size_t collapses = 0;
    ReduceOptions round_opt = opt;
    LocalIds local_ids;
    // The first round reads the input itself (its blocks are copies already), the next ones
    // the mesh the round before made.
    for (int round = 0; (round == 0 ? input : mesh).face_count() >= kRoundsDownTo; ++round) {
        const Mesh& from = round == 0 ? input : mesh;
        const std::size_t before = from.face_count();
        if (opt.progress)
            round_opt.progress = [&opt, round](double f) { opt.progress(std::min(0.8, 0.4 * (round + f))); };
        collapses += reduce_round(from, mesh, round_opt, frozen ? &fz : nullptr, round % 2 ? 0.5f : 0.0f,
                                  kBlockQuantile, local_ids);
        if (mesh.face_count() > before - before / 8) break; // under an eighth: the rest in one queue
    }
    ReduceOptions last = opt;
    if (opt.progress) last.progress = [&opt](double f) { opt.progress(0.8 + 0.2 * f); };
    DecimateStats st = reduce_once(mesh, last, frozen ? &fz : nullptr);
    st.faces_before = nf;
    st.collapses += collapses;
    return st;
}

// Runs `once` (from the input into `mesh`) and, while the result has faces crossing each
// other, runs it again from the input with the input vertices frozen where those faces
// cross (the overlap of the two faces' boxes, grown by a quarter). Frozen regions only grow
// and stay as the input had them; a restart that removes no crossing (the crossing faces
// reach beyond the frozen region) doubles the growth of the next. At most kMaxRestarts
// restarts.
template <typename Once>
DecimateStats without_crossings(const Mesh& input, Mesh& mesh, bool enabled, Once&& once) {
    if (!enabled) return once(input, mesh, nullptr);
    constexpr std::size_t kMaxRestarts = 6;
    std::vector<char> frozen;
    std::size_t last = SIZE_MAX;
    float reach = 0.25f;
    for (std::size_t restart = 0;; ++restart) {
        DecimateStats st = once(input, mesh, restart ? &frozen : nullptr);
        const std::vector<FacePair> pairs = find_self_intersections(mesh);
        st.restarts = restart;
        st.crossings_left = pairs.size();
        st.frozen_vertices = std::size_t(std::count(frozen.begin(), frozen.end(), char(1)));
        if (pairs.empty() || restart == kMaxRestarts) return st;
        if (pairs.size() >= last) reach *= 2;
        last = std::min(last, pairs.size());
        // The region of each crossing: where the two faces' boxes overlap, grown a little.
        std::vector<std::array<Vec3f, 2>> boxes;
        for (const auto& pr : pairs) {
            std::array<Vec3f, 2> fb[2];
            for (int i = 0; i < 2; ++i) {
                const auto& t = mesh.triangles[pr[std::size_t(i)]];
                fb[i] = {vmin(mesh.positions[t[0]], vmin(mesh.positions[t[1]], mesh.positions[t[2]])),
                         vmax(mesh.positions[t[0]], vmax(mesh.positions[t[1]], mesh.positions[t[2]]))};
            }
            const Vec3f lo = vmax(fb[0][0], fb[1][0]), hi = vmin(fb[0][1], fb[1][1]);
            const float small = std::min(length(fb[0][1] - fb[0][0]), length(fb[1][1] - fb[1][0]));
            const float grow = reach * std::max(length(hi - lo), 0.25f * small);
            const Vec3f g(grow, grow, grow);
            boxes.push_back({lo - g, hi + g});
        }
        frozen.resize(input.positions.size(), 0);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, input.positions.size(), 4096), [&](const auto& r) {
            for (std::size_t v = r.begin(); v != r.end(); ++v) {
                const Vec3f& p = input.positions[v];
                for (const auto& b : boxes)
                    if (p.x >= b[0].x && p.x <= b[1].x && p.y >= b[0].y && p.y <= b[1].y && p.z >= b[0].z &&
                        p.z <= b[1].z) {
                        frozen[v] = 1;
                        break;
                    }
            }
        });
    }
}

} // namespace

DecimateStats reduce_mesh(const Mesh& input, Mesh& out, const ReduceOptions& opt) {
    return without_crossings(
        input, out, opt.no_crossings,
        [&](const Mesh& in, Mesh& m, const std::vector<char>* frozen) { return reduce_blocked(in, m, opt, frozen); });
}

DecimateStats reduce_mesh(Mesh& mesh, const ReduceOptions& opt) {
    const Mesh input = std::move(mesh);
    return reduce_mesh(input, mesh, opt);
}

DecimateStats quadric_decimate(const Mesh& input, Mesh& out, const QuadricOptions& opt) {
    return without_crossings(input, out, opt.no_crossings,
                             [&](const Mesh& in, Mesh& m, const std::vector<char>* frozen) {
                                 m = in;
                                 return decimate::quadric_once(m, opt, frozen);
                             });
}

DecimateStats quadric_decimate(Mesh& mesh, const QuadricOptions& opt) {
    const Mesh input = std::move(mesh);
    return quadric_decimate(input, mesh, opt);
}

} // namespace cm
