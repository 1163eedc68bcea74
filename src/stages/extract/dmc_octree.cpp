#include "dmc_octree.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace cm {

void Qef::add(const Vec3d& p, const Vec3f& nf) {
    const Vec3d n(nf);
    const double d = dot(n, p);
    A[0] += n.x * n.x, A[1] += n.x * n.y, A[2] += n.x * n.z;
    A[3] += n.y * n.y, A[4] += n.y * n.z, A[5] += n.z * n.z;
    b += n * d;
    c += d * d;
    sum += p;
    ++count;
}

void Qef::add(const Qef& o) {
    for (int k = 0; k < 6; ++k) A[k] += o.A[k];
    b += o.b;
    c += o.c;
    sum += o.sum;
    count += o.count;
}

double Qef::error(const Vec3d& x) const {
    const Vec3d Ax{A[0] * x.x + A[1] * x.y + A[2] * x.z, A[1] * x.x + A[3] * x.y + A[4] * x.z,
                   A[2] * x.x + A[4] * x.y + A[5] * x.z};
    return std::max(0.0, dot(x, Ax) - 2 * dot(b, x) + c);
}

Qef::Result Qef::solve(const Vec3d& lo, double size, double singular_ratio) const {
    Result r;
    const Vec3d m = count ? sum / double(count) : lo + Vec3d(0.5, 0.5, 0.5) * size;
    Eigen::Matrix3d M;
    M << A[0], A[1], A[2], A[1], A[3], A[4], A[2], A[4], A[5];
    // A (x - m) = b - A m
    const Eigen::Vector3d rhs = Eigen::Vector3d(b.x, b.y, b.z) - M * Eigen::Vector3d(m.x, m.y, m.z);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(M);
    const Eigen::Vector3d ev = es.eigenvalues();
    const double top = std::max({ev[0], ev[1], ev[2], 0.0});
    // A hair inside the box, so the vertices of neighbouring boxes never coincide.
    const double margin = 1e-3;
    auto inside = [&](const Vec3d& x) {
        for (int a = 0; a < 3; ++a)
            if (x[a] < lo[a] + margin || x[a] > lo[a] + size - margin) return false;
        return true;
    };
    // The eigen-directions kept, strongest first (the solver sorts the eigenvalues up).
    int keep = 0;
    if (top > 0)
        for (int k = 2; k >= 0 && ev[k] > singular_ratio * top; --k) ++keep;
    // A minimum outside the box (a corner or crease that lies in a neighbour, or beyond
    // the surface in a thin or concave part) drops the weakest direction until it falls
    // inside: clamping it onto the box's side instead would pin the vertices of both cells
    // of a narrow groove to their common face, where their polygons cross.
    const Eigen::Matrix3d& V = es.eigenvectors();
    for (int rank = keep; rank >= 0; --rank) {
        Eigen::Vector3d y = Eigen::Vector3d::Zero();
        for (int k = 2; k > 2 - rank; --k) y += V.col(k) * (V.col(k).dot(rhs) / ev[k]);
        r.x = m + Vec3d(y[0], y[1], y[2]);
        r.rank = rank;
        if (inside(r.x)) return r;
        r.clamped = true;
    }
    for (int a = 0; a < 3; ++a) r.x[a] = std::clamp(r.x[a], lo[a] + margin, lo[a] + size - margin);
    return r;
}

namespace {

constexpr int kMaxLevel = 6;
/// A polygon around a merged vertex may turn by at most this much from its crossing's
/// normal (cosine): beyond, the merge would fold the surface.
constexpr double kMinFaceCos = 0.3;

class Octree {
public:
    Octree(DualMesh& D, double max_error, double ratio, std::vector<Index>& rep, const std::vector<char>* frozen)
        : D_(D), max_error_(max_error), ratio_(ratio), rep_(rep) {
        const std::size_t n = D.vert.size();
        next_.assign(n, kNoIndex);
        last_.resize(n);
        level_.assign(n, 0);
        stuck_.assign(n, 0);
        if (frozen && frozen->size() == n)
            for (std::size_t l = 0; l < n; ++l) stuck_[l] = (*frozen)[l] ? 1 : 0;
        for (std::size_t l = 0; l < n; ++l) last_[l] = Index(l);
        face_stamp_.assign(D.face_first.size(), 0);
        vert_stamp_.assign(n, 0);
    }

