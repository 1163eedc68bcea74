// What the sub-commands share: the mesh's own axes (--up, --front), fitting a mesh to
// its views (--fit), the views as views.load loads them, the messages of a stage run
// from a command, and a pipeline loaded and checked.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/commands.h"
#include "core/camera.h"
#include "core/mesh.h"
#include "core/progress.h"
#include "core/stage.h"
#include "core/views.h"
#include "pipeline/pipeline.h"

namespace cm::cli {

/// Makes `run` the action of `cmd`: it runs once the command line is parsed.
void set_action(CLI::App* cmd, std::function<int()>& action, std::function<int()> run);

/// The model's own up and front axes -> the conventions' frame (Y up, front +Z, X = Y x Z).
struct Orientation {
    Vec3d up{0, 1, 0}, front{0, 0, 1};
    bool identity() const { return up == Vec3d{0, 1, 0} && front == Vec3d{0, 0, 1}; }
    Vec3d apply(const Vec3d& p) const { return {dot(p, cross(up, front)), dot(p, up), dot(p, front)}; }
};

/// --up and --front as given ("+Y", "-z", "Y").
struct AxisOptions {
    std::string up = "+Y", front = "+Z";
    /// Adds --up and --front to `cmd`, with their help texts.
    void add_to(CLI::App* cmd, const std::string& up_doc, const std::string& front_doc);
    /// Throws cm::Error for a word that is no axis, or two axes that are not different.
    Orientation parse() const;
};

/// Reads a mesh and turns it from its own axes into the conventions' frame; throws
/// cm::Error for a mesh without triangles.
Mesh load_oriented(const std::string& file, const Orientation& o);

/// The bottom centre of the box [lo, hi]: the output frame's pivot.
Vec3d box_pivot(const Vec3f& lo, const Vec3f& hi);

/// Adds --fit (none, bbox, pivot) to `cmd`.
void add_fit_option(CLI::App* cmd, std::string& fit, const std::string& doc);
/// bbox: maps the mesh's bounding box onto the box the views imply (per axis); pivot:
/// moves the mesh so that its box's bottom centre is at the origin; none: nothing.
void fit_mesh(Mesh& m, const Views& views, const std::string& fit);

/// One view to draw from: a view name or azimuth/elevation.
struct ViewSpec {
    std::string name; ///< file stem and manifest key
    Camera dir;
    bool named = false;
    double az = 0, el = 0;
};
/// "front,right,top,az45el30,az-30" -> views; throws cm::Error naming a bad item.
std::vector<ViewSpec> parse_views(const std::string& list);

/// Prints what a tool's stage says: warnings unless quiet, notes when verbose.
class ToolMessages : public ProgressSink {
public:
    explicit ToolMessages(const GlobalOptions& g) : g_(g) {}
    void started(const std::string&, const std::string&) override {}
    void progress(const std::string&, double, const std::string&) override {}
    void finished(const std::string&, double) override {}
    void message(const std::string&, const std::string& level, const std::string& text) override;

private:
    const GlobalOptions& g_;
};

/// The views as views.load loads them in a pipeline, run through the registry.
std::shared_ptr<const Views> load_views_through_registry(const std::string& manifest, const GlobalOptions& g);
/// The inputs of an eval stage: a mesh and views.
Inputs mesh_and_views(Mesh mesh, std::shared_ptr<const Views> views);

/// f(), then the warnings of the plugins it loaded (plugins load on first use), whether it
/// returns or throws.
template <typename F>
auto with_plugin_warnings(const GlobalOptions& g, F&& f) -> decltype(f()) {
    try {
        if constexpr (std::is_void_v<decltype(f())>) {
            f();
            print_plugin_diagnostics(g);
        } else {
            auto r = f();
            print_plugin_diagnostics(g);
            return r;
        }
    } catch (...) {
        print_plugin_diagnostics(g);
        throw;
    }
}

/// A pipeline file with --set overrides applied, validated against the registry; prints the
/// warnings of the plugins that loaded on the way.
Pipeline load_checked(const std::string& file, const std::vector<std::string>& sets, const GlobalOptions& g);

} // namespace cm::cli
