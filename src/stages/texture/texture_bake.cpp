#include "texture_bake.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "atlas.h"
#include "core/error.h"
#include "geometry/mesh_adjacency.h"
#include "render/colour.h"
#include "render/raster.h"
#include "surface_colour.h"
#include "view_balance.h"

namespace cm {
namespace {

constexpr int kAxes = 6;
const char* const kAxisNames[kAxes] = {"front", "back", "right", "left", "top", "bottom"};

// Unseen vertices take the colour of the nearest seen one along the mesh's edges.
void spread_to_unseen(const Mesh& mesh, std::vector<std::array<float, 3>>& rgb, std::vector<char>& seen) {
    const VertexAdjacency adj = build_vertex_adjacency(mesh);
    std::vector<double> dist(rgb.size(), std::numeric_limits<double>::infinity());
    using Item = std::pair<double, std::uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> q;
    for (std::uint32_t v = 0; v < rgb.size(); ++v)
        if (seen[v]) {
            dist[v] = 0;
            q.push({0.0, v});
        }
    while (!q.empty()) {
        const auto [d, v] = q.top();
        q.pop();
        if (d > dist[v]) continue;
        for (const std::uint32_t* it = adj.begin(v); it != adj.end(v); ++it) {
            const double nd = d + length(Vec3d(mesh.positions[*it]) - Vec3d(mesh.positions[v]));
            if (nd < dist[*it]) {
                dist[*it] = nd;
                rgb[*it] = rgb[v];
                q.push({nd, *it});
            }
        }
    }
}

Vec3d face_normal(const Mesh& m, std::uint32_t f) {
    const auto& t = m.triangles[f];
    const Vec3d a(m.positions[t[0]]), b(m.positions[t[1]]), c(m.positions[t[2]]);
    return normalize(cross(b - a, c - a));
}

// Texels never covered take the mean of their covered neighbours, `rounds` times; the
// rest of the image the mean colour, so mipmaps of the atlas do not fade to black.
void pad_texels(Image& img, std::vector<char>& covered, int rounds) {
    const int w = img.width, h = img.height;
    for (int r = 0; r < rounds; ++r) {
        std::vector<std::pair<std::size_t, std::array<float, 3>>> add;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const std::size_t i = std::size_t(y) * w + x;
                if (covered[i]) continue;
                std::array<float, 3> s{0, 0, 0};
                int n = 0;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int xx = x + dx, yy = y + dy;
                        if (xx < 0 || yy < 0 || xx >= w || yy >= h || !covered[std::size_t(yy) * w + xx]) continue;
                        for (int k = 0; k < 3; ++k) s[k] += img.at(xx, yy, k);
                        ++n;
                    }
                if (n) add.push_back({i, {s[0] / n, s[1] / n, s[2] / n}});
            }
        if (add.empty()) break;
        for (const auto& [i, c] : add) {
            for (int k = 0; k < 3; ++k) img.pixels[i * 4 + k] = c[k];
            covered[i] = 1;
        }
    }
    double mean[3] = {0, 0, 0};
    std::size_t n = 0;
    for (std::size_t i = 0; i < covered.size(); ++i)
        if (covered[i]) {
            for (int k = 0; k < 3; ++k) mean[k] += img.pixels[i * 4 + k];
            ++n;
        }
    for (std::size_t i = 0; i < covered.size(); ++i)
        if (!covered[i])
            for (int k = 0; k < 3; ++k) img.pixels[i * 4 + k] = n ? float(mean[k] / double(n)) : 0.5f;
}

} // namespace

