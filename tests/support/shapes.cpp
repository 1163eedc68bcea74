#include "support/shapes.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <unordered_map>

namespace cm::test {

// ---- Meshes ------------------------------------------------------------------------

Mesh make_box(Vec3f lo, Vec3f hi) {
    Mesh m;
    for (int i = 0; i < 8; ++i)
        m.positions.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
    // Two outward triangles per face.
    const std::array<std::array<std::uint32_t, 4>, 6> quads = {
        {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}}};
    for (const auto& q : quads) {
        m.triangles.push_back({q[0], q[1], q[2]});
        m.triangles.push_back({q[0], q[2], q[3]});
    }
    return m;
}

std::array<float, 3> textured_box_colour(int side) {
    static const std::array<float, 3> colours[6] = {{0.9f, 0.1f, 0.1f}, {0.1f, 0.8f, 0.2f}, {0.1f, 0.2f, 0.9f},
                                                    {0.9f, 0.9f, 0.1f}, {0.1f, 0.9f, 0.9f}, {0.8f, 0.2f, 0.9f}};
    return colours[side];
}

Mesh make_textured_box(Vec3f lo, Vec3f hi) {
    Mesh m = make_box(lo, hi);
    constexpr int kBlock = 16;
    auto tex = std::make_shared<Image>();
    tex->width = 3 * kBlock;
    tex->height = 2 * kBlock;
    tex->channels = 4;
    tex->pixels.resize(std::size_t(tex->width * tex->height * 4));
    for (int y = 0; y < tex->height; ++y)
        for (int x = 0; x < tex->width; ++x) {
            const std::array<float, 3> c = textured_box_colour(y / kBlock * 3 + x / kBlock);
            for (int k = 0; k < 3; ++k) tex->at(x, y, k) = c[std::size_t(k)];
            tex->at(x, y, 3) = 1.0f;
        }
    m.texture = tex;
    // Corners well inside their block (a quarter block from its centre), v up.
    const float corner[3][2] = {{-0.25f, -0.25f}, {0.25f, -0.25f}, {0.0f, 0.25f}};
    for (std::size_t f = 0; f < m.triangles.size(); ++f) {
        const int side = int(f / 2);
        const float u0 = (float(side % 3) + 0.5f) / 3.0f, v0 = 1.0f - (float(side / 3) + 0.5f) / 2.0f;
        for (const auto& c : corner) m.corner_uvs.push_back({u0 + c[0] / 3.0f, v0 + c[1] / 2.0f});
    }
    return m;
}

Mesh make_sphere(Vec3f c, float r, int subdivisions) {
    Mesh m;
    const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
    std::vector<Vec3f> p = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                            {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
    std::vector<std::array<std::uint32_t, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                                   {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                                   {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                                   {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    for (auto& v : p) v = normalize(v);
    for (int s = 0; s < subdivisions; ++s) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            p.push_back(normalize((p[a] + p[b]) * 0.5f));
            return mid[key] = std::uint32_t(p.size() - 1);
        };
        std::vector<std::array<std::uint32_t, 3>> nf;
        for (const auto& tri : f) {
            const std::uint32_t a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]),
                                cc = midpoint(tri[2], tri[0]);
            nf.push_back({tri[0], a, cc});
            nf.push_back({tri[1], b, a});
            nf.push_back({tri[2], cc, b});
            nf.push_back({a, b, cc});
        }
        f.swap(nf);
    }
    for (auto& v : p) m.positions.push_back(c + v * r);
    m.triangles = f;
    return m;
}

void append_mesh(Mesh& into, const Mesh& part, bool flip) {
    const auto base = std::uint32_t(into.positions.size());
    into.positions.insert(into.positions.end(), part.positions.begin(), part.positions.end());
    for (auto t : part.triangles)
        into.triangles.push_back(flip ? std::array<std::uint32_t, 3>{t[0] + base, t[2] + base, t[1] + base}
                                      : std::array<std::uint32_t, 3>{t[0] + base, t[1] + base, t[2] + base});
}

Mesh make_crossing_boxes() {
    Mesh m = make_box({0, 0, 0}, {1, 1, 1});
    append_mesh(m, make_box({0.5f, 0.3f, 0.6f}, {1.5f, 1.4f, 1.7f}));
    return m;
}

