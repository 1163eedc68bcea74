#include "vdb_mesher.h"

#include <algorithm>
#include <cmath>

#include <openvdb/tools/VolumeToMesh.h>

#include "core/error.h"

namespace cm {

openvdb::FloatGrid::Ptr hull_level_set(const Volume& vol, bool use_crossings) {
    if (!vol.occupancy) throw Error("the volume has no occupancy grid");
    const float h = float(vol.voxel_size());
    // Far values: one cell. volumeToMesh only reads the sign away from the surface, and a
    // value of one cell keeps every edge's interpolation between its two ends.
    const float far = h;
    auto tree = std::make_shared<openvdb::FloatTree>(vol.occupancy->tree(), far, -far, openvdb::TopologyCopy());
    auto grid = openvdb::FloatGrid::create(tree);
    grid->setTransform(vol.occupancy->transform().copy());
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    grid->setName("surface");
    auto acc = grid->getAccessor();
    auto occ = vol.occupancy->getConstAccessor();
    // Every grid point next to the surface: the distance to the nearest crossing on its edges.
    auto lower = [&](const openvdb::Coord& c, float d, bool inside) {
        d = std::clamp(d, 1e-4f * h, 0.999f * far);
        const float cur = std::abs(acc.getValue(c)); // far until a crossing set it
        if (d < cur) acc.setValueOn(c, inside ? -d : d);
    };
    auto crossing = [&](const openvdb::Coord& p, int a, bool p_in) {
        openvdb::Coord q = p;
        q[a] += 1;
        float t = 0.5f;
        if (use_crossings && vol.crossings) {
            const float c = vol.crossings->tree().getValue(p)[a];
            if (c >= 0.0f && c <= 1.0f) t = c;
        }
        lower(p, t * h, p_in);
        lower(q, (1.0f - t) * h, !p_in);
    };
    // The edges with differing ends all touch an inside voxel of a leaf (volume.h).
    std::vector<openvdb::Coord> inside;
    for (auto it = vol.occupancy->tree().cbeginLeaf(); it; ++it)
        for (auto v = it->cbeginValueOn(); v; ++v) inside.push_back(v.getCoord());
    for (const openvdb::Coord& p : inside)
        for (int a = 0; a < 3; ++a)
            for (int dir : {-1, 1}) {
                openvdb::Coord q = p;
                q[a] += dir;
                if (occ.isValueOn(q)) continue;
                if (dir > 0) crossing(p, a, true);
                else crossing(q, a, false);
            }
    return grid;
}

Result<Mesh, VdbMesherStats> vdb_volume_to_mesh(const Volume& vol, const VdbMesherOptions& opt, Progress progress) {
    progress(0.05);
    openvdb::initialize();
    auto ls = hull_level_set(vol, opt.use_crossings);
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> tris;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(*ls, points, tris, quads, opt.isovalue, opt.adaptivity, opt.relax);
    if (points.empty() || (tris.empty() && quads.empty()))
        throw Error("the volume has no surface at isovalue " + std::to_string(opt.isovalue));
    Result<Mesh, VdbMesherStats> r;
    Mesh& m = r.value;
    m.positions.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) m.positions[i] = Vec3f(points[i].x(), points[i].y(), points[i].z());
    m.triangles.reserve(tris.size() + 2 * quads.size());
    for (const auto& t : tris) m.triangles.push_back({t[0], t[1], t[2]});
    for (const auto& q : quads) {
        // The shorter diagonal.
        const Vec3f d02 = m.positions[q[0]] - m.positions[q[2]], d13 = m.positions[q[1]] - m.positions[q[3]];
        if (dot(d02, d02) <= dot(d13, d13)) {
            m.triangles.push_back({q[0], q[1], q[2]});
            m.triangles.push_back({q[0], q[2], q[3]});
        } else {
            m.triangles.push_back({q[0], q[1], q[3]});
            m.triangles.push_back({q[1], q[2], q[3]});
        }
    }
    // volumeToMesh winds its polygons with normals into the negative side; flip to outward.
    double vol6 = 0;
    for (const auto& t : m.triangles) {
        const Vec3d a(m.positions[t[0]]), b(m.positions[t[1]]), c(m.positions[t[2]]);
        vol6 += dot(a, cross(b, c));
    }
    if (vol6 < 0)
        for (auto& t : m.triangles) std::swap(t[1], t[2]);
    VdbMesherStats& st = r.stats;
    st.quads = quads.size();
    st.triangles = tris.size();
    st.band_voxels = ls->tree().activeLeafVoxelCount();
    st.level_set_bytes = ls->tree().memUsage();
    st.refined = vol.crossings && opt.use_crossings;
    return r;
}

void VdbMesherStats::report(Metrics& m) const {
    m.count("quads", quads);
    m.count("triangles", triangles);
    m.count("level_set_bytes", level_set_bytes);
    m.flag("refined", refined);
}

void VdbMesherOptions::declare(ParamBinder& b) {
    b.add(adaptivity, ParamSpec::Float("adaptivity", 0.0, 0.0, 1.0, "",
                                       "volumeToMesh adaptivity: 0 one quad per crossed edge, towards 1 flat regions "
                                       "merge into larger polygons"));
    b.add(isovalue, ParamSpec::Float("isovalue", 0.0, -1e9, 1e9, "world units",
                                     "surface level: 0 the hull, positive grows it, negative shrinks it (beyond one "
                                     "cell the level set has no more detail)"));
    b.add(use_crossings, ParamSpec::Bool("crossings", true,
                                         "build the level set from the exact crossings (false: every crossing at its "
                                         "edge midpoint)"));
    b.add(relax, ParamSpec::Bool("relax", true,
                                 "volumeToMesh relaxDisorientedTriangles: smooth triangles whose normals disagree "
                                 "with the level set's gradient (adaptive meshes)"));
}

} // namespace cm
