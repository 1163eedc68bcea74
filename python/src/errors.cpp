// conceptmesh's errors as Python exceptions. The message is the command's one line; the kind
// is read from it, as a user reads it: a file that cannot be read or written is an OSError, a
// parameter or graph mistake a ValueError (a UsageError is always one: it is what --set
// refuses, and Python's values take the --set path).
#include <regex>

#include "core/error.h"
#include "module.h"

namespace cm::py {

namespace {

PyObject* error_type = nullptr;
PyObject* file_error_type = nullptr;
PyObject* parameter_error_type = nullptr;

bool mentions(const std::string& text, const char* const* phrases) {
    for (; *phrases; ++phrases)
        if (text.find(*phrases) != std::string::npos) return true;
    return false;
}

const char* const file_phrases[] = {"cannot read",  "cannot write", "cannot open",         "cannot make the folder",
                                    "no such file", "No such file", "cannot use the path", "does not exist",
                                    nullptr};
const char* const parameter_phrases[] = {"unknown parameter",   "parameter \"", "must be",         "is required",
                                         "unknown stage",       "unknown node", "missing input",   "unknown input port",
                                         "names unknown node",  "has a cycle",  "also written by", " but node \"",
                                         "expected NODE.PARAM", nullptr};

PyObject* new_type(pybind11::module_& m, const char* name, const char* doc, PyObject* bases) {
    const std::string full = std::string("conceptmesh.") + name;
    PyObject* t = PyErr_NewExceptionWithDoc(full.c_str(), doc, bases, nullptr);
    if (!t) throw pybind11::error_already_set();
    // Class defaults, so that every instance has them (raise_error sets them per error).
    pybind11::handle(t).attr("node") = pybind11::none();
    pybind11::handle(t).attr("stage") = pybind11::none();
    m.add_object(name, pybind11::handle(t));
    return t;
}

} // namespace

void bind_errors(pybind11::module_& m) {
    error_type = new_type(m, "Error",
                          "A conceptmesh failure, with the command's one-line message. Attributes: node and stage "
                          "(the pipeline node and stage it names, or None).",
                          PyExc_Exception);
    pybind11::tuple file_bases = pybind11::make_tuple(pybind11::handle(error_type), pybind11::handle(PyExc_OSError));
    file_error_type =
        new_type(m, "FileError", "A file that cannot be read or written (an OSError too).", file_bases.ptr());
    pybind11::tuple param_bases =
        pybind11::make_tuple(pybind11::handle(error_type), pybind11::handle(PyExc_ValueError));
    parameter_error_type = new_type(
        m, "ParameterError", "A parameter, input or graph the stages refuse (a ValueError too).", param_bases.ptr());
}

void raise_error(const std::exception& e, const std::string& stage_name) {
    namespace pyb = pybind11;
    const std::string text = e.what();
    if (dynamic_cast<const Cancelled*>(&e)) {
        PyErr_SetString(PyExc_KeyboardInterrupt, text.c_str());
        throw pyb::error_already_set();
    }
    PyObject* type = error_type;
    if (dynamic_cast<const UsageError*>(&e)) type = parameter_error_type;
    else if (mentions(text, file_phrases)) type = file_error_type;
    else if (mentions(text, parameter_phrases)) type = parameter_error_type;
    else if (dynamic_cast<const std::invalid_argument*>(&e)) type = parameter_error_type;
    // "file:line: node "id" (stage): ..." (Pipeline::where), the first node a message names.
    static const std::regex node_re("node \"([^\"]+)\" \\(([^)]+)\\)");
    std::smatch match;
    pyb::object node = pyb::none(),
                stage = stage_name.empty() ? pyb::object(pyb::none()) : pyb::object(pyb::str(stage_name));
    if (std::regex_search(text, match, node_re)) {
        node = pyb::str(match[1].str());
        stage = pyb::str(match[2].str());
    }
    pyb::object exc = pyb::reinterpret_borrow<pyb::object>(type)(text);
    exc.attr("node") = node;
    exc.attr("stage") = stage;
    PyErr_SetObject(type, exc.ptr());
    throw pyb::error_already_set();
}

} // namespace cm::py