Mesh make_box_with_flat_cap(Vec3f lo, Vec3f hi) {
    Mesh m = make_box(lo, hi);
    const auto [p, q, r] = m.triangles[0];
    const auto mid = std::uint32_t(m.positions.size());
    m.positions.push_back((m.positions[p] + m.positions[q]) * 0.5f);
    m.triangles[0] = {p, mid, r};
    m.triangles.push_back({mid, q, r});
    m.triangles.push_back({p, q, mid});
    return m;
}

Mesh make_lopsided() {
    Mesh m = make_sphere({0, 0, 0}, 1.0f, 4);
    append_mesh(m, make_box({0.5f, 0.5f, -0.2f}, {1.4f, 1.1f, 0.4f}));
    return m;
}

Mesh make_grid_box(float lo, float hi, int n) {
    Mesh m;
    std::map<std::array<int, 3>, std::uint32_t> index;
    auto vertex = [&](std::array<int, 3> g) {
        auto [it, fresh] = index.emplace(g, std::uint32_t(m.positions.size()));
        if (fresh) {
            const float s = (hi - lo) / float(n);
            m.positions.push_back({lo + s * float(g[0]), lo + s * float(g[1]), lo + s * float(g[2])});
        }
        return it->second;
    };
    for (int a = 0; a < 3; ++a) {
        const int ua = (a + 1) % 3, va = (a + 2) % 3; // e_u x e_v = e_a
        for (int side = 0; side < 2; ++side)
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) {
                    std::array<std::uint32_t, 4> q;
                    const int corners[4][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};
                    for (int c = 0; c < 4; ++c) {
                        std::array<int, 3> g{};
                        g[a] = side ? n : 0;
                        g[ua] = corners[c][0];
                        g[va] = corners[c][1];
                        q[c] = vertex(g);
                    }
                    if (side) {
                        m.triangles.push_back({q[0], q[1], q[2]});
                        m.triangles.push_back({q[0], q[2], q[3]});
                    } else {
                        m.triangles.push_back({q[0], q[2], q[1]});
                        m.triangles.push_back({q[0], q[3], q[2]});
                    }
                }
    }
    return m;
}

void add_radial_noise(Mesh& m, Vec3f centre, float amplitude, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-amplitude, amplitude);
    for (auto& p : m.positions) p = p + normalize(p - centre) * u(rng);
}

Views make_box_views(float lo, float hi, int width) {
    Views vs;
    const double scale = 0.8 * width / (hi - lo);
    const double mid = 0.5 * (lo + hi);
    for (const char* name : {"front", "right", "top"}) {
        View v;
        v.name = name;
        v.width = v.height = width;
        v.camera = *Camera::named(name);
        v.camera.scale = scale;
        // Put the box centre at the image centre.
        const Vec3d c{mid, mid, mid};
        v.camera.cx = 0.5 * width - scale * dot(c, v.camera.r);
        v.camera.cy = 0.5 * width + scale * dot(c, v.camera.u);
        // The box projects to the square [a, b]^2 in pixels.
        const double a = 0.5 * width - 0.5 * scale * (hi - lo), b = 0.5 * width + 0.5 * scale * (hi - lo);
        std::vector<float> cov(std::size_t(width) * width, 0.0f);
        for (int y = 0; y < width; ++y)
            for (int x = 0; x < width; ++x) {
                int in = 0;
                for (int sy = 0; sy < 4; ++sy)
                    for (int sx = 0; sx < 4; ++sx) {
                        const double px = x + (sx + 0.5) / 4, py = y + (sy + 0.5) / 4;
                        in += px >= a && px < b && py >= a && py < b;
                    }
                cov[std::size_t(y) * width + x] = float(in) / 16.0f;
            }
        v.coverage = Coverage(cov, width, width);
        vs.views.push_back(std::move(v));
    }
    vs.has_bounds = true;
    vs.bounds_min = {lo, lo, lo};
    vs.bounds_max = {hi, hi, hi};
    vs.units_per_pixel = 1.0 / scale;
    return vs;
}

