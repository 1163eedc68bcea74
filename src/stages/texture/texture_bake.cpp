#include "texture_bake.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <queue>
#include <string>
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

// The steps of project_texture, numbered as they run, over what they share: the mesh being
// coloured, the views' samplers, the vertices' colours, and with a texture the faces' chart
// frames, the atlas and its image.
class Bake {
public:
    Bake(const Mesh& in, const TextureOptions& opt, TextureStats& stats)
        : mesh_(in), opt_(opt), st_(stats), sco_{opt.angle_power, opt.conflict_de} {
        if (mesh_.normals.size() != mesh_.positions.size()) mesh_.compute_normals();
        mesh_.uvs.clear();
        mesh_.corner_uvs.clear();
        mesh_.texture.reset();
        st_.textured = opt.texture;
        st_.lines_stripped = opt.clean.strokes == CleanOptions::Strokes::Strip;
        st_.balanced = opt.balance_rounds > 0;
    }

    /// Step 1: each view with a drawing: the mesh's depth through its camera, and its cleaned
    /// colours.
    void sample_views(const Views& views, const Progress& progress) {
        samplers_.reserve(views.views.size());
        st_.line_pixels.clear();
        st_.sliver_pixels.clear();
        st_.views.clear();
        for (const View& v : views.views) {
            if (v.image.empty() || v.image.width != v.width || v.image.height != v.height) continue;
            ViewSampler s;
            s.view = &v;
            s.pixel_world = v.camera.orthographic() && v.camera.scale > 0 ? 1.0 / v.camera.scale : views.finest_pixel();
            s.depth = render_depth(mesh_, v.camera, v.width, v.height);
            s.colours = clean_view_colours(v, &s.depth, 4.0 * s.pixel_world, opt_.clean);
            st_.line_pixels.push_back(s.colours.line_pixels);
            st_.sliver_pixels.push_back(s.colours.sliver_pixels);
            st_.views.push_back(v.name);
            samplers_.push_back(std::move(s));
            progress(0.05 + 0.25 * double(samplers_.size()) / double(views.views.size()));
        }
        if (samplers_.empty()) throw Error("no view has a drawing to take colours from");
    }

    /// Step 2: the views' weights, from their colour errors (view_balance.h).
    void weigh_views() {
        const ViewBalance balance = balance_views(mesh_, samplers_, sco_, opt_.balance_rounds, opt_.balance_target);
        for (std::size_t i = 0; i < samplers_.size(); ++i) samplers_[i].weight = balance.weight[i];
        st_.view_weight = balance.weight;
        st_.view_error = balance.error;
        st_.view_error_unbalanced = balance.error_before;
    }