Mesh project_texture(const Mesh& in, const Views& views, const TextureOptions& opt, TextureStats& stats,
                     const std::function<void(double)>& progress) {
    auto step = [&](double f) {
        if (progress) progress(f);
    };
    Mesh mesh = in;
    if (mesh.normals.size() != mesh.positions.size()) mesh.compute_normals();
    mesh.uvs.clear();
    mesh.corner_uvs.clear();
    mesh.texture.reset();

    // Each view: the mesh's depth through its camera, and its cleaned colours.
    std::vector<ViewSampler> samplers;
    samplers.reserve(views.views.size());
    stats.line_pixels.clear();
    stats.views.clear();
    for (const View& v : views.views) {
        if (v.image.empty() || v.image.width != v.width || v.image.height != v.height) continue;
        ViewSampler s;
        s.view = &v;
        s.pixel_world = v.camera.orthographic() && v.camera.scale > 0 ? 1.0 / v.camera.scale : views.finest_pixel();
        s.depth = render_depth(mesh, v.camera, v.width, v.height);
        s.colours = clean_view_colours(v, &s.depth, 4.0 * s.pixel_world, opt.clean);
        stats.line_pixels.push_back(s.colours.line_pixels);
        stats.views.push_back(v.name);
        samplers.push_back(std::move(s));
        step(0.05 + 0.25 * double(samplers.size()) / double(views.views.size()));
    }
    if (samplers.empty()) throw Error("no view has a drawing to take colours from");
    const SurfaceColourOptions sco{opt.angle_power, opt.conflict_de};
    const ViewBalance balance = balance_views(mesh, samplers, sco, opt.balance_rounds, opt.balance_target);
    for (std::size_t i = 0; i < samplers.size(); ++i) samplers[i].weight = balance.weight[i];
    stats.view_weight = balance.weight;
    stats.view_error = balance.error;
    stats.view_error_unbalanced = balance.error_before;

    // Vertex colours; the unseen ones from the nearest seen vertex.
    const std::size_t nv = mesh.positions.size();
    std::vector<std::array<float, 3>> vrgb(nv, {0.5f, 0.5f, 0.5f});
    std::vector<char> vseen(nv, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i)
            vseen[i] =
                surface_colour(samplers, Vec3d(mesh.positions[i]), normalize(Vec3d(mesh.normals[i])), sco, vrgb[i]);
    });
    std::size_t nseen = 0;
    for (char s : vseen) nseen += s ? 1 : 0;
    stats.seen_vertices = nv ? double(nseen) / double(nv) : 0;
    if (nseen == 0) throw Error("no view sees the mesh (do the views belong to it?)");
    spread_to_unseen(mesh, vrgb, vseen);
    mesh.colors.resize(nv);
    for (std::size_t i = 0; i < nv; ++i)
        mesh.colors[i] = {srgb_to_linear(vrgb[i][0]), srgb_to_linear(vrgb[i][1]), srgb_to_linear(vrgb[i][2]), 1.0f};
    step(0.4);
    if (!opt.texture) return mesh;

    // Frames: every orthographic view's own, then the six axes for faces no view sees well.
    std::vector<ChartFrame> frames;
    std::vector<const ViewSampler*> frame_view;
    for (const ViewSampler& s : samplers)
        if (s.view->camera.orthographic()) {
            frames.push_back({s.view->camera.r, s.view->camera.u, s.view->camera.d});
            frame_view.push_back(&s);
        }
    const int nviews = int(frames.size());
    for (const char* name : kAxisNames) {
        const Camera c = *Camera::named(name);
        frames.push_back({c.r, c.u, c.d});
    }
    const std::size_t nf = mesh.triangles.size();
    std::vector<int> face_frame(nf, 0);
    std::vector<Vec3d> centroid(nf), fnormal(nf);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nf), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t f = r.begin(); f < r.end(); ++f) {
            const auto& t = mesh.triangles[f];
            centroid[f] =
                (Vec3d(mesh.positions[t[0]]) + Vec3d(mesh.positions[t[1]]) + Vec3d(mesh.positions[t[2]])) / 3.0;
            fnormal[f] = face_normal(mesh, std::uint32_t(f));
            int best = -1;
            double best_c = 0.35; // steeper than about 70 degrees: an axis chart has less stretch
            for (int k = 0; k < nviews; ++k) {
                const double c = dot(fnormal[f], -frames[std::size_t(k)].d);
                if (c > best_c && visible_in(*frame_view[std::size_t(k)], centroid[f], c)) {
                    best_c = c;
                    best = k;
                }
            }
            if (best < 0) {
                double bc = -2;
                for (int k = 0; k < kAxes; ++k) {
                    const double c = dot(fnormal[f], -frames[std::size_t(nviews + k)].d);
                    if (c > bc) {
                        bc = c;
                        best = nviews + k;
                    }
                }
            }
            face_frame[f] = best;
        }
    });
    merge_small_islands(mesh, face_frame, opt.min_island_faces, [&](std::uint32_t f, int frame) {
        const double c = dot(fnormal[f], -frames[std::size_t(frame)].d);
        if (frame < nviews) return c > 0.25 && visible_in(*frame_view[std::size_t(frame)], centroid[f], c);
        return c > 0.4;
    });
    step(0.5);
    Atlas atlas = build_atlas(mesh, frames, face_frame, opt.texture_size, opt.padding);
    stats.charts = atlas.charts.size();
    stats.texels_per_unit = atlas.texels_per_unit;
    step(0.6);

    // Every texel whose centre lies in a triangle: the colour of its surface point.
    const int size = opt.texture_size;
    auto img = std::make_shared<Image>();
    img->width = img->height = size;
    img->channels = 4;
    img->pixels.assign(std::size_t(size) * size * 4, 1.0f);
    std::vector<char> covered(std::size_t(size) * size, 0);
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, atlas.charts.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t ci = r.begin(); ci < r.end(); ++ci)
                for (std::uint32_t f : atlas.charts[ci].faces) {
                    const auto& t = mesh.triangles[f];
                    double tx[3], ty[3];
                    for (int k = 0; k < 3; ++k) {
                        tx[k] = atlas.corner_uvs[3 * f + k][0] * size;
                        ty[k] = (1.0 - atlas.corner_uvs[3 * f + k][1]) * size;
                    }
                    const double area = (tx[1] - tx[0]) * (ty[2] - ty[0]) - (tx[2] - tx[0]) * (ty[1] - ty[0]);
                    if (std::abs(area) < 1e-12) continue;
                    const int x0 = std::max(0, int(std::floor(std::min({tx[0], tx[1], tx[2]}))));
                    const int x1 = std::min(size - 1, int(std::ceil(std::max({tx[0], tx[1], tx[2]}))));
                    const int y0 = std::max(0, int(std::floor(std::min({ty[0], ty[1], ty[2]}))));
                    const int y1 = std::min(size - 1, int(std::ceil(std::max({ty[0], ty[1], ty[2]}))));
                    for (int y = y0; y <= y1; ++y)
                        for (int x = x0; x <= x1; ++x) {
                            const double px = x + 0.5, py = y + 0.5;
                            double b[3];
                            for (int k = 0; k < 3; ++k) {
                                const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
                                b[k] = ((tx[k2] - tx[k1]) * (py - ty[k1]) - (ty[k2] - ty[k1]) * (px - tx[k1])) / area;
                            }
                            if (b[0] < -1e-6 || b[1] < -1e-6 || b[2] < -1e-6) continue;
                            Vec3d p(0, 0, 0), n(0, 0, 0);
                            std::array<float, 3> c{0, 0, 0};
                            for (int k = 0; k < 3; ++k) {
                                p += Vec3d(mesh.positions[t[k]]) * b[k];
                                n += Vec3d(mesh.normals[t[k]]) * b[k];
                            }
                            if (!surface_colour(samplers, p, normalize(n), sco, c))
                                for (int k = 0; k < 3; ++k)
                                    for (int ch = 0; ch < 3; ++ch) c[ch] += float(b[k]) * vrgb[t[k]][ch];
                            const std::size_t i = std::size_t(y) * size + x;
                            for (int ch = 0; ch < 3; ++ch) img->pixels[i * 4 + ch] = c[ch];
                            covered[i] = 1;
                        }
                }
        });
    std::size_t ncov = 0;
    for (char c : covered) ncov += c ? 1 : 0;
    stats.atlas_fill = double(ncov) / double(covered.size());
    step(0.9);
    pad_texels(*img, covered, opt.padding + 1);
    mesh.corner_uvs = std::move(atlas.corner_uvs);
    mesh.texture = std::move(img);
    return mesh;
}

} // namespace cm
