// The hull's projections along the grid axes (plausible_projection.h).
#include "plausible_projection.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>

namespace cm::plausible {

double Projection::count(int a0, int a1, int b0, int b1) const {
    a0 = std::max(a0 - u0, 0);
    b0 = std::max(b0 - v0, 0);
    a1 = std::min(a1 - u0, nu - 1);
    b1 = std::min(b1 - v0, nv - 1);
    if (a1 < a0 || b1 < b0) return 0.0;
    const std::size_t w = std::size_t(nv) + 1;
    const auto at = [&](int i, int j) { return double(sat[std::size_t(i) * w + std::size_t(j)]); };
    return at(a1 + 1, b1 + 1) - at(a0, b1 + 1) - at(a1 + 1, b0) + at(a0, b0);
}

namespace {

void runs(const std::vector<std::uint8_t>& in, std::size_t first, std::size_t stride, int count, int origin,
          std::vector<std::int32_t>& lo, std::vector<std::int32_t>& hi) {
    for (int i = 0; i < count;) {
        if (!in[first + std::size_t(i) * stride]) {
            ++i;
            continue;
        }
        int j = i;
        while (j + 1 < count && in[first + std::size_t(j + 1) * stride]) ++j;
        for (int t = i; t <= j; ++t) {
            lo[first + std::size_t(t) * stride] = origin + i;
            hi[first + std::size_t(t) * stride] = origin + j;
        }
        i = j + 1;
    }
}

// The three projections' inside pixels, in parallel over leaves: each leaf's voxels are
// projected into an 8 x 8 mask per axis first (bits u * 8 + v, the axes as project_hull() sets
// them), so the arrays see one store per pixel. The masks come from the leaf mask's words (word
// x, byte y, bit z): along x their union (y * 8 + z), along y each word's bytes' union
// (x * 8 + z), along z each word's non-empty bytes (x * 8 + y).
void mark_inside(const HullVoxels& vox, std::array<Projection, 3>& proj) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vox.nleaf), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t l = r.begin(); l != r.end(); ++l) {
            const LeafT& leaf = vox.leaves.leaf(l);
            const auto& mask = leaf.getValueMask();
            std::array<std::uint64_t, 3> local{};
            for (unsigned x = 0; x < 8; ++x) {
                const std::uint64_t w = mask.getWord<std::uint64_t>(x);
                if (!w) continue;
                local[0] |= w;
                std::uint64_t zs = w | w >> 32;
                zs |= zs >> 16;
                zs |= zs >> 8;
                local[1] |= (zs & 0xff) << (x * 8);
                std::uint64_t ys = 0;
                for (unsigned y = 0; y < 8; ++y)
                    if ((w >> (8 * y)) & 0xff) ys |= std::uint64_t(1) << y;
                local[2] |= ys << (x * 8);
            }
            const Coord origin = leaf.origin();
            for (std::size_t k = 0; k < 3; ++k) {
                Projection& P = proj[k];
                for (std::uint64_t bits = local[k]; bits; bits &= bits - 1) {
                    const int b = __builtin_ctzll(bits);
                    // Leaves side by side along the axis share the pixel: relaxed stores of
                    // the same value.
                    std::atomic_ref<std::uint8_t>(P.in[P.index(origin[P.u] + b / 8, origin[P.v] + b % 8)])
                        .store(1, std::memory_order_relaxed);
                }
            }
        }
    });
}

// The runs along u and v through each inside pixel, and the summed-area table.
void tabulate(Projection& P) {
    const std::size_t n = P.in.size();
    P.lo_u.assign(n, 0);
    P.hi_u.assign(n, -1);
    P.lo_v.assign(n, 0);
    P.hi_v.assign(n, -1);
    // Runs along v (rows of the array), then along u (its columns).
    tbb::parallel_for(0, P.nu, [&](int iu) { runs(P.in, std::size_t(iu) * P.nv, 1, P.nv, P.v0, P.lo_v, P.hi_v); });
    tbb::parallel_for(0, P.nv,
                      [&](int iv) { runs(P.in, std::size_t(iv), std::size_t(P.nv), P.nu, P.u0, P.lo_u, P.hi_u); });
    const std::size_t w = std::size_t(P.nv) + 1;
    P.sat.assign((std::size_t(P.nu) + 1) * w, 0);
    for (int iu = 0; iu < P.nu; ++iu)
        for (int iv = 0; iv < P.nv; ++iv)
            P.sat[std::size_t(iu + 1) * w + std::size_t(iv + 1)] =
                P.sat[std::size_t(iu) * w + std::size_t(iv + 1)] + P.sat[std::size_t(iu + 1) * w + std::size_t(iv)] -
                P.sat[std::size_t(iu) * w + std::size_t(iv)] +
                P.in[std::size_t(iu) * std::size_t(P.nv) + std::size_t(iv)];
}

} // namespace

std::array<Projection, 3> project_hull(const HullVoxels& vox) {
    std::array<Projection, 3> proj;
    for (int k = 0; k < 3; ++k) {
        Projection& P = proj[std::size_t(k)];
        P.k = k;
        P.u = k == 0 ? 1 : 0;
        P.v = k == 2 ? 1 : 2;
        P.u0 = vox.box.min()[P.u];
        P.v0 = vox.box.min()[P.v];
        P.nu = vox.box.dim()[P.u];
        P.nv = vox.box.dim()[P.v];
        P.in.assign(std::size_t(P.nu) * std::size_t(P.nv), 0);
    }
    mark_inside(vox, proj);
    for (Projection& P : proj) tabulate(P);
    return proj;
}

} // namespace cm::plausible
