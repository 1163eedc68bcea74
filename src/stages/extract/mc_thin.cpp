#include "mc_thin.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_set>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "geometry/mesh_intersect.h"

namespace cm::mc {

using openvdb::Coord;

/// Points made inside so that thin parts (inside intervals on edges whose ends are both
/// outside) survive: for each such edge, its end nearer to the interval. The value is the
/// offset (in cells, per axis) from the point to the near face of its thin part: vertices on
/// the point's other edges, about which nothing is known, are moved there so the part keeps
/// its thickness instead of reaching back to the grid point.
/// An edge next to the resolved solid (a cell around it has an inside corner) is most often
/// the body's own surface bulging between two grid points, which the body's surface already
/// covers to within the cell; promoting a point there would raise a spike. Such edges are
/// promoted only when they link a thin part found away from the solid back to it (26-connected
/// to a promoted point), so a finger thinner than a cell stays attached to its hand.
FlipGrid::Ptr promote_thin(const Volume& vol, const openvdb::Vec3fGrid& enter, const openvdb::Vec3fGrid& leave,
                           std::size_t& count) {
    auto flips = FlipGrid::create(openvdb::Vec3f(0.0f));
    flips->setTransform(vol.occupancy->transform().copy());
    auto facc = flips->getAccessor();
    auto oacc = vol.occupancy->getConstAccessor();
    auto lacc = leave.getConstAccessor();
    auto promote = [&](const Coord& q, const openvdb::Vec3f& offset) {
        openvdb::Vec3f o = facc.getValue(q);
        if (!facc.isValueOn(q)) ++count;
        for (int a = 0; a < 3; ++a)
            if (offset[a] != 0.0f) o[a] = offset[a];
        facc.setValueOn(q, o);
    };
    std::map<Coord, openvdb::Vec3f> near; // candidate point -> offset, for edges next to the solid
    std::vector<Coord> frontier;
    for (auto it = enter.cbeginValueOn(); it; ++it) {
        if (!it.isVoxelValue()) continue;
        const Coord p = it.getCoord();
        const openvdb::Vec3f t0 = *it, t1 = lacc.getValue(p);
        for (int a = 0; a < 3; ++a) {
            if (!(t0[a] >= 0.0f && t1[a] <= 1.0f && t0[a] < t1[a])) continue;
            Coord q = p;
            openvdb::Vec3f offset(0.0f);
            if (t0[a] > 1.0f - t1[a]) {
                q[a] += 1;
                offset[a] = t1[a] - 1.0f;
            } else {
                offset[a] = t0[a];
            }
            bool v = false;
            if (oacc.probeValue(q, v) && v) continue; // inside already (not expected)
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            bool near_solid = false;
            for (int i = 0; i < 18 && !near_solid; ++i) {
                Coord r = p;
                r[a] += i & 1;
                r[b] += (i >> 1) % 3 - 1;
                r[c] += (i >> 1) / 3 - 1;
                near_solid = oacc.probeValue(r, v) && v;
            }
            if (near_solid) {
                near[q][a] = offset[a];
            } else {
                promote(q, offset);
                frontier.push_back(q);
            }
        }
    }
    while (!frontier.empty()) {
        const Coord q = frontier.back();
        frontier.pop_back();
        for (int d = 0; d < 27; ++d) {
            const Coord r = q.offsetBy(d % 3 - 1, (d / 3) % 3 - 1, d / 9 - 1);
            const auto it = near.find(r);
            if (it == near.end()) continue;
            promote(r, it->second);
            near.erase(it);
            frontier.push_back(r);
        }
    }
    return flips;
}

namespace {

std::uint64_t cell_key(const Coord& c) {
    return (std::uint64_t(std::uint32_t(c.x())) * 0x9E3779B97F4A7C15ull) ^
           (std::uint64_t(std::uint32_t(c.y())) * 0xC2B2AE3D27D4EB4Full) ^
           (std::uint64_t(std::uint32_t(c.z())) * 0x165667B19E3779F9ull);
}

Coord cell_of(const openvdb::math::Transform& xform, const Vec3f& p) {
    const openvdb::Vec3d i = xform.worldToIndex(openvdb::Vec3d(p.x, p.y, p.z));
    return Coord(int(std::floor(i.x())), int(std::floor(i.y())), int(std::floor(i.z())));
}

} // namespace

std::size_t untangle_thin(Mesh& mesh, const std::vector<ShiftedVertex>& shifted, std::size_t first_extra,
                          const openvdb::math::Transform& xform) {
    if (shifted.empty()) return 0;
    // Marching Cubes faces span one cell, and a shift less than one: only faces with a vertex
    // within three cells of a shifted vertex can cross a face that moved.
    constexpr int kReach = 3;
    std::unordered_set<std::uint64_t> near;
    for (const auto& s : shifted) {
        const Coord c = cell_of(xform, s.on_edge);
        for (int dx = -kReach; dx <= kReach; ++dx)
            for (int dy = -kReach; dy <= kReach; ++dy)
                for (int dz = -kReach; dz <= kReach; ++dz) near.insert(cell_key(c.offsetBy(dx, dy, dz)));
    }
    // Each vertex's cell is looked up once (a vertex is a corner of about six faces), then
    // the faces read their corners' answers.
    const std::size_t nv = mesh.positions.size(), nf = mesh.triangles.size();
    std::vector<char> vertex_near(nv);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 8192), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v)
            vertex_near[v] = near.count(cell_key(cell_of(xform, mesh.positions[v]))) != 0;
    });
    tbb::enumerable_thread_specific<std::vector<std::uint32_t>> found;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nf, 8192), [&](const tbb::blocked_range<std::size_t>& r) {
        auto& local = found.local();
        for (std::size_t f = r.begin(); f != r.end(); ++f) {
            const auto& t = mesh.triangles[f];
            if (vertex_near[t[0]] || vertex_near[t[1]] || vertex_near[t[2]]) local.push_back(std::uint32_t(f));
        }
    });
    std::vector<std::array<std::uint32_t, 3>> sub;
    for (auto& l : found)
        for (auto f : l) sub.push_back(mesh.triangles[f]);
    std::sort(sub.begin(), sub.end()); // the same order whatever the threads did

    std::map<std::uint32_t, Vec3f> on_edge;
    for (const auto& s : shifted) on_edge.emplace(s.vertex, s.on_edge);
    std::size_t put_back = 0;
    for (;;) {
        const SelfIntersectionIndex index(sub, mesh.positions);
        const std::vector<FacePair> pairs = index.all(mesh.positions);
        if (pairs.empty()) break;
        std::vector<std::uint32_t> moved;
        for (const auto& pr : pairs)
            for (auto f : pr)
                for (auto v : sub[f]) {
                    const auto it = on_edge.find(v);
                    if (it == on_edge.end()) continue;
                    mesh.positions[v] = it->second;
                    on_edge.erase(it);
                    moved.push_back(v);
                }
        if (moved.empty()) break; // crossings of unshifted faces: not this pass's to mend
        put_back += moved.size();
        // Centre vertices of loops through a moved vertex: back to their loop's mean.
        std::sort(moved.begin(), moved.end());
        std::map<std::uint32_t, std::vector<std::uint32_t>> ring; // centre -> loop vertices
        for (const auto& t : sub)
            for (int k = 0; k < 3; ++k)
                if (t[k] >= first_extra)
                    for (int j = 1; j < 3; ++j) ring[t[k]].push_back(t[(k + j) % 3]);
        for (auto& [c, r] : ring) {
            std::sort(r.begin(), r.end());
            r.erase(std::unique(r.begin(), r.end()), r.end());
            if (!std::any_of(r.begin(), r.end(),
                             [&](std::uint32_t v) { return std::binary_search(moved.begin(), moved.end(), v); }))
                continue;
            Vec3d m{};
            for (auto v : r) m += Vec3d(mesh.positions[v]);
            mesh.positions[c] = Vec3f(m / double(r.size()));
        }
    }
    return put_back;
}

} // namespace cm::mc