    /// Step 3: the vertices' colours; the unseen ones from the nearest seen vertex.
    void colour_vertices() {
        const std::size_t nv = mesh_.positions.size();
        vrgb_.assign(nv, {0.5f, 0.5f, 0.5f});
        std::vector<char> vseen(nv, 0);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i < r.end(); ++i)
                vseen[i] = surface_colour(samplers_, Vec3d(mesh_.positions[i]), normalize(Vec3d(mesh_.normals[i])),
                                          sco_, vrgb_[i]);
        });
        std::size_t nseen = 0;
        for (char s : vseen) nseen += s ? 1 : 0;
        st_.seen_vertices = nv ? double(nseen) / double(nv) : 0;
        if (nseen == 0) throw Error("no view sees the mesh (do the views belong to it?)");
        spread_to_unseen(mesh_, vrgb_, vseen);
        mesh_.colors.resize(nv);
        for (std::size_t i = 0; i < nv; ++i)
            mesh_.colors[i] = {srgb_to_linear(vrgb_[i][0]), srgb_to_linear(vrgb_[i][1]), srgb_to_linear(vrgb_[i][2]),
                               1.0f};
    }

    /// Step 4: each face's chart frame: the orthographic view that sees it best, else (steeper
    /// than about 70 degrees to every view, or unseen) the axis it faces most; then the small
    /// islands join their neighbours' charts.
    void choose_frames() {
        for (const ViewSampler& s : samplers_)
            if (s.view->camera.orthographic()) {
                frames_.push_back({s.view->camera.r, s.view->camera.u, s.view->camera.d});
                frame_view_.push_back(&s);
            }
        const int nviews = int(frames_.size());
        for (const char* name : kAxisNames) {
            const Camera c = *Camera::named(name);
            frames_.push_back({c.r, c.u, c.d});
        }
        const std::size_t nf = mesh_.triangles.size();
        face_frame_.assign(nf, 0);
        centroid_.resize(nf);
        fnormal_.resize(nf);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nf), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t f = r.begin(); f < r.end(); ++f) face_frame_[f] = frame_of(std::uint32_t(f), nviews);
        });
        merge_small_islands(mesh_, face_frame_, opt_.min_island_faces, [&](std::uint32_t f, int frame) {
            const double c = dot(fnormal_[f], -frames_[std::size_t(frame)].d);
            if (frame < nviews) return c > 0.25 && visible_in(*frame_view_[std::size_t(frame)], centroid_[f], c);
            return c > 0.4;
        });
    }

    /// Step 5: the charts packed into the atlas.
    void pack_atlas() {
        atlas_ = build_atlas(mesh_, frames_, face_frame_, opt_.texture_size, opt_.padding);
        st_.charts = atlas_.charts.size();
        st_.texels_per_unit = atlas_.texels_per_unit;
    }

    /// Step 6: every texel whose centre lies in a triangle: the colour of its surface point.
    void bake_texels() {
        const int size = opt_.texture_size;
        img_ = std::make_shared<Image>();
        img_->width = img_->height = size;
        img_->channels = 4;
        img_->pixels.assign(std::size_t(size) * size * 4, 1.0f);
        covered_.assign(std::size_t(size) * size, 0);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, atlas_.charts.size(), 1),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t ci = r.begin(); ci < r.end(); ++ci)
                                  for (std::uint32_t f : atlas_.charts[ci].faces) bake_face(f);
                          });
        std::size_t ncov = 0;
        for (char c : covered_) ncov += c ? 1 : 0;
        st_.atlas_fill = double(ncov) / double(covered_.size());
    }

    /// Step 7: the padding around the charts; the mesh takes the atlas.
    void finish_texture() {
        pad_texels(*img_, covered_, opt_.padding + 1);
        mesh_.corner_uvs = std::move(atlas_.corner_uvs);
        mesh_.texture = std::move(img_);
    }

    Mesh take() { return std::move(mesh_); }

private:
    // Face f's frame (of nviews views' frames, then the axes'), its centroid and normal kept.
    int frame_of(std::uint32_t f, int nviews) {
        const auto& t = mesh_.triangles[f];
        centroid_[f] =
            (Vec3d(mesh_.positions[t[0]]) + Vec3d(mesh_.positions[t[1]]) + Vec3d(mesh_.positions[t[2]])) / 3.0;
        fnormal_[f] = face_normal(mesh_, f);
        int best = -1;
        double best_c = 0.35; // steeper than about 70 degrees: an axis chart has less stretch
        for (int k = 0; k < nviews; ++k) {
            const double c = dot(fnormal_[f], -frames_[std::size_t(k)].d);
            if (c > best_c && visible_in(*frame_view_[std::size_t(k)], centroid_[f], c)) {
                best_c = c;
                best = k;
            }
        }
        if (best < 0) {
            double bc = -2;
            for (int k = 0; k < kAxes; ++k) {
                const double c = dot(fnormal_[f], -frames_[std::size_t(nviews + k)].d);
                if (c > bc) {
                    bc = c;
                    best = nviews + k;
                }
            }
        }
        return best;
    }

    // The texels of face f (charts are apart in the atlas: threads baking different charts
    // write different texels).
    void bake_face(std::uint32_t f) {
        const int size = opt_.texture_size;
        const auto& t = mesh_.triangles[f];
        double tx[3], ty[3];
        for (int k = 0; k < 3; ++k) {
            tx[k] = atlas_.corner_uvs[3 * f + k][0] * size;
            ty[k] = (1.0 - atlas_.corner_uvs[3 * f + k][1]) * size;
        }
        const double area = (tx[1] - tx[0]) * (ty[2] - ty[0]) - (tx[2] - tx[0]) * (ty[1] - ty[0]);
        if (std::abs(area) < 1e-12) return;
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
                    p += Vec3d(mesh_.positions[t[k]]) * b[k];
                    n += Vec3d(mesh_.normals[t[k]]) * b[k];
                }
                if (!surface_colour(samplers_, p, normalize(n), sco_, c))
                    for (int k = 0; k < 3; ++k)
                        for (int ch = 0; ch < 3; ++ch) c[ch] += float(b[k]) * vrgb_[t[k]][ch];
                const std::size_t i = std::size_t(y) * size + x;
                for (int ch = 0; ch < 3; ++ch) img_->pixels[i * 4 + ch] = c[ch];
                covered_[i] = 1;
            }
    }

    Mesh mesh_;
    const TextureOptions& opt_;
    TextureStats& st_;
    const SurfaceColourOptions sco_;
    std::vector<ViewSampler> samplers_;
    std::vector<std::array<float, 3>> vrgb_; ///< per vertex, sRGB
    std::vector<ChartFrame> frames_;         ///< every orthographic view's own, then the six axes
    std::vector<const ViewSampler*> frame_view_;
    std::vector<int> face_frame_;
    std::vector<Vec3d> centroid_, fnormal_; ///< per face
    Atlas atlas_;
    std::shared_ptr<Image> img_;
    std::vector<char> covered_; ///< per texel: a triangle's colour is there
};

} // namespace

