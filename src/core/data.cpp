#include "core/data.h"

#include "core/error.h"

namespace cm {

const char* to_string(DataKind k) {
    switch (k) {
    case DataKind::Views: return "views";
    case DataKind::Volume: return "volume";
    case DataKind::Mesh: return "mesh";
    case DataKind::File: return "file";
    case DataKind::Report: return "report";
    }
    return "?";
}

DataKind kind_of(const Data& d) {
    switch (d.index()) {
    case 1: return DataKind::Views;
    case 2: return DataKind::Volume;
    case 3: return DataKind::Mesh;
    case 4: return DataKind::File;
    case 5: return DataKind::Report;
    default: throw Error("a stage returned no data");
    }
}

} // namespace cm
