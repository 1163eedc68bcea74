// Speed and memory of hull.carve and hull.marching_intersections from 2048 px views
// of real meshes (front, right, top, rendered with the project's rasteriser).
//
//   bench_hull --benchmark_filter='Chain/bunny/512$'
//
// One process per case gives its own peak memory (peak_rss_mb is the process's
// high-water mark); bench/hull/run_hull_bench.sh runs every case that way.
#include <benchmark/benchmark.h>

#include <sys/resource.h>
#include <chrono>
#include <cstdlib>
#include <map>

#include "carve.h"
#include "io/mesh_io.h"
#include "refine.h"
#include "render/raster.h"

using namespace cm;

namespace {

constexpr int kImage = 2048;

std::shared_ptr<const Views> model_views(const std::string& model) {
    static std::map<std::string, std::shared_ptr<const Views>> cache;
    auto& slot = cache[model];
    if (slot) return slot;
    const std::string file = model == "bunny" ? "bunny00.off" : model == "spot" ? "spot.obj" : model + ".off";
    const Mesh mesh = read_mesh(std::string(CM_SHARED_DIR) + "/data/models/" + file);
    Vec3f lo, hi;
    mesh.bounds(lo, hi);
    auto views = std::make_shared<Views>();
    for (const char* n : {"front", "right", "top"}) {
        View v;
        v.name = n;
        v.width = v.height = kImage;
        v.camera = framed_camera(*Camera::named(n), Vec3d(lo), Vec3d(hi), kImage, kImage);
        const auto mask = render_mask(mesh, v.camera, kImage, kImage);
        v.coverage = Coverage(std::vector<float>(mask.begin(), mask.end()), v.width, v.height);
        views->views.push_back(std::move(v));
    }
    views->has_bounds = true;
    views->bounds_min = Vec3d(lo);
    views->bounds_max = Vec3d(hi);
    slot = views;
    return slot;
}

double peak_rss_mb() {
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    return double(ru.ru_maxrss) / 1024.0;
}

// CPU seconds of the whole process (all threads): on a loaded machine wall time says
// little, CPU time divided by the cores says what an idle machine would do.
double cpu_seconds() {
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    return double(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) + 1e-6 * double(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// carve + refine; the time of each stage and the grids' sizes as counters.
void BM_Chain(benchmark::State& state, std::string model) {
    auto views = model_views(model);
    CarveOptions opt;
    opt.resolution = int(state.range(0));
    double carve_s = 0, refine_s = 0, carve_cpu = 0, refine_cpu = 0;
    std::shared_ptr<Volume> vol, ref;
    RefineStats rs;
    for (auto _ : state) {
        vol.reset(), ref.reset();
        auto t0 = std::chrono::steady_clock::now();
        double c0 = cpu_seconds();
        vol = carve(views, opt).value;
        carve_s += seconds_since(t0);
        carve_cpu += cpu_seconds() - c0;
        t0 = std::chrono::steady_clock::now();
        c0 = cpu_seconds();
        auto refined = refine(*vol, nullptr, {});
        ref = std::move(refined.value);
        rs = refined.stats;
        refine_s += seconds_since(t0);
        refine_cpu += cpu_seconds() - c0;
    }
    const double n = double(state.iterations());
    const auto& occ = vol->occupancy->tree();
    state.counters["carve_s"] = carve_s / n;
    state.counters["refine_s"] = refine_s / n;
    state.counters["carve_cpu_s"] = carve_cpu / n;
    state.counters["refine_cpu_s"] = refine_cpu / n;
    state.counters["leaves"] = double(occ.leafCount());
    state.counters["active_tiles"] = double(occ.activeTileCount());
    state.counters["active_voxels"] = double(occ.activeVoxelCount());
    state.counters["occupancy_mb"] = double(occ.memUsage()) / 1048576.0;
    state.counters["crossings"] = double(rs.crossings);
    state.counters["thin"] = double(rs.thin_crossings);
    state.counters["cell_px"] = rs.cell_px;
    state.counters["crossings_mb"] = double(ref->crossings->tree().memUsage()) / 1048576.0;
    state.counters["peak_rss_mb"] = peak_rss_mb();
}

void register_all() {
    for (const char* model : {"bunny", "spot"})
        for (int res : {256, 512, 1024, 2048}) {
            auto* b =
                benchmark::RegisterBenchmark((std::string("Chain/") + model).c_str(), BM_Chain, std::string(model));
            b->Arg(res)
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime()
                ->Iterations(res <= 512 ? 5 : (res == 1024 ? 2 : 1));
        }
}

} // namespace

int main(int argc, char** argv) {
    register_all();
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
