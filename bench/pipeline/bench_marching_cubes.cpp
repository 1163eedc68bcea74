// extract.marching_cubes alone: a sphere of diameter D cells (tiles inside, leaves at
// the surface, analytic crossings), so the figure is the extraction without carving.
//   build/release/bin/bench_marching_cubes
#include <benchmark/benchmark.h>

#include <sys/resource.h>
#include <cmath>
#include <map>
#include <memory>

#include <openvdb/tools/LevelSetSphere.h>
#include <openvdb/tools/LevelSetUtil.h>

#include "marching_cubes.h"

namespace {

std::shared_ptr<cm::Volume> sphere_volume(int diameter) {
    static std::map<int, std::shared_ptr<cm::Volume>> cache;
    auto& v = cache[diameter];
    if (v) return v;
    openvdb::initialize();
    const float r = 0.5f * float(diameter);
    const openvdb::Vec3f c(0.31f, -0.17f, 0.05f);
    auto sdf = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(r, c, 1.0f, 3.0f);
    v = std::make_shared<cm::Volume>();
    v->occupancy = openvdb::tools::sdfInteriorMask(*sdf, 0.0f);
    v->occupancy->setTransform(openvdb::math::Transform::createLinearTransform(1.0));
    v->crossings = openvdb::Vec3fGrid::create(openvdb::Vec3f(-1.0f));
    auto in = v->occupancy->getConstAccessor();
    auto out = v->crossings->getAccessor();
    for (auto leaf = v->occupancy->tree().cbeginLeaf(); leaf; ++leaf)
        for (int dx = -1; dx < 8; ++dx)
            for (int dy = -1; dy < 8; ++dy)
                for (int dz = -1; dz < 8; ++dz) {
                    const openvdb::Coord p = leaf->origin().offsetBy(dx, dy, dz);
                    openvdb::Vec3f t(-1.0f);
                    bool any = false;
                    for (int a = 0; a < 3; ++a) {
                        openvdb::Coord q = p;
                        q[a] += 1;
                        if (in.isValueOn(p) == in.isValueOn(q)) continue;
                        // |p + s e_a - c| = r, the root inside [0, 1].
                        const openvdb::Vec3d d = openvdb::Vec3d(p.x(), p.y(), p.z()) - openvdb::Vec3d(c);
                        const double b = d[a], cc = d.lengthSqr() - double(r) * r;
                        const double disc = std::sqrt(std::max(0.0, b * b - cc));
                        double s = -b + disc;
                        if (s < 0 || s > 1) s = -b - disc;
                        t[a] = float(std::clamp(s, 0.0, 1.0));
                        any = true;
                    }
                    if (any) out.setValueOn(p, t);
                }
    return v;
}

void BM_MarchingCubesSphere(benchmark::State& state) {
    const auto vol = sphere_volume(int(state.range(0)));
    cm::MarchingCubesOptions opt;
    std::size_t faces = 0;
    // CPU seconds of all threads: on a busy machine wall time says little, this does not.
    auto cpu = [] {
        rusage u{};
        getrusage(RUSAGE_SELF, &u);
        return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
    };
    const double cpu0 = cpu();
    for (auto _ : state) {
        cm::Mesh m = cm::marching_cubes(*vol, opt).value;
        faces = m.face_count();
        benchmark::DoNotOptimize(m.positions.data());
    }
    state.counters["cpu_s_all_threads"] = (cpu() - cpu0) / double(state.iterations());
    state.counters["faces"] = double(faces);
    state.counters["Mfaces_per_s"] =
        benchmark::Counter(double(faces) * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_MarchingCubesSphere)
    ->Arg(256)
    ->Arg(512)
    ->Arg(1024)
    ->Arg(2048)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

} // namespace

BENCHMARK_MAIN();