void TextureOptions::declare(ParamBinder& b) {
    b.add(texture, ParamSpec::Bool("texture", true, "bake a texture atlas and UVs; false: vertex colours only"));
    b.add(texture_size,
          ParamSpec::Int("texture_size", 2048, 64, 16384, "texels", "width and height of the atlas image"));
    b.add(padding, ParamSpec::Int("padding", 4, 0, 64, "texels",
                                  "free texels around each chart, filled from its border (against bleeding "
                                  "in filtering and mipmaps)"));
    clean.declare(b);
    b.add(angle_power, ParamSpec::Float("angle_power", 2, 0, 16, "",
                                        "a view's weight is cos(angle between normal and view)^angle_power"));
    b.add(conflict_de, ParamSpec::Float("conflict_de", 4, 0, 100, "delta E",
                                        "views whose colours for a point differ by much more than this are not "
                                        "averaged: the point takes the colour that costs the views least (a robust "
                                        "weighted median in CIELAB); 0: the weighted mean of the views"));
    b.add(balance_rounds,
          ParamSpec::Int("balance_rounds", 16, 0, 100, "",
                         "evaluations of the views' colour errors (each view's mean delta E at its own pixels, "
                         "ink left out, of the colour the mesh gets there) while weighting the views: every "
                         "view's pixels count alike, and when a view is over balance_target the weights are "
                         "searched; 0: every view weighs 1"));
    b.add(balance_target,
          ParamSpec::Float("balance_target", 3, 0, 100, "delta E",
                           "the mean colour error a view is held to: views over it weigh more until they are "
                           "at it, or as far over it as each other; under it, the sum of the views' errors is "
                           "what is made small. 0: the worst view's error alone"));
    b.add(min_island_faces,
          ParamSpec::Int("min_island_faces", 8, 1, 1000000, "faces",
                         "chart islands with fewer faces join a neighbouring chart where its projection allows"));
}

void TextureStats::report(Metrics& m) const {
    m.metric("seen_vertices", seen_vertices);
    if (textured) {
        m.count("charts", charts);
        m.metric("texels_per_unit", texels_per_unit);
        m.metric("atlas_fill", atlas_fill);
    }
    if (lines_stripped) {
        m.per_view("ink_pixels", views, line_pixels);
        m.per_view("paper_sliver_pixels", views, sliver_pixels);
    }
    m.per_view("view_delta_e", views, view_error);
    if (balanced) {
        m.per_view("view_weight", views, view_weight);
        m.per_view("view_delta_e_unbalanced", views, view_error_unbalanced);
    }
    if (seen_vertices < 0.5)
        m.warn("the views see only " + std::to_string(int(seen_vertices * 100)) +
               " % of the vertices; the rest take the nearest seen colour");
}

Result<Mesh, TextureStats> project_texture(const Mesh& in, const Views& views, const TextureOptions& opt,
                                           Progress progress) {
    TextureStats stats;
    Bake bake(in, opt, stats);
    bake.sample_views(views, progress);
    bake.weigh_views();
    bake.colour_vertices();
    progress(0.4);
    if (opt.texture) {
        bake.choose_frames();
        progress(0.5);
        bake.pack_atlas();
        progress(0.6);
        bake.bake_texels();
        progress(0.9);
        bake.finish_texture();
    }
    return {bake.take(), std::move(stats)};
}

} // namespace cm
