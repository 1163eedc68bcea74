// Smoothing and reduction speed on meshes of about a million faces:
//   sphere_1M: a 289 x 289 grid cube projected onto the unit sphere (1.00 M faces);
//   bunny_1M:  the Stanford bunny (75 k faces) split twice (1.21 M faces), lightly smoothed
//              so the split faces are not exactly flat.
//   file:      the mesh named by the environment variable CM_BENCH_MESH, when it is set (a
//              Marching Cubes surface of the pipeline, smoothed, say: written by a mesh.write
//              node after mesh.laplacian_smooth); its benchmarks are registered only then.
// Smoothing with and without the guard against crossing, turned-over and collapsed faces;
// the self-intersection test alone. Peers for the quadric decimation: meshoptimizer's meshopt_simplify and OpenMesh's
// DecimaterT + ModQuadricT (+ ModNormalFlippingT), both to 10 % of the faces.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#ifdef CM_HAVE_MESHOPTIMIZER
#include <meshoptimizer.h>
#endif

#include "core/mesh.h"
#include "geometry/distance_transform.h"
#include "geometry/mesh_adjacency.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_intersect.h"
#include "io/mesh_io.h"
#include "mesh_decimate.h"
#include "mesh_smooth.h"
#include "support/shapes.h"

using namespace cm;

