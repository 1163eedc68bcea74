#include "plausible_rays.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "geometry/silhouette_field.h"

namespace cm::plausible {

Lattice::Lattice(const openvdb::math::Transform& xf) {
    auto w = [&](int i, int j, int k) {
        const auto p = xf.indexToWorld(Coord(i, j, k));
        return Vec3d{p.x(), p.y(), p.z()};
    };
    o = w(0, 0, 0);
    ex = w(1, 0, 0) - o;
    ey = w(0, 1, 0) - o;
    ez = w(0, 0, 1) - o;
}

RayRaster make_raster(const View& view, const Lattice& lat, const openvdb::CoordBBox& box, double voxel) {
    RayRaster r;
    r.lat = &lat;
    const Camera& cam = view.camera;
    r.ortho = cam.orthographic();
    const SilhouetteField field(view);
    // The projection of grid indices: the view's homogeneous matrix times the lattice map.
    {
        const Vec3d cols[4] = {lat.ex, lat.ey, lat.ez, lat.o};
        for (int c = 0; c < 4; ++c) {
            // project_h is affine in p, so its value at the columns (minus the constant for the
            // direction columns) gives the matrix.
            const auto at0 = field.project_h(Vec3d{0, 0, 0});
            const auto v = field.project_h(cols[c]);
            for (int row = 0; row < 3; ++row) r.m[std::size_t(row) * 4 + c] = c < 3 ? v[row] - at0[row] : v[row];
        }
        if (r.ortho)
            for (int c = 0; c < 4; ++c) r.dm[std::size_t(c)] = c < 3 ? dot(cols[c], cam.d) : dot(cols[3], cam.d);
    }
    const Vec3d lo = lat.at(box.min()), hi = lat.at(box.max());
    const Vec3d mid = (lo + hi) * 0.5;
    r.cp = voxel / field.pixel_size_at(mid);
    if (!r.ortho) r.centre = cam.center();
    double xmin = 1e300, ymin = 1e300, xmax = -1e300, ymax = -1e300, dlo = 1e300, dhi = -1e300;
    for (int k = 0; k < 8; ++k) {
        const Vec3d c{(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
        if (!r.ortho && cam.depth(c) <= SilhouetteField::kMinDepth)
            throw Error("view \"" + view.name +
                        "\": the camera is inside the object's box, so its lines of sight cannot be laid out");
        const Vec2d q = cam.project(c);
        xmin = std::min(xmin, q.x), xmax = std::max(xmax, q.x);
        ymin = std::min(ymin, q.y), ymax = std::max(ymax, q.y);
        const double d = r.ortho ? dot(c, cam.d) : length(c - r.centre);
        dlo = std::min(dlo, d), dhi = std::max(dhi, d);
    }
    // Grid point (0,0,0) projects to a cell centre, so axis-aligned columns never
    // straddle two cells.
    const Vec2d o = cam.project(lat.o);
    r.x0 = o.x + (std::floor((xmin - o.x) / r.cp) - 1.5) * r.cp;
    r.y0 = o.y + (std::floor((ymin - o.y) / r.cp) - 1.5) * r.cp;
    const double cw = std::ceil((xmax - r.x0) / r.cp) + 2, ch = std::ceil((ymax - r.y0) / r.cp) + 2;
    if (!(cw * ch < 2.5e8))
        throw Error("view \"" + view.name + "\": its line-of-sight raster would have " + std::to_string(cw * ch) +
                    " cells (a perspective camera very close to the object)");
    r.w = int(cw), r.h = int(ch);
    // Depth keys an eighth of a cell apart; the nearest box corner is no lower bound of a
    // perspective distance (a face can be nearer), so that range starts at 0.
    r.dq = voxel / 8;
    r.dmin = r.ortho ? dlo - voxel : 0.0;
    r.dkeys = std::uint32_t(std::ceil((dhi + voxel - r.dmin) / r.dq)) + 1;
    if (r.dkeys > (1u << 28))
        throw Error("view \"" + view.name + "\": the object is too deep along its lines of sight");
    // A depth step larger than 1.5 cells (3 for oblique or perspective rays) splits a run.
    r.gap_keys = field.drop_axis() >= 0 ? 12 : 24;
    r.axis_aligned = r.ortho && field.drop_axis() >= 0;
    r.axis = r.axis_aligned ? field.drop_axis() : -1;
    return r;
}

void stable_bucket_order(const std::vector<std::uint32_t>& keys, std::uint32_t nkeys,
                         const std::vector<std::uint32_t>& in, std::vector<std::uint32_t>& out,
                         std::vector<std::uint32_t>* starts) {
    const std::size_t n = in.empty() ? keys.size() : in.size();
    out.resize(n);
    auto item = [&](std::size_t i) { return in.empty() ? std::uint32_t(i) : in[i]; };
    // Chunks of the input, each counted, then given its place in every bucket after the
    // chunks before it: stable, and each chunk fills its places in parallel.
    const std::size_t chunks = std::clamp<std::size_t>(n / (std::size_t(nkeys) * 2 + 1), 1,
                                                       std::size_t(tbb::this_task_arena::max_concurrency()) * 2);
    std::vector<std::vector<std::uint32_t>> count(chunks, std::vector<std::uint32_t>(nkeys, 0));
    auto range = [&](std::size_t c) { return std::pair{n * c / chunks, n * (c + 1) / chunks}; };
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
        auto [b, e] = range(c);
        auto& h = count[c];
        for (std::size_t i = b; i < e; ++i) ++h[keys[item(i)]];
    });
    std::uint32_t at = 0;
    if (starts) starts->assign(std::size_t(nkeys) + 1, 0);
    for (std::uint32_t k = 0; k < nkeys; ++k) {
        if (starts) (*starts)[k] = at;
        for (std::size_t c = 0; c < chunks; ++c) {
            const std::uint32_t cnt = count[c][k];
            count[c][k] = at;
            at += cnt;
        }
    }
    if (starts) (*starts)[nkeys] = at;
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
        auto [b, e] = range(c);
        auto& pos = count[c];
        for (std::size_t i = b; i < e; ++i) {
            const std::uint32_t x = item(i);
            out[pos[keys[x]]++] = x;
        }
    });
}

