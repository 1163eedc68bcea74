// mesh.write's algorithm: the mesh sized for its file, written in the format its extension
// names, and checked against the output rules, in steps that report their progress under
// names of their own ("writing", "checking").
#pragma once
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "core/algorithm.h"
#include "core/mesh.h"
#include "geometry/flat_caps.h"
#include "geometry/mesh_check.h"
#include "io/mesh_io.h"

namespace cm {

/// The parameters of mesh.write beside its path.
struct MeshFileOptions {
    MeshWriteOptions format; ///< `binary` and `normals`; MeshFile::write() takes a copy that names the files
    /// Check the mesh before writing it (closed, 2-manifold, outward, no degenerate faces, no
    /// self-intersections): figures in the stats; degenerate or crossing faces are an error
    /// (nothing written), another broken rule a warning.
    bool check;
    double height;     ///< > 0: scale the model to this height (Y extent) in the file; 0: keep its size
    double unit_scale; ///< multiply every coordinate by this (not with height)

    MeshFileOptions() { set_declared_defaults(*this); }
    /// `binary`, `normals`, `check`, `height` and `unit_scale`.
    void declare(ParamBinder& b);
};

struct MeshFileStats {
    double scale = 1;  ///< the factor on every coordinate
    double height = 0; ///< Y extent of the mesh written
    std::size_t faces = 0, vertices = 0;
    std::string path;                 ///< the name the file goes by
    std::uintmax_t bytes = 0;         ///< its size
    std::optional<OutputCheck> check; ///< the output rules, when they were checked
    FlatCaps caps;                    ///< the flat caps flipped away before writing (geometry/flat_caps.h)
    /// The scale (when not 1), height, faces, vertices, path and bytes; flat_caps_flipped and
    /// flat_caps_left when it had flat caps; with the check its
    /// figures (boundary_edges, nonmanifold_edges, degenerate_faces, self_intersections,
    /// volume, components, and genus when it is a closed 2-manifold: the tunnels through it,
    /// summed over its components) and one warning naming the rules the mesh breaks.
    void report(Metrics& m) const;
};

/// @brief A mesh as mesh.write puts it in a file, in named steps: sized (the constructor),
/// written (write()), checked (check()). The stage reports each step's progress under its own
/// name, so each takes a Progress of its own.
class MeshFile {
public:
    /// Sizes `mesh` (which must outlive this) for the file: scaled to `opt.height` or by
    /// `opt.unit_scale`, with normals computed when `opt.format.normals` asks for them and it
    /// has none, its flat caps flipped away (a copy only for one of these). @throw cm::Error for a mesh of no height to scale to.
    MeshFile(const Mesh& mesh, const MeshFileOptions& opt);
    /// The mesh as the file holds it.
    const Mesh& mesh() const { return changed_ ? *changed_ : input_; }
    /// Writes it to `file` (the format by its extension) with `format`'s options and names;
    /// `path` is the name the file goes by in the figures and the warning. A stop thrown by
    /// `progress` (per chunk) leaves a partial file for the caller to remove.
    void write(const std::filesystem::path& file, const std::filesystem::path& path, const MeshWriteOptions& format,
               Progress progress = {});
    /// Checks the mesh as the file will hold it against the output rules (geometry/mesh_check.h).
    void check(Progress progress = {});
    /// @throw cm::Error (one line naming `path`) when check() found degenerate faces or pairs
    /// of crossing faces: those are never written. Nothing without a check.
    void refuse_broken_faces(const std::filesystem::path& path) const;
    const MeshFileStats& stats() const { return stats_; }

private:
    const Mesh& input_;
    std::optional<Mesh> changed_; ///< scaled or given normals; empty: the input as it is
    MeshFileStats stats_;
};

} // namespace cm
