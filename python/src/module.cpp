// The extension module conceptmesh._conceptmesh; conceptmesh/__init__.py is its face.
#include "module.h"

PYBIND11_MODULE(_conceptmesh, m) {
    m.doc() = "conceptmesh's C++ side: the registry, the data types over numpy, running stages and pipelines.";
    m.attr("__version__") = CONCEPTMESH_VERSION_STRING;
    cm::py::bind_errors(m);
    cm::py::bind_data(m);
    cm::py::bind_stages(m);
    cm::py::bind_pipeline(m);
}
