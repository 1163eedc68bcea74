// Rasteriser speed: binary silhouettes and depth buffers of icospheres of 0.3 M to 5.2 M
// triangles at 1024 x 1024, from an oblique view.
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>

#include "render/raster.h"

namespace {

// Icosphere by repeated 4-way subdivision (kept here so the benchmark needs no test library).
cm::Mesh icosphere(int level) {
    cm::Mesh m;
    const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
    m.positions = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                   {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
    m.triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                   {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                   {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (auto& p : m.positions) p = cm::normalize(p);
    for (int l = 0; l < level; ++l) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            const auto i = std::uint32_t(m.positions.size());
            m.positions.push_back(cm::normalize((m.positions[a] + m.positions[b]) * 0.5f));
            mid[key] = i;
            return i;
        };
        std::vector<std::array<std::uint32_t, 3>> next;
        next.reserve(m.triangles.size() * 4);
        for (const auto& f : m.triangles) {
            const auto a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
            next.push_back({f[0], a, c});
            next.push_back({f[1], b, a});
            next.push_back({f[2], c, b});
            next.push_back({a, b, c});
        }
        m.triangles.swap(next);
    }
    return m;
}

const cm::Mesh& sphere(int level) {
    static std::map<int, cm::Mesh> cache;
    auto it = cache.find(level);
    if (it == cache.end()) it = cache.emplace(level, icosphere(level)).first;
    return it->second;
}

cm::Camera camera() {
    return cm::framed_camera(cm::Camera::from_azimuth_elevation(30, 20), {-1, -1, -1}, {1, 1, 1}, 1024, 1024);
}

void BM_RenderMask(benchmark::State& state) {
    const cm::Mesh& m = sphere(int(state.range(0)));
    const cm::Camera c = camera();
    for (auto _ : state) benchmark::DoNotOptimize(cm::render_mask(m, c, 1024, 1024));
    state.counters["triangles"] = double(m.triangles.size());
    state.counters["tri_per_s"] =
        benchmark::Counter(double(m.triangles.size()), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_RenderDepth(benchmark::State& state) {
    const cm::Mesh& m = sphere(int(state.range(0)));
    const cm::Camera c = camera();
    for (auto _ : state) benchmark::DoNotOptimize(cm::render_depth(m, c, 1024, 1024));
    state.counters["triangles"] = double(m.triangles.size());
    state.counters["tri_per_s"] =
        benchmark::Counter(double(m.triangles.size()), benchmark::Counter::kIsIterationInvariantRate);
}

} // namespace

BENCHMARK(BM_RenderMask)->Arg(7)->Arg(8)->Arg(9)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_RenderDepth)->Arg(7)->Arg(8)->Arg(9)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_MAIN();
