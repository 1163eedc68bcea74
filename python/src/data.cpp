// The data between stages as Python objects over numpy arrays. What a stage made is handed
// out without copying: each array's base is a capsule holding the C++ object, so the arrays
// keep it alive after the Mesh (or the run's result) is gone, and they are read-only, as the
// stages' data is const. Data from numpy is copied once into the C++ layout.
#include <cstring>

#include "core/error.h"
#include "core/mesh.h"
#include "core/views.h"
#include "core/volume.h"
#include "io/image_io.h"
#include "module.h"

namespace cm::py {

namespace {

static_assert(sizeof(Vec3f) == 3 * sizeof(float), "Vec3f is three packed floats");

/// The first scalar of a vector of packed rows (Vec3f, std::array<float, N>); null when empty.
template <typename T, typename Row>
const T* scalars(const std::vector<Row>& rows) {
    return reinterpret_cast<const T*>(rows.data());
}

/// A read-only array over `data`, whose base owns `owner` (a shared_ptr kept in a capsule).
template <typename T, typename Owner>
pyb::array view_of(const std::shared_ptr<Owner>& owner, const T* data, std::vector<pyb::ssize_t> shape) {
    auto* keep = new std::shared_ptr<Owner>(owner);
    pyb::capsule base(keep, [](void* p) { delete static_cast<std::shared_ptr<Owner>*>(p); });
    pyb::array a(pyb::dtype::of<T>(), std::move(shape), std::vector<pyb::ssize_t>(), data, base);
    a.attr("setflags")(pyb::arg("write") = false);
    return a;
}

/// An image as (height, width, channels): uint8 for an 8-bit source, float32 in [0, 1] else.
template <typename Owner>
pyb::object image_array(const std::shared_ptr<Owner>& owner, const Image& img) {
    if (img.empty()) return pyb::none();
    std::vector<pyb::ssize_t> shape{img.height, img.width, img.channels};
    if (img.eight_bit()) return view_of(owner, img.bytes.data(), shape);
    return view_of(owner, img.pixels.data(), shape);
}

/// A C-contiguous array of `dtype` with `cols` columns (or the given trailing shape).
template <typename T>
pyb::array_t<T, pyb::array::c_style | pyb::array::forcecast> rows_of(const pyb::handle& obj, const char* what,
                                                                     pyb::ssize_t cols) {
    auto a = pyb::array_t<T, pyb::array::c_style | pyb::array::forcecast>::ensure(obj);
    if (!a || a.ndim() != 2 || a.shape(1) != cols)
        throw std::invalid_argument(std::string(what) + " must be an array of shape (n, " + std::to_string(cols) + ")");
    return a;
}

Image image_from(const pyb::handle& obj, const char* what) {
    auto any = pyb::array::ensure(obj);
    if (!any || (any.ndim() != 2 && any.ndim() != 3))
        throw std::invalid_argument(std::string(what) + " must be an image array (height, width[, channels])");
    Image img;
    img.height = int(any.shape(0));
    img.width = int(any.shape(1));
    img.channels = any.ndim() == 3 ? int(any.shape(2)) : 1;
    if (img.channels < 1 || img.channels > 4)
        throw std::invalid_argument(std::string(what) + " must have 1 to 4 channels, got " +
                                    std::to_string(img.channels));
    if (any.dtype().kind() == 'u' && any.dtype().itemsize() == 1) {
        auto a = pyb::array_t<std::uint8_t, pyb::array::c_style>::ensure(obj);
        img.bytes.assign(a.data(), a.data() + a.size());
    } else {
        auto a = pyb::array_t<float, pyb::array::c_style | pyb::array::forcecast>::ensure(obj);
        img.pixels.assign(a.data(), a.data() + a.size());
    }
    return img;
}

template <typename V, typename T, std::size_t N>
void copy_rows(std::vector<V>& out, const pyb::array_t<T, pyb::array::c_style | pyb::array::forcecast>& a) {
    static_assert(sizeof(V) == N * sizeof(T));
    out.resize(std::size_t(a.shape(0)));
    if (!out.empty()) std::memcpy(static_cast<void*>(out.data()), a.data(), out.size() * sizeof(V));
}

std::shared_ptr<const Mesh> mesh_from_arrays(const pyb::handle& vertices, const pyb::handle& faces,
                                             const pyb::handle& normals, const pyb::handle& uvs,
                                             const pyb::handle& colors, const pyb::handle& corner_uvs,
                                             const pyb::handle& texture) {
    auto m = std::make_shared<Mesh>();
    copy_rows<Vec3f, float, 3>(m->positions, rows_of<float>(vertices, "vertices", 3));
    auto f = rows_of<std::int64_t>(faces, "faces", 3);
    const std::int64_t n = std::int64_t(m->positions.size());
    m->triangles.resize(std::size_t(f.shape(0)));
    auto fr = f.unchecked<2>();
    for (pyb::ssize_t i = 0; i < f.shape(0); ++i) {
        const std::int64_t a = fr(i, 0), b = fr(i, 1), c = fr(i, 2);
        if (a < 0 || b < 0 || c < 0 || a >= n || b >= n || c >= n)
            throw std::invalid_argument("faces[" + std::to_string(i) + "] names a vertex outside 0.." +
                                        std::to_string(n - 1));
        if (a == b || b == c || a == c)
            throw std::invalid_argument("faces[" + std::to_string(i) + "] is degenerate (a vertex twice)");
        m->triangles[std::size_t(i)] = {std::uint32_t(a), std::uint32_t(b), std::uint32_t(c)};
    }
    auto per_vertex = [&](auto& out, const pyb::handle& h, const char* what, auto tag) {
        using Row = std::decay_t<decltype(out[0])>;
        constexpr std::size_t k = decltype(tag)::value;
        if (h.is_none()) return;
        copy_rows<Row, float, k>(out, rows_of<float>(h, what, pyb::ssize_t(k)));
        if (out.size() != m->positions.size())
            throw std::invalid_argument(std::string(what) + " must have one row per vertex");
    };
    per_vertex(m->normals, normals, "normals", std::integral_constant<std::size_t, 3>{});
    per_vertex(m->uvs, uvs, "uvs", std::integral_constant<std::size_t, 2>{});
    per_vertex(m->colors, colors, "colors", std::integral_constant<std::size_t, 4>{});
    if (!corner_uvs.is_none()) {
        auto a = pyb::array_t<float, pyb::array::c_style | pyb::array::forcecast>::ensure(corner_uvs);
        if (!a || a.ndim() != 3 || a.shape(0) != f.shape(0) || a.shape(1) != 3 || a.shape(2) != 2)
            throw std::invalid_argument("corner_uvs must be an array of shape (faces, 3, 2)");
        m->corner_uvs.resize(std::size_t(a.shape(0)) * 3);
        if (!m->corner_uvs.empty())
            std::memcpy(static_cast<void*>(m->corner_uvs.data()), a.data(), m->corner_uvs.size() * 8);
    }
    if (!texture.is_none()) m->texture = std::make_shared<const Image>(image_from(texture, "texture"));
    return m;
}

pyb::dict camera_dict(const Camera& c) {
    pyb::dict d;
    if (c.orthographic()) {
        d["kind"] = "orthographic";
        d["right"] = pyb::make_tuple(c.r.x, c.r.y, c.r.z);
        d["up"] = pyb::make_tuple(c.u.x, c.u.y, c.u.z);
        d["direction"] = pyb::make_tuple(c.d.x, c.d.y, c.d.z);
        d["scale"] = c.scale;
        d["origin"] = pyb::make_tuple(c.cx, c.cy);
        d["azimuth"] = c.azimuth_deg;
        d["elevation"] = c.elevation_deg;
    } else {
        d["kind"] = "perspective";
    }
    // The 3x4 matrix from world to homogeneous pixels, for both kinds (orthographic: its last
    // row is 0 0 0 1), so a caller projects every view the same way.
    pyb::array_t<double> P(std::vector<pyb::ssize_t>{3, 4});
    auto p = P.mutable_unchecked<2>();
    if (c.orthographic()) {
        const double rows[3][4] = {{c.scale * c.r.x, c.scale * c.r.y, c.scale * c.r.z, c.cx},
                                   {-c.scale * c.u.x, -c.scale * c.u.y, -c.scale * c.u.z, c.cy},
                                   {0, 0, 0, 1}};
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 4; ++j) p(i, j) = rows[i][j];
    } else {
        for (int i = 0; i < 12; ++i) p(i / 4, i % 4) = c.P[std::size_t(i)];
    }
    d["matrix"] = P;
    return d;
}

/// One view of a Views, keeping the whole Views alive.
struct ViewRef {
    std::shared_ptr<const Views> views;
    std::size_t index;
    const View& get() const { return views->views[index]; }
};

} // namespace