namespace {

const Mesh& input(int which) {
    static std::map<int, Mesh> cache;
    auto it = cache.find(which);
    if (it != cache.end()) return it->second;
    Mesh m;
    if (which == 2) {
        m = read_mesh(std::getenv("CM_BENCH_MESH"));
    } else if (which == 0) {
        m = test::make_grid_box(-1.0f, 1.0f, 289);
        for (auto& p : m.positions) p = normalize(p);
    } else {
        m = test::subdivide(read_mesh(std::filesystem::path(CM_SHARED_DIR) / "data/models/bunny00.off"), 2);
        SmoothOptions o;
        o.method = SmoothOptions::Method::Taubin;
        o.iterations = 2;
        smooth_mesh_in_place(m, o);
    }
    return cache[which] = std::move(m);
}
const char* name_of(int which) { return which == 0 ? "sphere_1M" : which == 1 ? "bunny_1M" : "file"; }

void BM_Adjacency(benchmark::State& st) {
    const Mesh& m = input(int(st.range(0)));
    for (auto _ : st) benchmark::DoNotOptimize(build_vertex_adjacency(m));
    st.SetLabel(name_of(int(st.range(0))));
    st.counters["faces"] = double(m.face_count());
}

// The mesh check the extractor and mesh.write report (edges, fans, components).
void BM_CheckMesh(benchmark::State& st) {
    const Mesh& m = input(int(st.range(0)));
    for (auto _ : st) benchmark::DoNotOptimize(check_mesh(m));
    st.SetLabel(name_of(int(st.range(0))));
    st.counters["faces"] = double(m.face_count());
}

// The exact distance transform of a 2048 x 2048 silhouette-like mask (an ellipse with
// stripes): seeds inside (range 0) or outside (range 1), as views.load runs it, or both
// transforms of the signed field near the border (range 2), as a silhouette's distance field
// for the smoothing and the reduction takes them.
void BM_DistanceTransform(benchmark::State& st) {
    const int w = 2048, h = 2048;
    std::vector<char> seed(std::size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double u = (x - 1024) / 700.0, v = (y - 1100) / 500.0;
            const bool in = u * u + v * v < 1 || ((x / 37 + y / 53) % 7 == 0 && u * u + v * v < 1.6);
            seed[std::size_t(y) * w + x] = st.range(0) == 1 ? !in : in;
        }
    std::vector<float> out(seed.size());
    for (auto _ : st) {
        if (st.range(0) < 2) benchmark::DoNotOptimize(squared_edt(seed, w, h));
        else
            squared_edt_signed(seed.data(), w, h, 8, [&](int y, const float* row) {
                std::copy(row, row + w, out.begin() + std::ptrdiff_t(y) * w);
            });
    }
    st.SetLabel(st.range(0) == 0 ? "to_inside" : st.range(0) == 1 ? "to_outside" : "signed");
}

void BM_Smooth(benchmark::State& st, SmoothOptions::Method method) {
    const Mesh& m0 = input(int(st.range(0)));
    for (auto _ : st) {
        st.PauseTiming();
        Mesh m = m0;
        st.ResumeTiming();
        SmoothOptions o;
        o.method = method;
        o.iterations = 10;
        o.guard = st.range(1) != 0;
        const SmoothStats s = smooth_mesh_in_place(m, o);
        st.counters["bad_faces"] = double(s.bad_faces);
        st.counters["rounds"] = double(s.guard_rounds);
        benchmark::DoNotOptimize(m.positions.data());
    }
    st.SetLabel(std::string(name_of(int(st.range(0)))) + (st.range(1) ? " guard" : " no guard"));
    st.counters["faces"] = double(m0.face_count());
}
void BM_LaplacianSmooth10(benchmark::State& st) { BM_Smooth(st, SmoothOptions::Method::Laplacian); }
void BM_TaubinSmooth10(benchmark::State& st) { BM_Smooth(st, SmoothOptions::Method::Taubin); }

// The whole test each time: find_self_intersections() keeps its last answers by the mesh's
// fingerprint, so asking it again would time the fingerprint only.
void BM_SelfIntersections(benchmark::State& st) {
    const Mesh& m = input(int(st.range(0)));
    std::size_t pairs = 0;
    for (auto _ : st) {
        const std::vector<char> fans = embedded_fans(m.triangles, m.positions);
        pairs = SelfIntersectionIndex(m.triangles, m.positions).all(m.positions, {}, &fans).size();
    }
    st.SetLabel(name_of(int(st.range(0))));
    st.counters["faces"] = double(m.face_count());
    st.counters["pairs"] = double(pairs);
}

// The vertices within a hundred-thousandth of the box diagonal of another (the smoothing
// guard's question about vertices drawn onto one another).
void BM_CoincidentVertices(benchmark::State& st) {
    const Mesh& m = input(int(st.range(0)));
    Vec3f lo, hi;
    m.bounds(lo, hi);
    const double tol = 10 * kCoincidentTolerance * double(length(hi - lo));
    std::size_t n = 0;
    for (auto _ : st) n = find_coincident_vertices(m.positions, tol).size();
    st.SetLabel(name_of(int(st.range(0))));
    st.counters["vertices"] = double(m.positions.size());
    st.counters["coincident"] = double(n);
}

// Runs a decimation to a tenth of the faces as the stages run it: from the const input into
// a new mesh (one copy of the input included), with the crossing guard when range(1) says so.
template <typename Decimate>
void run_decimation(benchmark::State& st, Decimate&& decimate) {
    const Mesh& m0 = input(int(st.range(0)));
    std::size_t out = 0;
    for (auto _ : st) {
        Mesh m;
        const DecimateStats ds = decimate(m0, m, m0.face_count() / 10, st.range(1) != 0);
        out = m.face_count();
        st.counters["restarts"] = double(ds.restarts);
    }
    st.SetLabel(std::string(name_of(int(st.range(0)))) + (st.range(1) ? " guard" : " no guard"));
    st.counters["faces_in"] = double(m0.face_count());
    st.counters["faces_out"] = double(out);
}

void BM_Reduce(benchmark::State& st) {
    run_decimation(st, [](const Mesh& in, Mesh& out, std::size_t target, bool guard) {
        ReduceOptions o;
        o.max_angle_deg = 40;
        o.target_faces = target;
        o.no_crossings = guard;
        auto [mesh, stats] = reduce_mesh(in, o);
        out = std::move(mesh);
        return stats;
    });
}

void BM_QuadricOwn(benchmark::State& st) {
    run_decimation(st, [](const Mesh& in, Mesh& out, std::size_t target, bool guard) {
        QuadricOptions o;
        o.target_faces = target;
        o.no_crossings = guard;
        auto [mesh, stats] = quadric_decimate(in, o);
        out = std::move(mesh);
        return DecimateStats(stats);
    });
}

#ifdef CM_HAVE_MESHOPTIMIZER
void BM_QuadricMeshoptimizer(benchmark::State& st) {
    const Mesh& m0 = input(int(st.range(0)));
    std::size_t out = 0;
    bool manifold = true;
    for (auto _ : st) {
        std::vector<unsigned> idx(m0.triangles.size() * 3), dst(idx.size());
        for (std::size_t f = 0; f < m0.triangles.size(); ++f)
            for (int k = 0; k < 3; ++k) idx[3 * f + k] = m0.triangles[f][k];
        const std::size_t n = meshopt_simplify(dst.data(), idx.data(), idx.size(), &m0.positions[0].x,
                                               m0.positions.size(), sizeof(Vec3f), idx.size() / 10, 1.0f, 0, nullptr);
        out = n / 3;
        st.PauseTiming();
        Mesh r;
        r.positions = m0.positions;
        for (std::size_t f = 0; f < out; ++f) r.triangles.push_back({dst[3 * f], dst[3 * f + 1], dst[3 * f + 2]});
        manifold = check_mesh(r).closed_manifold();
        st.ResumeTiming();
    }
    st.SetLabel(std::string(name_of(int(st.range(0)))) + (manifold ? " closed-manifold" : " NOT-manifold"));
    st.counters["faces_in"] = double(m0.face_count());
    st.counters["faces_out"] = double(out);
}
#endif

void BM_QuadricOpenMesh(benchmark::State& st) {
    using OM = OpenMesh::TriMesh_ArrayKernelT<>;
    const Mesh& m0 = input(int(st.range(0)));
    std::size_t out = 0;
    for (auto _ : st) {
        st.PauseTiming();
        OM om;
        for (const auto& p : m0.positions) om.add_vertex(OM::Point(p.x, p.y, p.z));
        for (const auto& t : m0.triangles)
            om.add_face(OM::VertexHandle(int(t[0])), OM::VertexHandle(int(t[1])), OM::VertexHandle(int(t[2])));
        st.ResumeTiming();
        OpenMesh::Decimater::DecimaterT<OM> dec(om);
        OpenMesh::Decimater::ModQuadricT<OM>::Handle hq;
        OpenMesh::Decimater::ModNormalFlippingT<OM>::Handle hn;
        dec.add(hq);
        dec.add(hn);
        dec.module(hq).unset_max_err();
        dec.initialize();
        dec.decimate_to_faces(0, m0.face_count() / 10);
        om.garbage_collection();
        out = om.n_faces();
    }
    st.SetLabel(name_of(int(st.range(0))));
    st.counters["faces_in"] = double(m0.face_count());
    st.counters["faces_out"] = double(out);
}

} // namespace

BENCHMARK(BM_Adjacency)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CheckMesh)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DistanceTransform)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LaplacianSmooth10)->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TaubinSmooth10)->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SelfIntersections)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CoincidentVertices)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Reduce)->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_QuadricOwn)->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMillisecond)->Iterations(3);
#ifdef CM_HAVE_MESHOPTIMIZER
BENCHMARK(BM_QuadricMeshoptimizer)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(3);
#endif
BENCHMARK(BM_QuadricOpenMesh)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(1);

// The mesh of CM_BENCH_MESH (input 2), when given.
const bool file_benchmarks = [] {
    if (!std::getenv("CM_BENCH_MESH")) return false;
    benchmark::RegisterBenchmark("BM_Adjacency", BM_Adjacency)->Arg(2)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark("BM_CheckMesh", BM_CheckMesh)->Arg(2)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark("BM_SelfIntersections", BM_SelfIntersections)->Arg(2)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark("BM_CoincidentVertices", BM_CoincidentVertices)->Arg(2)->Unit(benchmark::kMillisecond);
    return true;
}();

BENCHMARK_MAIN();
