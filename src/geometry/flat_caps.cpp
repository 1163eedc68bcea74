#include "geometry/flat_caps.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace cm {
namespace {

using Tri = std::array<std::uint32_t, 3>;

std::uint64_t key(std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; }

Vec3d normal_of(const Mesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const Vec3d pa(m.positions[a]);
    return cross(Vec3d(m.positions[b]) - pa, Vec3d(m.positions[c]) - pa);
}

// Twice the area against the longest edge's squared length: under kFlatCapHeight a cap.
bool flat(const Mesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const Vec3d pa(m.positions[a]), pb(m.positions[b]), pc(m.positions[c]);
    const double l = std::max({dot(pb - pa, pb - pa), dot(pc - pb, pc - pb), dot(pa - pc, pa - pc)});
    return length(cross(pb - pa, pc - pa)) <= kFlatCapHeight * l;
}

// The corner opposite the face's longest edge.
int widest_corner(const Mesh& m, const Tri& t) {
    int best = 0;
    double longest = -1;
    for (int k = 0; k < 3; ++k) {
        const Vec3d e = Vec3d(m.positions[t[std::size_t(k + 2) % 3]]) - Vec3d(m.positions[t[std::size_t(k + 1) % 3]]);
        const double l = dot(e, e);
        if (l > longest) longest = l, best = k;
    }
    return best;
}

int corner_of(const Tri& t, std::uint32_t v) { return t[0] == v ? 0 : t[1] == v ? 1 : 2; }

bool repeats(const Tri& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; }

class Flipper {
public:
    explicit Flipper(Mesh& m) : m_(m) {
        edges_.reserve(m.triangles.size() * 3);
        for (std::uint32_t f = 0; f < m.triangles.size(); ++f)
            for (int k = 0; k < 3; ++k)
                edges_[key(m.triangles[f][std::size_t(k)], m.triangles[f][std::size_t(k + 1) % 3])] = f;
    }

    // Flips cap f's long edge with the face across it; false when no valid flip exists.
    bool flip(std::uint32_t f) {
        const Tri tf = m_.triangles[f];
        const int k = widest_corner(m_, tf);
        const std::uint32_t mid = tf[std::size_t(k)], a = tf[std::size_t(k + 1) % 3], b = tf[std::size_t(k + 2) % 3];
        const auto across = edges_.find(key(b, a));
        if (across == edges_.end()) return false;
        const std::uint32_t g = across->second;
        const Tri tg = m_.triangles[g];
        const std::uint32_t d = tg[std::size_t(corner_of(tg, a) + 1) % 3];
        if (d == mid || edges_.count(key(d, mid)) || edges_.count(key(mid, d))) return false;
        if (flat(m_, a, d, mid) || flat(m_, d, b, mid)) return false;
        const Vec3d ng = normal_of(m_, tg[0], tg[1], tg[2]);
        if (dot(normal_of(m_, a, d, mid), ng) <= 0 || dot(normal_of(m_, d, b, mid), ng) <= 0) return false;
        if (!m_.corner_uvs.empty() && !flip_corner_uvs(f, g, tf, tg, a, b, mid, d)) return false;
        m_.triangles[f] = {a, d, mid};
        m_.triangles[g] = {d, b, mid};
        edges_.erase(key(a, b));
        edges_.erase(key(b, a));
        edges_[key(a, d)] = f;
        edges_[key(b, mid)] = g;
        edges_[key(d, mid)] = f;
        edges_[key(mid, d)] = g;
        return true;
    }

private:
    // The new faces' corner UVs, when the shared edge is no seam (both faces on one chart).
    bool flip_corner_uvs(std::uint32_t f, std::uint32_t g, const Tri& tf, const Tri& tg, std::uint32_t a,
                         std::uint32_t b, std::uint32_t mid, std::uint32_t d) {
        auto uv = [&](std::uint32_t face, const Tri& t, std::uint32_t v) {
            return m_.corner_uvs[3 * std::size_t(face) + std::size_t(corner_of(t, v))];
        };
        if (uv(f, tf, a) != uv(g, tg, a) || uv(f, tf, b) != uv(g, tg, b)) return false;
        const auto ua = uv(f, tf, a), ub = uv(f, tf, b), um = uv(f, tf, mid), ud = uv(g, tg, d);
        auto set = [&](std::uint32_t face, std::array<std::array<float, 2>, 3> c) {
            for (std::size_t i = 0; i < 3; ++i) m_.corner_uvs[3 * std::size_t(face) + i] = c[i];
        };
        set(f, {ua, ud, um});
        set(g, {ud, ub, um});
        return true;
    }

    Mesh& m_;
    std::unordered_map<std::uint64_t, std::uint32_t> edges_; // directed edge -> its face
};

std::vector<std::uint32_t> caps_of(const Mesh& m) {
    std::vector<std::uint32_t> caps;
    for (std::uint32_t f = 0; f < m.triangles.size(); ++f) {
        const Tri& t = m.triangles[f];
        if (!repeats(t) && flat(m, t[0], t[1], t[2])) caps.push_back(f);
    }
    return caps;
}

} // namespace

FlatCaps flip_flat_caps(Mesh& mesh) {
    FlatCaps r;
    std::vector<std::uint32_t> caps = caps_of(mesh);
    r.found = caps.size();
    if (caps.empty()) return r;
    Flipper flipper(mesh);
    // A flip can make a neighbouring cap flippable (its face across changed): a few rounds.
    for (int round = 0; round < 64 && !caps.empty(); ++round) {
        std::vector<std::uint32_t> left;
        for (std::uint32_t f : caps) {
            const Tri& t = mesh.triangles[f];
            if (!flat(mesh, t[0], t[1], t[2])) continue; // no longer a cap: a flip beside it changed it
            if (flipper.flip(f)) ++r.flipped;
            else left.push_back(f);
        }
        if (left.size() == caps.size()) break;
        caps.swap(left);
    }
    r.left = caps_of(mesh).size();
    return r;
}

std::size_t count_flat_caps(const Mesh& mesh) { return caps_of(mesh).size(); }

} // namespace cm