LeafColumns::LeafColumns(const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves,
                         const std::vector<std::size_t>& base)
    : leaves_(leaves), base_(base) {}

void LeafColumns::stacks_along(int axis) const {
    auto& order = order_[std::size_t(axis)];
    auto& stack = stack_[std::size_t(axis)];
    if (!stack.empty()) return;
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    order.resize(leaves_.leafCount());
    for (std::size_t l = 0; l < order.size(); ++l) order[l] = std::uint32_t(l);
    auto origin = [&](std::uint32_t l) { return leaves_.leaf(l).origin(); };
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        const Coord oa = origin(a), ob = origin(b);
        if (oa[a1] != ob[a1]) return oa[a1] < ob[a1];
        if (oa[a2] != ob[a2]) return oa[a2] < ob[a2];
        return oa[axis] < ob[axis];
    });
    for (std::size_t k = 0; k < order.size(); ++k)
        if (k == 0 || origin(order[k])[a1] != origin(order[k - 1])[a1] ||
            origin(order[k])[a2] != origin(order[k - 1])[a2])
            stack.push_back(k);
    stack.push_back(order.size());
}

std::uint64_t LeafColumns::column_bits(const Mask& m, int axis) {
    // Voxel offset x * 64 + y * 8 + z: word x, byte y, bit z.
    std::uint64_t out = 0;
    if (axis == 0) { // columns y * 8 + z: the words' union
        for (const std::uint64_t w : m) out |= w;
        return out;
    }
    // By word arithmetic, without a loop over the bytes: kLow is bit 0 of each byte.
    constexpr std::uint64_t kLow = 0x0101010101010101ull;
    for (int x = 0; x < 8; ++x) {
        const std::uint64_t w = m[std::size_t(x)];
        if (axis == 1) { // columns z * 8 + x: the bytes' union is the z bits
            std::uint64_t zs = w | w >> 32;
            zs |= zs >> 16;
            zs |= zs >> 8;
            // Bit z of zs to bit 0 of byte z: byte z keeps its bit z, which adding 0x7f carries
            // to bit 7.
            const std::uint64_t spread = ((zs & 0xff) * kLow) & 0x8040201008040201ull;
            out |= (((spread + 0x7f7f7f7f7f7f7f7full) >> 7) & kLow) << x;
        } else { // columns x * 8 + y: the non-empty bytes
            std::uint64_t t = w | w >> 4;
            t |= t >> 2;
            t |= t >> 1;
            // Bit 0 of byte y (set when the byte is not empty) to bit 56 + y, the products
            // landing on distinct bits.
            out |= (((t & kLow) * 0x0102040810204080ull) >> 56) << (8 * x);
        }
    }
    return out;
}

} // namespace cm::plausible
