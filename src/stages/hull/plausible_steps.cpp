#include "plausible_steps.h"

#include <openvdb/tree/LeafManager.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>

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

// One normalised binomial pass from `src` into `dst` (same topology): each active voxel
// gets the [1 2 1]^3 weighted mean of the active voxels around it. Per leaf, its 10^3
// neighbourhood is gathered from the 27 leaves around it, then filtered separably.
void binomial_pass(const openvdb::FloatGrid& src, openvdb::FloatGrid& dst, const std::vector<char>& active) {
    using FLeaf = openvdb::FloatTree::LeafNodeType;
    openvdb::tree::LeafManager<openvdb::FloatTree> lm(dst.tree());
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, lm.leafCount()), [&](const tbb::blocked_range<std::size_t>& r) {
            constexpr int N = 10;
            std::vector<float> v(N * N * N), w(N * N * N), v2(N * N * N), w2(N * N * N);
            auto at = [](int x, int y, int z) { return (x * N + y) * N + z; };
            for (std::size_t l = r.begin(); l != r.end(); ++l) {
                if (!active[l]) continue;
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

SwellField::SwellField(const openvdb::CoordBBox& box, int f) : lo_(box.min()), f_(std::max(1, f)) {
    const Coord d = box.dim();
    nx_ = d.x() / f_ + 2, ny_ = d.y() / f_ + 2, nz_ = d.z() / f_ + 2;
    g_.assign(std::size_t(nx_) * ny_ * nz_, 0.0f);
}

void SwellField::seed(const Coord& c, float value) {
    if (!(value > 0)) return;
    const Coord q = c - lo_;
    const int i = std::clamp(int(std::lround(double(q.x()) / f_)), 0, nx_ - 1),
              j = std::clamp(int(std::lround(double(q.y()) / f_)), 0, ny_ - 1),
              k = std::clamp(int(std::lround(double(q.z()) / f_)), 0, nz_ - 1);
    seeds_.push_back({std::uint32_t((std::size_t(i) * ny_ + j) * nz_ + k), value});
    any_ = true;
}

void SwellField::settle() {
    if (seeds_.empty()) return;
    // One seed a coarse cell (the largest), then the balls.
    std::sort(seeds_.begin(), seeds_.end(), [](const auto& a, const auto& b) {
        return a.first < b.first || (a.first == b.first && a.second > b.second);
    });
    seeds_.erase(
        std::unique(seeds_.begin(), seeds_.end(), [](const auto& a, const auto& b) { return a.first == b.first; }),
        seeds_.end());
    std::vector<float> raised(g_.size(), 0.0f);
    for (const auto& [c, value] : seeds_) {
        const int i = int(c / (std::size_t(ny_) * nz_)), j = int(c / nz_ % ny_), k = int(c % nz_);
        const double rad = (double(value) + 2 * f_) / f_;
        const int ir = int(std::ceil(rad));
        for (int x = std::max(0, i - ir); x <= std::min(nx_ - 1, i + ir); ++x)
            for (int y = std::max(0, j - ir); y <= std::min(ny_ - 1, j + ir); ++y)
                for (int z = std::max(0, k - ir); z <= std::min(nz_ - 1, k + ir); ++z) {
                    const double dd = double(x - i) * (x - i) + double(y - j) * (y - j) + double(z - k) * (z - k);
                    if (dd > rad * rad) continue;
                    float& g = raised[(std::size_t(x) * ny_ + y) * nz_ + z];
                    g = std::max(g, value);
                }
    }
    seeds_.clear();
    // Two [1 2 1] passes along each axis (the balls' steps become slopes).
    std::vector<float> tmp(raised.size());
    for (int pass = 0; pass < 2; ++pass)
        for (int axis = 0; axis < 3; ++axis) {
            const std::size_t st = axis == 0 ? std::size_t(ny_) * nz_ : (axis == 1 ? std::size_t(nz_) : 1);
            const int len = axis == 0 ? nx_ : (axis == 1 ? ny_ : nz_);
            tbb::parallel_for(tbb::blocked_range<int>(0, nx_), [&](const tbb::blocked_range<int>& xs) {
                for (int x = xs.begin(); x != xs.end(); ++x)
                    for (int y = 0; y < ny_; ++y)
                        for (int z = 0; z < nz_; ++z) {
                            const std::size_t c = (std::size_t(x) * ny_ + y) * nz_ + z;
                            const int pos = axis == 0 ? x : (axis == 1 ? y : z);
                            const float a = pos > 0 ? raised[c - st] : 0.0f;
                            const float b = pos + 1 < len ? raised[c + st] : 0.0f;
                            tmp[c] = 0.25f * (a + 2 * raised[c] + b);
                        }
            });
            raised.swap(tmp);
        }
    for (std::size_t c = 0; c < g_.size(); ++c) g_[c] += raised[c];
}

float SwellField::at(const Coord& c) const {
    if (!any_) return 0.0f;
    const Coord q = c - lo_;
    const double fx = double(q.x()) / f_, fy = double(q.y()) / f_, fz = double(q.z()) / f_;
    const int i = int(std::floor(fx)), j = int(std::floor(fy)), k = int(std::floor(fz));
    if (i < 0 || j < 0 || k < 0 || i + 1 >= nx_ || j + 1 >= ny_ || k + 1 >= nz_) return 0.0f;
    const double tx = fx - i, ty = fy - j, tz = fz - k;
    double v = 0;
    for (int n = 0; n < 8; ++n) {
        const int di = n & 1, dj = (n >> 1) & 1, dk = (n >> 2) & 1;
        const double wgt = (di ? tx : 1 - tx) * (dj ? ty : 1 - ty) * (dk ? tz : 1 - tz);
        if (wgt > 0) v += wgt * g_[(std::size_t(i + di) * ny_ + (j + dj)) * nz_ + (k + dk)];
    }
    return float(v);
}

VoxelIndex::VoxelIndex(const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves,
                       const std::vector<std::size_t>& base)
    : leaves_(leaves), base_(base) {
    leaf_of_.reserve(leaves.leafCount() * 2);
    for (std::size_t l = 0; l < leaves.leafCount(); ++l) leaf_of_[key(leaves.leaf(l).origin())] = std::uint32_t(l);
}

std::size_t VoxelIndex::operator()(const Coord& c) const {
    using Leaf = openvdb::BoolTree::LeafNodeType;
    const auto it = leaf_of_.find(key(c & ~(Leaf::DIM - 1)));
    if (it == leaf_of_.end()) return npos;
    const auto& mask = leaves_.leaf(it->second).getValueMask();
    const openvdb::Index off = Leaf::coordToOffset(c);
    if (!mask.isOn(off)) return npos;
    std::size_t rank = 0;
    const openvdb::Index word = off >> 6;
    for (openvdb::Index w = 0; w < word; ++w) rank += std::size_t(__builtin_popcountll(mask.getWord<std::uint64_t>(w)));
    const std::uint64_t below = (std::uint64_t(1) << (off & 63)) - 1;
    rank += std::size_t(__builtin_popcountll(mask.getWord<std::uint64_t>(word) & below));
    return base_[it->second] + rank;
}

void loose_pieces(const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves, const std::vector<std::size_t>& base,
                  const std::vector<char>& member, const std::vector<char>& anchor, std::vector<char>& loose) {
    const std::size_t n = member.size();
    loose.assign(n, 0);
    // Union-find over the members (parent indices into the voxel numbering).
    std::vector<std::uint32_t> parent(n);
    std::vector<char> touches(n, 0);
    auto find = [&](std::uint32_t a) {
        while (parent[a] != a) {
            parent[a] = parent[parent[a]];
            a = parent[a];
        }
        return a;
    };
    std::vector<std::size_t> leaf_list; // leaves holding a member
    for (std::size_t l = 0; l < leaves.leafCount(); ++l)
        for (std::size_t i = base[l]; i < base[l + 1]; ++i)
            if (member[i]) {
                leaf_list.push_back(l);
                break;
            }
    for (std::size_t l : leaf_list)
        for (std::size_t i = base[l]; i < base[l + 1]; ++i)
            if (member[i]) parent[i] = std::uint32_t(i);
    const VoxelIndex index(leaves, base);
    for (std::size_t l : leaf_list) {
        std::size_t i = base[l];
        for (auto it = leaves.leaf(l).cbeginValueOn(); it; ++it, ++i) {
            if (!member[i]) continue;
            const Coord g = it.getCoord();
            for (int k = 0; k < 6; ++k) {
                Coord q = g;
                q[k / 2] += (k & 1) ? 1 : -1;
                const std::size_t j = index(q);
                if (j == VoxelIndex::npos) continue;
                if (anchor[j]) {
                    touches[i] = 1;
                } else if (member[j]) {
                    const std::uint32_t a = find(std::uint32_t(i)), b = find(std::uint32_t(j));
                    if (a != b) parent[std::max(a, b)] = std::min(a, b);
                }
            }
        }
    }
    for (std::size_t l : leaf_list)
        for (std::size_t i = base[l]; i < base[l + 1]; ++i)
            if (member[i] && touches[i]) touches[find(std::uint32_t(i))] = 1;
    for (std::size_t l : leaf_list)
        for (std::size_t i = base[l]; i < base[l + 1]; ++i)
            if (member[i]) loose[i] = !touches[find(std::uint32_t(i))];
}

BallField::BallField(const openvdb::CoordBBox& box, int f) : lo_(box.min()), f_(std::max(1, f)) {
    const Coord d = box.dim();
    nx_ = d.x() / f_ + 2, ny_ = d.y() / f_ + 2, nz_ = d.z() / f_ + 2;
    g_.assign(std::size_t(nx_) * ny_ * nz_, std::numeric_limits<float>::infinity());
}

void BallField::settle(double reach) {
    if (balls_.empty()) return;
    any_ = true;
    // By slabs of coarse x, each thread writing only its own slab.
    tbb::parallel_for(tbb::blocked_range<int>(0, nx_, 4), [&](const tbb::blocked_range<int>& xs) {
        for (const Ball& b : balls_) {
            const double ext = (b.radius + reach) / f_;
            const double cx = (b.centre.x() - lo_.x()) / f_, cy = (b.centre.y() - lo_.y()) / f_,
                         cz = (b.centre.z() - lo_.z()) / f_;
            const int x0 = std::max(xs.begin(), int(std::ceil(cx - ext))),
                      x1 = std::min(xs.end() - 1, int(std::floor(cx + ext)));
            if (x0 > x1) continue;
            const int y0 = std::max(0, int(std::ceil(cy - ext))), y1 = std::min(ny_ - 1, int(std::floor(cy + ext)));
            const int z0 = std::max(0, int(std::ceil(cz - ext))), z1 = std::min(nz_ - 1, int(std::floor(cz + ext)));
            for (int x = x0; x <= x1; ++x)
                for (int y = y0; y <= y1; ++y)
                    for (int z = z0; z <= z1; ++z) {
                        const double dx = x - cx, dy = y - cy, dz = z - cz;
                        const float v = float(std::sqrt(dx * dx + dy * dy + dz * dz) * f_ - b.radius);
                        float& g = g_[(std::size_t(x) * ny_ + y) * nz_ + z];
                        g = std::min(g, v);
                    }
        }
    });
    balls_.clear();
}

float BallField::at(const Coord& c) const {
    constexpr float inf = std::numeric_limits<float>::infinity();
    if (!any_) return inf;
    const Coord q = c - lo_;
    const double fx = double(q.x()) / f_, fy = double(q.y()) / f_, fz = double(q.z()) / f_;
    const int i = int(std::floor(fx)), j = int(std::floor(fy)), k = int(std::floor(fz));
    if (i < 0 || j < 0 || k < 0 || i + 1 >= nx_ || j + 1 >= ny_ || k + 1 >= nz_) return inf;
    const double tx = fx - i, ty = fy - j, tz = fz - k;
    double v = 0;
    for (int n = 0; n < 8; ++n) {
        const int di = n & 1, dj = (n >> 1) & 1, dk = (n >> 2) & 1;
        const double wgt = (di ? tx : 1 - tx) * (dj ? ty : 1 - ty) * (dk ? tz : 1 - tz);
        if (wgt <= 0) continue;
        const float g = g_[(std::size_t(i + di) * ny_ + (j + dj)) * nz_ + (k + dk)];
        if (g == inf) return inf;
        v += wgt * g;
    }
    return float(v);
}

} // namespace cm::plausible