/// The Python classes' C++ side: each holds the stage data it shows.
struct PyMesh {
    std::shared_ptr<const Mesh> mesh;
};
struct PyViews {
    std::shared_ptr<const Views> views;
};
struct PyVolume {
    std::shared_ptr<const Volume> volume;
};

pyb::object to_python(const Data& d) {
    if (auto* m = std::get_if<std::shared_ptr<const Mesh>>(&d)) return pyb::cast(PyMesh{*m});
    if (auto* v = std::get_if<std::shared_ptr<const Views>>(&d)) return pyb::cast(PyViews{*v});
    if (auto* v = std::get_if<std::shared_ptr<const Volume>>(&d)) return pyb::cast(PyVolume{*v});
    if (auto* f = std::get_if<std::shared_ptr<const FileOutput>>(&d)) {
        pyb::list paths;
        for (const auto& p : (*f)->paths) paths.append(p.string());
        return paths;
    }
    if (auto* r = std::get_if<std::shared_ptr<const Report>>(&d))
        return pyb::module_::import("json").attr("loads")((*r)->json);
    return pyb::none();
}

Data from_python(const pyb::handle& obj, const std::string& what) {
    if (pyb::isinstance<PyMesh>(obj)) return obj.cast<const PyMesh&>().mesh;
    if (pyb::isinstance<PyViews>(obj)) return obj.cast<const PyViews&>().views;
    if (pyb::isinstance<PyVolume>(obj)) return obj.cast<const PyVolume&>().volume;
    throw std::invalid_argument(what + " must be a conceptmesh.Mesh, Views or Volume, got " +
                                std::string(pyb::str(obj.get_type().attr("__name__"))));
}

