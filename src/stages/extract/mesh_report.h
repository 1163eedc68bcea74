// What the extractors share: the stage's shape (a volume in, a mesh out, the `check`
// parameter), the figures of the mesh every one makes (its size, and the check it runs on it,
// with a warning when the mesh fails), and handing the mesh and its figures to the run.
#pragma once
#include <memory>

#include "core/algorithm.h"
#include "core/error.h"
#include "core/mesh.h"
#include "core/params.h"
#include "core/stage.h"
#include "core/volume.h"

namespace cm {

/// When to run the check: on, off, or auto (meshes up to kAutoCheckFaces faces).
enum class MeshCheckMode { Auto, On, Off };
constexpr std::size_t kAutoCheckFaces = 5'000'000;

/// The `check` parameter of the extractors.
struct MeshCheckOptions {
    MeshCheckMode mode;

    MeshCheckOptions() { set_declared_defaults(*this); }
    /// `check`.
    void declare(ParamBinder& b);
};

/// Reports the mesh's faces and vertices, and runs check_mesh() when `opt` asks for it and
/// reports its counts; a mesh that is not closed, manifold and outward is a warning naming the
/// counts.
void report_mesh(const Mesh& mesh, const MeshCheckOptions& opt, Metrics& m);

/// The stage's output from an extractor's result: its stats and the mesh's figures into the
/// run (in that order), then the mesh.
/// @throw cm::Error when the mesh is empty (the volume holds no inside point).
template <typename Stats>
Data extracted_mesh(Result<Mesh, Stats>&& r, const MeshCheckOptions& check, Context& ctx) {
    if (r.value.triangles.empty())
        throw Error("the volume has no surface: its occupancy holds no inside point (is the hull empty?)");
    r.stats.report(ctx);
    report_mesh(r.value, check, ctx);
    return std::make_shared<const Mesh>(std::move(r.value));
}

/// An extractor stage: the options of its algorithm and `check` as its parameters; a volume
/// with an occupancy grid in, the mesh extract() makes (through extracted_mesh()) out.
template <typename Options>
class ExtractorStage : public Stage {
public:
    void declare(ParamBinder& b) override {
        opt_.declare(b);
        check_.declare(b);
    }
    Data run(const Inputs& in, Context& ctx) override {
        auto vol = in.get<Volume>("volume");
        if (!vol->occupancy) throw Error("the volume has no occupancy grid");
        return extract(*vol, ctx);
    }

protected:
    /// The algorithm on `volume`, handed to the run by extracted_mesh(..., check_, ctx).
    virtual Data extract(const Volume& volume, Context& ctx) = 0;

    Options opt_;
    MeshCheckOptions check_;
};

} // namespace cm