Mesh subdivide(const Mesh& in, int levels) {
    Mesh m = in;
    m.normals.clear();
    m.uvs.clear();
    m.colors.clear();
    for (int l = 0; l < levels; ++l) {
        std::unordered_map<std::uint64_t, std::uint32_t> mid;
        mid.reserve(m.triangles.size() * 2);
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
            auto [it, fresh] = mid.emplace(key, std::uint32_t(m.positions.size()));
            if (fresh) m.positions.push_back((m.positions[a] + m.positions[b]) * 0.5f);
            return it->second;
        };
        std::vector<std::array<std::uint32_t, 3>> nf;
        nf.reserve(m.triangles.size() * 4);
        for (const auto& t : m.triangles) {
            const std::uint32_t a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
            nf.push_back({t[0], a, c});
            nf.push_back({t[1], b, a});
            nf.push_back({t[2], c, b});
            nf.push_back({a, b, c});
        }
        m.triangles.swap(nf);
    }
    return m;
}

// ---- Views drawn from exact outlines, and volumes --------------------------------

double ramp_coverage(double sd_px) { return std::clamp(0.5 + sd_px / 3.0, 0.0, 1.0); }

View ortho_view(const std::string& name, int size, double scale, const Outline& outline) {
    View v;
    v.name = name;
    v.camera = *Camera::named(name);
    v.camera.scale = scale;
    v.camera.cx = v.camera.cy = size / 2.0;
    v.width = v.height = size;
    std::vector<float> cov(std::size_t(size) * size);
    for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i) {
            const double a = (i + 0.5 - v.camera.cx) / scale, b = (v.camera.cy - (j + 0.5)) / scale;
            const Vec3d q = v.camera.r * a + v.camera.u * b;
            cov[std::size_t(j) * size + i] = float(ramp_coverage(outline(q) * scale));
        }
    v.coverage = Coverage(cov, size, size);
    return v;
}

std::shared_ptr<Views> make_views(std::vector<View> views, Vec3d lo, Vec3d hi) {
    auto vs = std::make_shared<Views>();
    vs->views = std::move(views);
    vs->has_bounds = true;
    vs->bounds_min = lo;
    vs->bounds_max = hi;
    return vs;
}

Outline sphere_outline(double radius) {
    return [radius](const Vec3d& q) { return radius - length(q); };
}

Outline box_outline(Vec3d lo, Vec3d hi, Vec3d d) {
    return [lo, hi, d](const Vec3d& q) {
        double sd = 1e300;
        for (int k = 0; k < 3; ++k) {
            if (std::abs(d[k]) > 0.5) continue; // the viewing axis
            sd = std::min({sd, q[k] - lo[k], hi[k] - q[k]});
        }
        return sd;
    };
}

Outline union_outline(Outline a, Outline b) {
    return [a, b](const Vec3d& q) { return std::max(a(q), b(q)); };
}

std::array<double, 12> look_at(Vec3d eye, Vec3d target, Vec3d up, double f, double cx, double cy) {
    const Vec3d z = normalize(target - eye); // camera forward
    const Vec3d x = normalize(cross(z, up)); // image right
    const Vec3d y = cross(z, x);             // image down
    // P = K [R | -R eye], rows of R: x, y, z.
    const double t[3] = {-dot(x, eye), -dot(y, eye), -dot(z, eye)};
    const Vec3d R[3] = {x, y, z};
    std::array<double, 12> P{};
    for (int c = 0; c < 3; ++c) {
        P[c] = f * R[0][c] + cx * R[2][c];
        P[4 + c] = f * R[1][c] + cy * R[2][c];
        P[8 + c] = R[2][c];
    }
    P[3] = f * t[0] + cx * t[2];
    P[7] = f * t[1] + cy * t[2];
    P[11] = t[2];
    return P;
}

View perspective_sphere_view(const std::string& name, const std::array<double, 12>& P, int w, int h, double f, Vec3d c,
                             double r) {
    View v;
    v.name = name;
    v.camera = Camera::perspective(P);
    v.width = w;
    v.height = h;
    std::vector<float> cov(std::size_t(w) * h);
    const Vec3d eye = v.camera.center();
    const double dist = length(c - eye);
    const double cone = std::asin(r / dist);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            Vec3d o, dir;
            v.camera.ray(i + 0.5, j + 0.5, o, dir);
            const double ang = std::acos(std::clamp(dot(dir, normalize(c - eye)), -1.0, 1.0));
            // Angle to pixels: about f pixels per radian near the centre of the image.
            cov[std::size_t(j) * w + i] = float(ramp_coverage((cone - ang) * f));
        }
    v.coverage = Coverage(cov, w, h);
    return v;
}