    /// One level: returns the loops merged.
    std::size_t level(int L) {
        // Roots grouped by their node at level L.
        std::vector<std::pair<openvdb::Coord, Index>> nodes;
        for (Index l = 0; l < Index(rep_.size()); ++l)
            if (rep_[l] == l) nodes.emplace_back(D_.loop_cell[l] >> L, l);
        std::sort(nodes.begin(), nodes.end(), [](const auto& a, const auto& b) {
            return a.first < b.first || (a.first == b.first && a.second < b.second);
        });
        std::size_t merged = 0;
        for (std::size_t i = 0; i < nodes.size();) {
            std::size_t j = i;
            while (j < nodes.size() && nodes[j].first == nodes[i].first) ++j;
            std::vector<Index> K;
            bool ok = true;
            for (std::size_t k = i; k < j; ++k) {
                const Index r = nodes[k].second;
                K.push_back(r);
                ok = ok && !stuck_[r] && level_[r] == L - 1;
            }
            if (ok && K.size() == 1) {
                level_[K[0]] = std::uint8_t(L);
            } else if (ok && try_merge(K, nodes[i].first, L)) {
                merged += K.size() - 1;
            } else {
                for (Index r : K) stuck_[r] = 1;
            }
            i = j;
        }
        return merged;
    }

private:
    bool try_merge(const std::vector<Index>& K, const openvdb::Coord& node, int L) {
        // 1. One vertex within the tolerance of every crossing's tangent plane.
        Qef q;
        for (Index r : K)
            for (Index m = r; m != kNoIndex; m = next_[m])
                for (Index i = D_.loop_first[m]; i < D_.loop_first[m + 1]; ++i) {
                    const Index v = D_.loop_cross[i];
                    q.add(D_.cross_pos[v], D_.cross_n[v]);
                }
        const double size = double(1 << L);
        const Vec3d lo(node.x() * size, node.y() * size, node.z() * size);
        const Qef::Result res = q.solve(lo, size, ratio_);
        // A minimum outside the node: one vertex in it cannot stand for the region (and one
        // pinned to its side makes long polygons that cut through a sheet nearby).
        if (res.clamped) return false;
        for (Index r : K)
            for (Index m = r; m != kNoIndex; m = next_[m])
                for (Index i = D_.loop_first[m]; i < D_.loop_first[m + 1]; ++i) {
                    const Index v = D_.loop_cross[i];
                    if (std::abs(dot(Vec3d(D_.cross_n[v]), res.x - D_.cross_pos[v])) > max_error_) return false;
                }
        // 2. The contraction keeps the mesh a closed 2-manifold of the same topology.
        if (!contractible(K, res.x)) return false;
        // Merge: the first root keeps the vertex.
        const Index X = K[0];
        for (std::size_t k = 1; k < K.size(); ++k) {
            const Index r = K[k];
            for (Index m = r; m != kNoIndex; m = next_[m]) rep_[m] = X;
            next_[last_[X]] = r;
            last_[X] = last_[r];
        }
        D_.vert[X] = res.x;
        level_[X] = std::uint8_t(L);
        return true;
    }

    /// Is the ring of the vertex that replaces the roots K one simple cycle, with every
    /// polygon around it facing its crossing's way?
    bool contractible(const std::vector<Index>& K, const Vec3d& x) {
        ++stamp_;
        for (Index r : K) vert_stamp_[r] = stamp_;
        constexpr Index kX = kNoIndex - 1;
        struct Path {
            Index v[4];
            int n;
        };
        std::vector<Path> paths;
        for (Index r : K)
            for (Index m = r; m != kNoIndex; m = next_[m])
                for (Index i = D_.loop_first[m]; i < D_.loop_first[m + 1]; ++i) {
                    const Index f = D_.loop_cross[i];
                    if (face_stamp_[f] == stamp_) continue;
                    face_stamp_[f] = stamp_;
                    Index poly[16];
                    int k = 0;
                    for (Index j = D_.face_first[f]; j < D_.face_first[f + 1]; ++j) {
                        Index u = rep_[D_.face_loops[j]];
                        if (vert_stamp_[u] == stamp_) u = kX;
                        if (k == 0 || poly[k - 1] != u) poly[k++] = u;
                    }
                    while (k > 1 && poly[k - 1] == poly[0]) --k;
                    if (k < 3) continue; // inside the node: it vanishes
                    int at = -1, xs = 0;
                    for (int t = 0; t < k; ++t)
                        if (poly[t] == kX) at = t, ++xs;
                    if (xs != 1 || k > 5) return false;
                    Path p{{0, 0, 0, 0}, k - 1};
                    for (int t = 1; t < k; ++t) p.v[t - 1] = poly[(at + t) % k];
                    // The polygon must not turn over (Newell normal against the crossing's).
                    Vec3d nn{};
                    for (int t = 0; t < k; ++t) {
                        const Vec3d a = poly[t] == kX ? x : D_.vert[poly[t]];
                        const Vec3d b = poly[(t + 1) % k] == kX ? x : D_.vert[poly[(t + 1) % k]];
                        nn += cross(a, b);
                    }
                    const double len = length(nn);
                    if (!(len > 0) || dot(nn, Vec3d(D_.cross_n[f])) < kMinFaceCos * len) return false;
                    paths.push_back(p);
                }
        if (paths.size() < 2) return false;
        // One simple cycle: every path's end starts exactly one other path, the chain visits
        // every path once, and no vertex occurs twice in it.
        std::vector<Index> seen;
        for (const Path& p : paths)
            for (int t = 0; t + 1 < p.n; ++t) seen.push_back(p.v[t]); // each path's vertices but its end
        std::sort(seen.begin(), seen.end());
        if (std::adjacent_find(seen.begin(), seen.end()) != seen.end()) return false;
        if (seen.size() < 3) return false;
        std::size_t cur = 0, steps = 0;
        do {
            const Index end = paths[cur].v[paths[cur].n - 1];
            std::size_t next = paths.size();
            for (std::size_t i = 0; i < paths.size(); ++i)
                if (paths[i].v[0] == end) {
                    if (next != paths.size()) return false;
                    next = i;
                }
            if (next == paths.size()) return false;
            cur = next;
            ++steps;
        } while (cur != 0 && steps <= paths.size());
        return cur == 0 && steps == paths.size();
    }

    DualMesh& D_;
    const double max_error_, ratio_;
    std::vector<Index>& rep_;
    std::vector<Index> next_, last_; ///< members of each root, as a list
    std::vector<std::uint8_t> level_, stuck_;
    std::vector<std::uint32_t> face_stamp_, vert_stamp_;
    std::uint32_t stamp_ = 0;
};

} // namespace

void merge_octree(DualMesh& D, double max_error, double singular_ratio, std::vector<Index>& rep, AdaptiveStats& st,
                  const std::vector<char>* frozen) {
    Octree tree(D, max_error, singular_ratio, rep, frozen);
    for (int L = 1; L <= kMaxLevel; ++L) {
        const std::size_t m = tree.level(L);
        if (m) st.levels = L;
        st.merged += m;
    }
}

} // namespace cm