namespace {

void bind_mesh(pyb::module_& m);
void bind_views(pyb::module_& m);
void bind_volume(pyb::module_& m);

} // namespace

void bind_data(pyb::module_& m) {
    bind_mesh(m);
    bind_views(m);
    bind_volume(m);
    m.def(
        "write_png",
        [](const pyb::handle& image, const std::string& path) {
            translated([&] {
                const Image img = image_from(image, "image");
                if (img.channels == 2) throw std::invalid_argument("image must have 1, 3 or 4 channels, got 2");
                write_image(img, path);
            });
        },
        pyb::arg("image"), pyb::arg("path"), "Writes an (H, W[, C]) uint8 or float [0, 1] array as an 8-bit PNG.");
}

namespace {

void bind_mesh(pyb::module_& m) {
    pyb::class_<PyMesh>(m, "Mesh",
                        "A triangle mesh: vertices (N, 3) float32, faces (M, 3) uint32 and, where present, "
                        "normals (N, 3), uvs (N, 2), corner_uvs (M, 3, 2), colors (N, 4) RGBA and the texture "
                        "image. The arrays are read-only views of the C++ mesh (no copy).")
        .def(pyb::init([](const pyb::handle& vertices, const pyb::handle& faces, const pyb::handle& normals,
                          const pyb::handle& uvs, const pyb::handle& colors, const pyb::handle& corner_uvs,
                          const pyb::handle& texture) {
                 return translated([&] {
                     return PyMesh{mesh_from_arrays(vertices, faces, normals, uvs, colors, corner_uvs, texture)};
                 });
             }),
             pyb::arg("vertices"), pyb::arg("faces"), pyb::kw_only(), pyb::arg("normals") = pyb::none(),
             pyb::arg("uvs") = pyb::none(), pyb::arg("colors") = pyb::none(), pyb::arg("corner_uvs") = pyb::none(),
             pyb::arg("texture") = pyb::none(),
             "A mesh from numpy arrays (copied once): vertices (N, 3), faces (M, 3) of vertex indices; "
             "optional per-vertex normals (N, 3), uvs (N, 2), colors (N, 4), per-corner corner_uvs (M, 3, 2) "
             "and a texture (H, W, C) uint8 or float in [0, 1], row 0 at the top.")
        .def_property_readonly(
            "vertices",
            [](const PyMesh& s) {
                return view_of(s.mesh, scalars<float>(s.mesh->positions), {pyb::ssize_t(s.mesh->positions.size()), 3});
            })
        .def_property_readonly("faces",
                               [](const PyMesh& s) {
                                   return view_of(s.mesh, scalars<std::uint32_t>(s.mesh->triangles),
                                                  {pyb::ssize_t(s.mesh->triangles.size()), 3});
                               })
        .def_property_readonly(
            "normals",
            [](const PyMesh& s) -> pyb::object {
                if (s.mesh->normals.empty()) return pyb::none();
                return view_of(s.mesh, scalars<float>(s.mesh->normals), {pyb::ssize_t(s.mesh->normals.size()), 3});
            })
        .def_property_readonly(
            "uvs",
            [](const PyMesh& s) -> pyb::object {
                if (s.mesh->uvs.empty()) return pyb::none();
                return view_of(s.mesh, scalars<float>(s.mesh->uvs), {pyb::ssize_t(s.mesh->uvs.size()), 2});
            })
        .def_property_readonly("corner_uvs",
                               [](const PyMesh& s) -> pyb::object {
                                   if (s.mesh->corner_uvs.empty()) return pyb::none();
                                   return view_of(s.mesh, scalars<float>(s.mesh->corner_uvs),
                                                  {pyb::ssize_t(s.mesh->corner_uvs.size() / 3), 3, 2});
                               })
        .def_property_readonly(
            "colors",
            [](const PyMesh& s) -> pyb::object {
                if (s.mesh->colors.empty()) return pyb::none();
                return view_of(s.mesh, scalars<float>(s.mesh->colors), {pyb::ssize_t(s.mesh->colors.size()), 4});
            })
        .def_property_readonly("texture",
                               [](const PyMesh& s) -> pyb::object {
                                   if (!s.mesh->texture) return pyb::none();
                                   return image_array(s.mesh->texture, *s.mesh->texture);
                               })
        .def("__repr__", [](const PyMesh& s) {
            return "<conceptmesh.Mesh " + std::to_string(s.mesh->positions.size()) + " vertices, " +
                   std::to_string(s.mesh->triangles.size()) + " faces>";
        });
}

void bind_views(pyb::module_& m) {
    pyb::class_<ViewRef>(m, "View", "One view: its name, image, silhouette coverage and camera.")
        .def_property_readonly("name", [](const ViewRef& v) { return v.get().name; })
        .def_property_readonly("source", [](const ViewRef& v) { return v.get().source.string(); })
        .def_property_readonly(
            "image", [](const ViewRef& v) { return image_array(v.views, v.get().image); },
            "The drawing, (height, width, channels): uint8 as read, or float32 in [0, 1].")
        .def_property_readonly(
            "coverage",
            [](const ViewRef& v) {
                const View& view = v.get();
                pyb::array_t<float> a(std::vector<pyb::ssize_t>{view.height, view.width});
                const std::vector<float> full = view.coverage.full();
                if (!full.empty()) std::memcpy(a.mutable_data(), full.data(), full.size() * sizeof(float));
                else std::memset(a.mutable_data(), 0, a.nbytes());
                return a;
            },
            "The silhouette as coverage in [0, 1], (height, width) float32 (a copy: it is stored windowed).")
        .def_property_readonly(
            "camera", [](const ViewRef& v) { return camera_dict(v.get().camera); },
            "The camera: kind, matrix (3x4, world to pixels) and, orthographic, right, up, "
            "direction, scale, origin, azimuth and elevation.")
        .def("__repr__", [](const ViewRef& v) {
            return "<conceptmesh.View " + v.get().name + " " + std::to_string(v.get().width) + "x" +
                   std::to_string(v.get().height) + ">";
        });

    pyb::class_<PyViews>(m, "Views", "The views a pipeline reconstructs from (views.load's output).")
        .def("__len__", [](const PyViews& v) { return v.views->views.size(); })
        .def("__getitem__",
             [](const PyViews& v, pyb::object key) {
                 if (pyb::isinstance<pyb::str>(key)) {
                     const std::string name = key.cast<std::string>();
                     for (std::size_t i = 0; i < v.views->views.size(); ++i)
                         if (v.views->views[i].name == name) return ViewRef{v.views, i};
                     throw pyb::key_error("no view named \"" + name + "\"");
                 }
                 pyb::ssize_t i = key.cast<pyb::ssize_t>();
                 const auto n = pyb::ssize_t(v.views->views.size());
                 if (i < 0) i += n;
                 if (i < 0 || i >= n) throw pyb::index_error("view index out of range");
                 return ViewRef{v.views, std::size_t(i)};
             })
        .def_property_readonly("names",
                               [](const PyViews& v) {
                                   std::vector<std::string> names;
                                   for (const auto& view : v.views->views) names.push_back(view.name);
                                   return names;
                               })
        .def_property_readonly("calibrated", [](const PyViews& v) { return v.views->calibrated; })
        .def_property_readonly("bounds",
                               [](const PyViews& v) -> pyb::object {
                                   if (!v.views->has_bounds) return pyb::none();
                                   const auto& a = v.views->bounds_min;
                                   const auto& b = v.views->bounds_max;
                                   return pyb::make_tuple(pyb::make_tuple(a.x, a.y, a.z),
                                                          pyb::make_tuple(b.x, b.y, b.z));
                               })
        .def_property_readonly("units_per_pixel", [](const PyViews& v) { return v.views->units_per_pixel; })
        .def("__repr__", [](const PyViews& v) {
            return "<conceptmesh.Views " + std::to_string(v.views->views.size()) + " views>";
        });
}

void bind_volume(pyb::module_& m) {
    pyb::class_<PyVolume>(m, "Volume",
                          "The hull: an OpenVDB occupancy grid (sparse). save() writes it as a .vdb level set; "
                          "grid() gives it to pyopenvdb where that is installed.")
        .def_property_readonly("voxel_size", [](const PyVolume& v) { return v.volume->voxel_size(); })
        .def_property_readonly("active_voxels",
                               [](const PyVolume& v) { return v.volume->occupancy->activeVoxelCount(); })
        .def_property_readonly(
            "bounds",
            [](const PyVolume& v) {
                const auto box = v.volume->occupancy->evalActiveVoxelBoundingBox();
                const auto lo = v.volume->transform().indexToWorld(box.min());
                const auto hi = v.volume->transform().indexToWorld(box.max());
                return pyb::make_tuple(pyb::make_tuple(lo.x(), lo.y(), lo.z()),
                                       pyb::make_tuple(hi.x(), hi.y(), hi.z()));
            },
            "World box of the grid points inside ((xmin, ymin, zmin), (xmax, ymax, zmax)).")
        .def_property_readonly("refined", [](const PyVolume& v) { return bool(v.volume->crossings); })
        .def("__repr__", [](const PyVolume& v) {
            return "<conceptmesh.Volume voxel " + std::to_string(v.volume->voxel_size()) + ", " +
                   std::to_string(v.volume->occupancy->activeVoxelCount()) + " active>";
        });
}

} // namespace

} // namespace cm::py
