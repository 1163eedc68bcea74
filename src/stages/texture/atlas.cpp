#include "atlas.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <unordered_map>

#include "core/error.h"

namespace cm {
namespace {

// Faces across each edge: for every face, the three neighbours (or -1) through its edges.
std::vector<std::array<std::int64_t, 3>> face_neighbours(const Mesh& mesh) {
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> edges;
    edges.reserve(mesh.triangles.size() * 2);
    auto key = [](std::uint32_t a, std::uint32_t b) {
        if (a > b) std::swap(a, b);
        return (std::uint64_t(a) << 32) | b;
    };
    for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k) edges[key(mesh.triangles[f][k], mesh.triangles[f][(k + 1) % 3])].push_back(f);
    std::vector<std::array<std::int64_t, 3>> nb(mesh.triangles.size(), {-1, -1, -1});
    for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            const auto& fs = edges[key(mesh.triangles[f][k], mesh.triangles[f][(k + 1) % 3])];
            if (fs.size() != 2) continue; // a border or a non-manifold edge joins nothing
            nb[f][k] = fs[0] == f ? fs[1] : fs[0];
        }
    return nb;
}

std::vector<std::vector<std::uint32_t>> components(const std::vector<std::array<std::int64_t, 3>>& nb,
                                                   const std::vector<int>& label) {
    std::vector<std::vector<std::uint32_t>> out;
    std::vector<char> seen(label.size(), 0);
    std::vector<std::uint32_t> stack;
    for (std::uint32_t s = 0; s < label.size(); ++s) {
        if (seen[s]) continue;
        out.emplace_back();
        seen[s] = 1;
        stack.assign(1, s);
        while (!stack.empty()) {
            const std::uint32_t f = stack.back();
            stack.pop_back();
            out.back().push_back(f);
            for (std::int64_t g : nb[f])
                if (g >= 0 && !seen[std::size_t(g)] && label[std::size_t(g)] == label[f]) {
                    seen[std::size_t(g)] = 1;
                    stack.push_back(std::uint32_t(g));
                }
        }
    }
    return out;
}

// Shelf packing, tallest first; false when the rectangles do not fit.
bool pack(std::vector<AtlasChart>& charts, const std::vector<std::size_t>& order, int size) {
    int x = 0, y = 0, row = 0;
    for (std::size_t i : order) {
        AtlasChart& c = charts[i];
        if (c.w > size || c.h > size) return false;
        if (x + c.w > size) {
            y += row;
            x = 0;
            row = 0;
        }
        if (y + c.h > size) return false;
        c.x = x;
        c.y = y;
        x += c.w;
        row = std::max(row, c.h);
    }
    return true;
}

} // namespace

std::vector<std::vector<std::uint32_t>> label_components(const Mesh& mesh, const std::vector<int>& label) {
    return components(face_neighbours(mesh), label);
}

void merge_small_islands(const Mesh& mesh, std::vector<int>& face_frame, int min_faces,
                         const std::function<bool(std::uint32_t, int)>& allowed) {
    const auto nb = face_neighbours(mesh);
    for (int pass = 0; pass < 4; ++pass) {
        bool changed = false;
        for (const auto& island : components(nb, face_frame)) {
            if (int(island.size()) >= min_faces) continue;
            std::map<int, int> votes;
            for (std::uint32_t f : island)
                for (std::int64_t g : nb[f])
                    if (g >= 0 && face_frame[std::size_t(g)] != face_frame[f]) ++votes[face_frame[std::size_t(g)]];
            std::vector<std::pair<int, int>> ranked(votes.begin(), votes.end());
            std::sort(ranked.begin(), ranked.end(), [](auto& a, auto& b) { return a.second > b.second; });
            for (const auto& [frame, count] : ranked) {
                (void)count;
                if (!std::all_of(island.begin(), island.end(),
                                 [&, frame = frame](std::uint32_t f) { return allowed(f, frame); }))
                    continue;
                for (std::uint32_t f : island) face_frame[f] = frame;
                changed = true;
                break;
            }
        }
        if (!changed) break;
    }
}

