#include "mc_table.h"

#include <functional>
#include <stdexcept>
#include <string>

namespace cm::mc {
namespace {

int other_axis(int a, int which) { // the two axes other than a, in increasing order
    const int o[3][2] = {{1, 2}, {0, 2}, {0, 1}};
    return o[a][which];
}

/// Edge id from its axis and the offsets of its start along the other axes.
std::uint8_t edge_id(int axis, const int off[3]) {
    return std::uint8_t(4 * axis + (off[other_axis(axis, 0)] | (off[other_axis(axis, 1)] << 1)));
}

std::array<EdgeDef, 12> make_edges() {
    std::array<EdgeDef, 12> e{};
    for (int a = 0; a < 3; ++a)
        for (int o = 0; o < 4; ++o) {
            const int b = other_axis(a, 0), c = other_axis(a, 1);
            e[std::size_t(4 * a + o)] = {std::uint8_t(a), std::uint8_t(((o & 1) << b) | ((o >> 1) << c))};
        }
    return e;
}

std::array<std::array<std::uint8_t, 4>, 6> make_face_edges() {
    std::array<std::array<std::uint8_t, 4>, 6> fe{};
    for (int f = 0; f < 6; ++f) {
        const int n = f / 2, s = f % 2, u = other_axis(n, 0), v = other_axis(n, 1);
        int off[3] = {0, 0, 0};
        off[n] = s;
        off[v] = 0;
        fe[std::size_t(f)][0] = edge_id(u, off); // Eu0
        off[v] = 1;
        fe[std::size_t(f)][1] = edge_id(u, off); // Eu1
        off[v] = 0;
        off[u] = 0;
        fe[std::size_t(f)][2] = edge_id(v, off); // Ev0
        off[u] = 1;
        fe[std::size_t(f)][3] = edge_id(v, off); // Ev1
    }
    return fe;
}

struct P3 {
    double x, y, z;
};
P3 corner_pos(int c) { return {double(c & 1), double((c >> 1) & 1), double((c >> 2) & 1)}; }
P3 edge_mid(int e) {
    const EdgeDef& d = kEdges[std::size_t(e)];
    P3 p = corner_pos(d.corner);
    (d.axis == 0 ? p.x : d.axis == 1 ? p.y : p.z) += 0.5;
    return p;
}
P3 sub(P3 a, P3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
P3 crossp(P3 a, P3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dotp(P3 a, P3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

/// True when the two edges lie on a common face of the cell: a diagonal between their
/// vertices could then coincide with one chosen by the neighbouring cell.
bool share_face(int e1, int e2) {
    const EdgeDef a = kEdges[std::size_t(e1)], b = kEdges[std::size_t(e2)];
    for (int ax = 0; ax < 3; ++ax) {
        if (ax == a.axis || ax == b.axis) continue;
        if (((a.corner >> ax) & 1) == ((b.corner >> ax) & 1)) return true;
    }
    return false;
}

bool inside(unsigned config, int c) { return (config >> c) & 1u; }
bool crossed(unsigned config, int e) {
    const EdgeDef d = kEdges[std::size_t(e)];
    return inside(config, d.corner) != inside(config, d.corner | (1 << d.axis));
}

int face_corner(int f, int iu, int iv) {
    const int n = f / 2, s = f % 2;
    return (s << n) | (iu << other_axis(n, 0)) | (iv << other_axis(n, 1));
}

/// Any triangulation of the loop whose diagonals join edges on no common face.
bool search_triangulation(const std::vector<int>& idx, const Loop& loop,
                          std::vector<std::array<std::uint8_t, 3>>& out) {
    const std::size_t n = idx.size();
    if (n < 3) return true;
    const int a = idx.front(), b = idx.back();
    for (std::size_t k = 1; k + 1 < n; ++k) {
        const int m = idx[k];
        if (k > 1 && share_face(loop.edges[std::size_t(a)], loop.edges[std::size_t(m)])) continue;
        if (k + 2 < n && share_face(loop.edges[std::size_t(m)], loop.edges[std::size_t(b)])) continue;
        const std::size_t mark = out.size();
        out.push_back({std::uint8_t(a), std::uint8_t(m), std::uint8_t(b)});
        std::vector<int> left(idx.begin(), idx.begin() + std::ptrdiff_t(k) + 1);
        std::vector<int> right(idx.begin() + std::ptrdiff_t(k), idx.end());
        if (search_triangulation(left, loop, out) && search_triangulation(right, loop, out)) return true;
        out.resize(mark);
    }
    return false;
}

void triangulate(Loop& loop) {
    const int n = loop.size;
    if (n == 3) {
        loop.mode = Loop::Fan;
        loop.fan_apexes = 1;
        return;
    }
    for (int k = 0; k < n; ++k) {
        bool ok = true;
        for (int j = 0; j < n && ok; ++j) {
            if (j == k || j == (k + 1) % n || j == (k + n - 1) % n) continue;
            ok = !share_face(loop.edges[std::size_t(k)], loop.edges[std::size_t(j)]);
        }
        if (ok) loop.fan_apexes = std::uint16_t(loop.fan_apexes | (1u << k));
    }
    if (loop.fan_apexes) {
        loop.mode = Loop::Fan;
        return;
    }
    std::vector<int> idx(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) idx[std::size_t(i)] = i;
    std::vector<std::array<std::uint8_t, 3>> tris;
    if (search_triangulation(idx, loop, tris)) {
        loop.mode = Loop::Fixed;
        loop.tri_count = std::uint8_t(tris.size());
        for (std::size_t i = 0; i < tris.size(); ++i) loop.tris[i] = tris[i];
        return;
    }
    loop.mode = Loop::Centroid;
}

} // namespace

const std::array<EdgeDef, 12> kEdges = make_edges();
const std::array<std::array<std::uint8_t, 4>, 6> kFaceEdges = make_face_edges();

const Table& Table::get() {
    static const Table table;
    return table;
}

Table::Table() : cases_(256 * 64) {
    for (unsigned config = 0; config < 256; ++config) {
        std::uint8_t amb = 0, sep = 0;
        for (int f = 0; f < 6; ++f) {
            const bool c00 = inside(config, face_corner(f, 0, 0)), c11 = inside(config, face_corner(f, 1, 1));
            const bool c10 = inside(config, face_corner(f, 1, 0)), c01 = inside(config, face_corner(f, 0, 1));
            if (c00 == c11 && c10 == c01 && c00 != c10) {
                amb = std::uint8_t(amb | (1 << f));
                if (!c00) sep = std::uint8_t(sep | (1 << f)); // inside on (1,0),(0,1): pairing B separates
            }
        }
        ambiguous_[config] = amb;
        separating_[config] = sep;
        for (unsigned bits = 0; bits < 64; ++bits) {
            if (bits & ~unsigned(amb)) continue;
            Case& cs = cases_[config | (bits << 8)];
            cs.first_loop = std::uint32_t(loops_.size());
            cs.valid = true;
            // Oriented face segments: next[e] is the edge after e on its loop.
            int next[12], prev_count[12] = {};
            for (int& x : next) x = -1;
            for (int f = 0; f < 6; ++f) {
                const auto& fe = kFaceEdges[std::size_t(f)];
                int segs[2][2];
                int nseg = 0;
                std::vector<int> cr;
                for (int k = 0; k < 4; ++k)
                    if (crossed(config, fe[std::size_t(k)])) cr.push_back(k);
                if (cr.size() == 2) {
                    segs[0][0] = fe[std::size_t(cr[0])];
                    segs[0][1] = fe[std::size_t(cr[1])];
                    nseg = 1;
                } else if (cr.size() == 4) {
                    const bool pair_b = (bits >> f) & 1;
                    segs[0][0] = fe[0];
                    segs[0][1] = pair_b ? fe[3] : fe[2];
                    segs[1][0] = fe[1];
                    segs[1][1] = pair_b ? fe[2] : fe[3];
                    nseg = 2;
                } else if (!cr.empty()) {
                    throw std::logic_error("marching cubes table: odd crossings on a face");
                }
                const int n = f / 2;
                P3 normal{0, 0, 0};
                (n == 0 ? normal.x : n == 1 ? normal.y : normal.z) = (f % 2) ? 1.0 : -1.0;
                for (int s = 0; s < nseg; ++s) {
                    const int e1 = segs[s][0], e2 = segs[s][1];
                    const EdgeDef d1 = kEdges[std::size_t(e1)], d2 = kEdges[std::size_t(e2)];
                    // Reference corner: the corner the segment cuts off when the edges meet,
                    // else any corner of e1 (parallel edges split the face 2 | 2).
                    int ref = d1.corner;
                    for (int c1 : {int(d1.corner), d1.corner | (1 << d1.axis)})
                        for (int c2 : {int(d2.corner), d2.corner | (1 << d2.axis)})
                            if (c1 == c2) ref = c1;
                    const P3 m1 = edge_mid(e1), m2 = edge_mid(e2);
                    const double side = dotp(crossp(normal, sub(m2, m1)), sub(corner_pos(ref), m1));
                    const bool forward = inside(config, ref) ? side < 0 : side > 0;
                    const int from = forward ? e1 : e2, to = forward ? e2 : e1;
                    if (next[from] != -1) throw std::logic_error("marching cubes table: edge leaves twice");
                    next[from] = to;
                    ++prev_count[to];
                }
            }
            bool seen[12] = {};
            for (int e = 0; e < 12; ++e) {
                if (!crossed(config, e)) continue;
                if (next[e] < 0 || prev_count[e] != 1) throw std::logic_error("marching cubes table: open loop");
                if (seen[e]) continue;
                Loop loop;
                int cur = e;
                do {
                    seen[cur] = true;
                    loop.edges[loop.size++] = std::uint8_t(cur);
                    cur = next[cur];
                } while (cur != e && loop.size < 12);
                if (cur != e) throw std::logic_error("marching cubes table: loop does not close");
                triangulate(loop);
                loops_.push_back(loop);
                ++cs.loop_count;
            }
        }
    }
}

Table::Stats Table::stats() const {
    Stats s;
    for (const Case& c : cases_) s.cases += c.valid;
    s.loops = loops_.size();
    for (const Loop& l : loops_) {
        s.fan += l.mode == Loop::Fan;
        s.fixed += l.mode == Loop::Fixed;
        s.centroid += l.mode == Loop::Centroid;
        if (l.size > s.max_loop) s.max_loop = l.size;
    }
    return s;
}

} // namespace cm::mc
