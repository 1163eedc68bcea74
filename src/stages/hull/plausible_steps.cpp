#include "plausible_steps.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "geometry/silhouette_field.h"

namespace cm::plausible {
Vec3d world_of(const openvdb::math::Transform& xf, const Coord& c) {
    const auto w = xf.indexToWorld(c);
    return {w.x(), w.y(), w.z()};
}

RayRaster make_raster(const View& view, const openvdb::math::Transform& xf, const openvdb::CoordBBox& box,
                      double voxel) {
    RayRaster r;
    r.cam = &view.camera;
    const SilhouetteField field(view);
    Vec3d lo = world_of(xf, box.min()), hi = world_of(xf, box.max());
    const Vec3d mid = (lo + hi) * 0.5;
    r.cp = voxel / field.pixel_size_at(mid);
    if (!view.camera.orthographic()) r.centre = view.camera.center();
    double xmin = 1e300, ymin = 1e300, xmax = -1e300, ymax = -1e300;
    for (int k = 0; k < 8; ++k) {
        const Vec3d c{(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
        if (!view.camera.orthographic() && view.camera.depth(c) <= SilhouetteField::kMinDepth)
            throw Error("view \"" + view.name +
                        "\": the camera is inside the object's box, so its lines of sight cannot be laid out");
        const Vec2d q = view.camera.project(c);
        xmin = std::min(xmin, q.x), xmax = std::max(xmax, q.x);
        ymin = std::min(ymin, q.y), ymax = std::max(ymax, q.y);
    }
    // Grid point (0,0,0) projects to a cell centre, so axis-aligned columns never
    // straddle two cells.
    const Vec2d o = view.camera.project(world_of(xf, Coord(0, 0, 0)));
    r.x0 = o.x + (std::floor((xmin - o.x) / r.cp) - 1.5) * r.cp;
    r.y0 = o.y + (std::floor((ymin - o.y) / r.cp) - 1.5) * r.cp;
    const double cw = std::ceil((xmax - r.x0) / r.cp) + 2, ch = std::ceil((ymax - r.y0) / r.cp) + 2;
    if (!(cw * ch < 2.5e8))
        throw Error("view \"" + view.name + "\": its line-of-sight raster would have " + std::to_string(cw * ch) +
                    " cells (a perspective camera very close to the object)");
    r.w = int(cw), r.h = int(ch);
    r.gap = field.drop_axis() >= 0 ? 1.5 * voxel : 3.0 * voxel;
    return r;
}

// 3x3 box passes over a raster, normalised over the cells not `masked` (all when null);
// masked cells keep their value.
void box_blur(std::vector<float>& f, const std::vector<char>* masked, int w, int h, int passes) {
    std::vector<float> tmp(f.size());
    for (int k = 0; k < passes; ++k) {
        tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
            for (int j = rows.begin(); j != rows.end(); ++j)
                for (int i = 0; i < w; ++i) {
                    const std::size_t c = std::size_t(j) * w + i;
                    if (masked && (*masked)[c]) {
                        tmp[c] = f[c];
                        continue;
                    }
                    float sum = 0;
                    int cnt = 0;
                    for (int dj = -1; dj <= 1; ++dj)
                        for (int di = -1; di <= 1; ++di) {
                            const int x = i + di, y = j + dj;
                            if (x < 0 || y < 0 || x >= w || y >= h) continue;
                            const std::size_t q = std::size_t(y) * w + x;
                            if (masked && (*masked)[q]) continue;
                            sum += f[q];
                            ++cnt;
                        }
                    tmp[c] = sum / float(cnt);
                }
        });
        f.swap(tmp);
    }
}

// 3x3 maximum passes over a raster.
void dilate(std::vector<float>& f, int w, int h, int passes) {
    std::vector<float> tmp(f.size());
    for (int k = 0; k < passes; ++k) {
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                float m = f[std::size_t(j) * w + i];
                for (int dj = -1; dj <= 1; ++dj)
                    for (int di = -1; di <= 1; ++di) {
                        const int x = i + di, y = j + dj;
                        if (x >= 0 && y >= 0 && x < w && y < h) m = std::max(m, f[std::size_t(y) * w + x]);
                    }
                tmp[std::size_t(j) * w + i] = m;
            }
        f.swap(tmp);
    }
}

// One normalised binomial pass from `src` into `dst` (same topology): each active voxel
// gets the [1 2 1]^3 weighted mean of the active voxels around it. Per leaf, its 10^3
// neighbourhood is gathered from the 27 leaves around it, then filtered separably.
void binomial_pass(const openvdb::FloatGrid& src, openvdb::FloatGrid& dst) {
    using FLeaf = openvdb::FloatTree::LeafNodeType;
    openvdb::tree::LeafManager<openvdb::FloatTree> lm(dst.tree());
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, lm.leafCount()), [&](const tbb::blocked_range<std::size_t>& r) {
            constexpr int N = 10;
            std::vector<float> v(N * N * N), w(N * N * N), v2(N * N * N), w2(N * N * N);
            auto at = [](int x, int y, int z) { return (x * N + y) * N + z; };
            for (std::size_t l = r.begin(); l != r.end(); ++l) {
                FLeaf& leaf = lm.leaf(l);
                const Coord o = leaf.origin();
                const FLeaf* nb[27];
                for (int k = 0; k < 27; ++k)
                    nb[k] =
                        src.tree().probeConstLeaf(o.offsetBy((k / 9 - 1) * 8, (k / 3 % 3 - 1) * 8, (k % 3 - 1) * 8));
                for (int x = 0; x < N; ++x)
                    for (int y = 0; y < N; ++y)
                        for (int z = 0; z < N; ++z) {
                            const int gx = x - 1, gy = y - 1, gz = z - 1;
                            const int bx = gx < 0 ? 0 : (gx > 7 ? 2 : 1), by = gy < 0 ? 0 : (gy > 7 ? 2 : 1),
                                      bz = gz < 0 ? 0 : (gz > 7 ? 2 : 1);
                            const FLeaf* s = nb[bx * 9 + by * 3 + bz];
                            const openvdb::Index off = FLeaf::coordToOffset(Coord(gx & 7, gy & 7, gz & 7));
                            const bool on = s && s->isValueOn(off);
                            v[at(x, y, z)] = on ? s->getValue(off) : 0.0f;
                            w[at(x, y, z)] = on ? 1.0f : 0.0f;
                        }
                // Along x, y, then z; each pass leaves the halo of the axes still to come.
                for (int axis = 0; axis < 3; ++axis) {
                    const int sx = axis == 0 ? N * N : 0, sy = axis == 1 ? N : 0, sz = axis == 2 ? 1 : 0;
                    const int st = sx + sy + sz;
                    for (int x = axis == 0 ? 1 : 0; x < (axis == 0 ? N - 1 : N); ++x)
                        for (int y = axis == 1 ? 1 : 0; y < (axis == 1 ? N - 1 : N); ++y)
                            for (int z = axis == 2 ? 1 : 0; z < (axis == 2 ? N - 1 : N); ++z) {
                                const int c = at(x, y, z);
                                v2[c] = v[c - st] + 2 * v[c] + v[c + st];
                                w2[c] = w[c - st] + 2 * w[c] + w[c + st];
                            }
                    std::swap(v, v2);
                    std::swap(w, w2);
                }
                for (auto it = leaf.beginValueOn(); it; ++it) {
                    const Coord g = it.getCoord() - o;
                    const int c = at(g.x() + 1, g.y() + 1, g.z() + 1);
                    if (w[c] > 0) it.setValue(v[c] / w[c]);
                }
            }
        });
}

} // namespace cm::plausible