Atlas build_atlas(const Mesh& mesh, const std::vector<ChartFrame>& frames, const std::vector<int>& face_frame, int size,
                  int padding) {
    Atlas atlas;
    atlas.size = size;
    atlas.padding = padding;
    atlas.face_chart.assign(mesh.triangles.size(), -1);
    for (auto& faces : label_components(mesh, face_frame)) {
        AtlasChart c;
        c.frame = face_frame[faces.front()];
        const ChartFrame& fr = frames[std::size_t(c.frame)];
        c.lo_a = c.lo_b = std::numeric_limits<double>::infinity();
        c.hi_a = c.hi_b = -std::numeric_limits<double>::infinity();
        for (std::uint32_t f : faces)
            for (int k = 0; k < 3; ++k) {
                const Vec3d p(mesh.positions[mesh.triangles[f][k]]);
                c.lo_a = std::min(c.lo_a, dot(p, fr.r));
                c.hi_a = std::max(c.hi_a, dot(p, fr.r));
                c.lo_b = std::min(c.lo_b, dot(p, fr.u));
                c.hi_b = std::max(c.hi_b, dot(p, fr.u));
            }
        c.faces = std::move(faces);
        atlas.charts.push_back(std::move(c));
    }
    double biggest = 0;
    for (const auto& c : atlas.charts) biggest = std::max({biggest, c.hi_a - c.lo_a, c.hi_b - c.lo_b});
    if (biggest <= 0) throw Error("the mesh has no extent to texture");
    auto sized = [&](double tpu) {
        for (auto& c : atlas.charts) {
            c.w = int(std::ceil((c.hi_a - c.lo_a) * tpu)) + 1 + 2 * padding;
            c.h = int(std::ceil((c.hi_b - c.lo_b) * tpu)) + 1 + 2 * padding;
        }
    };
    std::vector<std::size_t> order(atlas.charts.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    auto fits = [&](double tpu) {
        sized(tpu);
        std::stable_sort(order.begin(), order.end(),
                         [&](std::size_t a, std::size_t b) { return atlas.charts[a].h > atlas.charts[b].h; });
        return pack(atlas.charts, order, size);
    };
    double lo = 0, hi = double(size - 1 - 2 * padding) / biggest;
    if (!fits(lo))
        throw Error(std::to_string(atlas.charts.size()) + " charts do not fit a texture of " + std::to_string(size) +
                    " texels with padding " + std::to_string(padding) +
                    " (reduce the mesh first, or raise texture_size)");
    if (fits(hi)) {
        lo = hi;
    } else {
        for (int it = 0; it < 40; ++it) {
            const double mid = 0.5 * (lo + hi);
            (fits(mid) ? lo : hi) = mid;
        }
    }
    fits(lo);
    atlas.texels_per_unit = lo;
    atlas.corner_uvs.resize(mesh.triangles.size() * 3);
    for (std::size_t ci = 0; ci < atlas.charts.size(); ++ci) {
        const AtlasChart& c = atlas.charts[ci];
        const ChartFrame& fr = frames[std::size_t(c.frame)];
        for (std::uint32_t f : c.faces) {
            atlas.face_chart[f] = int(ci);
            for (int k = 0; k < 3; ++k) {
                const Vec3d p(mesh.positions[mesh.triangles[f][k]]);
                const double tx = c.x + padding + 0.5 + (dot(p, fr.r) - c.lo_a) * lo;
                const double ty = c.y + padding + 0.5 + (c.hi_b - dot(p, fr.u)) * lo;
                atlas.corner_uvs[3 * f + k] = {float(tx / size), float(1.0 - ty / size)};
            }
        }
    }
    return atlas;
}

} // namespace cm
