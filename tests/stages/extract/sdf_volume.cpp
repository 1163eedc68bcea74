#include "sdf_volume.h"

namespace cm::test {

using openvdb::Coord;

// A volume on the lattice origin + h * ijk over `box`: inside where sdf < 0, crossings
// found by bisection on each edge with differing ends (from the start point, as the
// contract says), solid interior pruned into tiles.
Volume volume_from_sdf(const Sdf& sdf, const openvdb::CoordBBox& box, double h, Vec3d origin, bool refine) {
    Volume v;
    auto xf = openvdb::math::Transform::createLinearTransform(h);
    xf->postTranslate(openvdb::Vec3d(origin.x, origin.y, origin.z));
    v.occupancy = openvdb::BoolGrid::create(false);
    v.occupancy->setTransform(xf);
    auto world = [&](const Coord& p) { return origin + Vec3d(p.x(), p.y(), p.z()) * h; };
    auto acc = v.occupancy->getAccessor();
    for (auto it = box.begin(); it; ++it)
        if (sdf(world(*it)) < 0) acc.setValueOn(*it, true);
    if (refine) {
        v.crossings = openvdb::Vec3fGrid::create(openvdb::Vec3f(-1.0f));
        v.crossings->setTransform(xf->copy());
        auto cacc = v.crossings->getAccessor();
        for (auto it = v.occupancy->cbeginValueOn(); it; ++it) {
            const Coord p = it.getCoord();
            for (int a = 0; a < 3; ++a)
                for (int dir : {-1, 1}) {
                    Coord q = p;
                    q[a] += dir;
                    if (acc.isValueOn(q)) continue;
                    const Coord s = dir > 0 ? p : q; // edge start
                    Coord e = s;
                    e[a] += 1;
                    const Vec3d ws = world(s), we = world(e);
                    const bool s_in = sdf(ws) < 0;
                    double lo = 0, hi = 1;
                    for (int i = 0; i < 60; ++i) {
                        const double m = 0.5 * (lo + hi);
                        const bool m_in = sdf(ws + (we - ws) * m) < 0;
                        (m_in == s_in ? lo : hi) = m;
                    }
                    openvdb::Vec3f c = cacc.getValue(s);
                    c[a] = float(0.5 * (lo + hi));
                    cacc.setValueOn(s, c);
                }
        }
    }
    v.occupancy->tree().prune();
    return v;
}

void add_sdf_normals(Volume& v, const Sdf& sdf) {
    const char* names[3] = {"normal_x", "normal_y", "normal_z"};
    const auto& xf = v.transform();
    for (int a = 0; a < 3; ++a) {
        auto g = openvdb::Vec3fGrid::create(openvdb::Vec3f(0.0f));
        g->setTransform(xf.copy());
        g->setName(names[a]);
        auto acc = g->getAccessor();
        for (auto it = v.crossings->cbeginValueOn(); it; ++it) {
            const float t = (*it)[a];
            if (t < 0) continue;
            openvdb::Vec3d ip = it.getCoord().asVec3d();
            ip[a] += t;
            const openvdb::Vec3d w = xf.indexToWorld(ip);
            const Vec3d p{w.x(), w.y(), w.z()};
            const double e = 1e-5 * v.voxel_size();
            Vec3d grad;
            for (int k = 0; k < 3; ++k) {
                Vec3d lo = p, hi = p;
                lo[k] -= e;
                hi[k] += e;
                grad[k] = (sdf(hi) - sdf(lo)) / (2 * e);
            }
            const Vec3d n = normalize(grad);
            acc.setValueOn(it.getCoord(), openvdb::Vec3f(float(n.x), float(n.y), float(n.z)));
        }
        v.extra.push_back(g);
    }
}

} // namespace cm::test