double coverage_iou(const std::vector<float>& coverage, int w, int h,
                    const std::function<bool(double x, double y)>& inside) {
    std::size_t inter = 0, uni = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool s = coverage[std::size_t(y) * w + x] >= 0.5f, t = inside(x + 0.5, y + 0.5);
            inter += s && t;
            uni += s || t;
        }
    return uni ? double(inter) / double(uni) : 1.0;
}

std::vector<View> perspective_sphere_ring(Vec3d c, double r, double f) {
    std::vector<View> vs;
    const Vec3d eyes[] = {{0, 0, 6}, {6, 0.5, 0}, {0, 6, 0.5}, {-4, 3, -3}};
    for (const Vec3d& e : eyes) {
        const Vec3d up = std::abs(e.y) > 5 ? Vec3d{0, 0, -1} : Vec3d{0, 1, 0};
        vs.push_back(perspective_sphere_view("cam" + std::to_string(vs.size()), look_at(e + c, c, up, f, 200, 150), 400,
                                             300, f, c, r));
    }
    return vs;
}

double counted_volume(const Volume& v) {
    const double h = v.voxel_size();
    return double(v.occupancy->tree().activeVoxelCount()) * h * h * h;
}

double crossing_volume(const Volume& v) {
    const double h = v.voxel_size();
    double corr = 0;
    auto acc = v.occupancy->getConstAccessor();
    for (auto it = v.crossings->cbeginValueOn(); it; ++it) {
        const float t = (*it)[0];
        if (t < 0) continue;
        corr += acc.isValueOn(it.getCoord()) ? t - 0.5 : 0.5 - t;
    }
    return (double(v.occupancy->tree().activeVoxelCount()) + corr) * h * h * h;
}

Image ink_drawing(int w, int h, const std::function<bool(double x, double y)>& ink, std::array<float, 3> pen,
                  std::array<float, 3> paper) {
    Image img;
    img.width = w;
    img.height = h;
    img.channels = 3;
    img.pixels.resize(std::size_t(w) * std::size_t(h) * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            int hits = 0;
            for (int sy = 0; sy < 4; ++sy)
                for (int sx = 0; sx < 4; ++sx) hits += ink(x + (sx + 0.5) / 4, y + (sy + 0.5) / 4);
            for (std::size_t k = 0; k < 3; ++k)
                img.pixels[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * 3 + k] =
                    paper[k] + float(hits) / 16.0f * (pen[k] - paper[k]);
        }
    return img;
}

Image compose_sheet(const std::vector<Image>& drawings, int gap, int strip) {
    Image s;
    s.channels = 3;
    int tallest = 0;
    s.width = gap;
    std::vector<int> left; // each drawing's first column on the sheet
    for (const Image& d : drawings) {
        left.push_back(s.width);
        s.width += d.width + gap;
        tallest = std::max(tallest, d.height);
    }
    s.height = gap + tallest + strip + gap;
    s.pixels.resize(std::size_t(s.width) * s.height * 3);
    // Every pixel from the nearest drawing, its coordinates clamped into it: the drawings
    // where they are, their edges continued across the gaps and the strip.
    for (int x = 0; x < s.width; ++x) {
        std::size_t k = 0;
        while (k + 1 < drawings.size() && x >= (left[k] + drawings[k].width + left[k + 1]) / 2) ++k;
        const Image& d = drawings[k];
        const int dx = std::clamp(x - left[k], 0, d.width - 1);
        for (int y = 0; y < s.height; ++y) {
            const int dy = std::clamp(y - gap, 0, d.height - 1);
            for (int c = 0; c < 3; ++c) s.at(x, y, c) = d.at(dx, dy, std::min(c, d.channels - 1));
        }
    }
    const int block = std::max(2, strip / 4), step = block + std::max(2, block / 2);
    for (std::size_t k = 0; k < drawings.size(); ++k) {
        const int lx = left[k] + drawings[k].width / 2 - (5 * step) / 2, ly = gap + tallest + strip / 3;
        for (int b = 0; b < 5; ++b)
            for (int y = ly; y < ly + block; ++y)
                for (int x = lx + b * step; x < lx + b * step + block; ++x)
                    for (int c = 0; c < 3; ++c) s.at(x, y, c) = 0.15f;
    }
    return s;
}

} // namespace cm::test
