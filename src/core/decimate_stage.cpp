#include "core/decimate_stage.h"

#include <cmath>
#include <sstream>

#include "core/error.h"

namespace cm {

std::vector<ParamSpec> face_target_params(double default_ratio) {
    return {ParamSpec::Int("target_faces", 0, 0, 2e9, "faces", "stop at or below this many faces; 0: no face count"),
            ParamSpec::Float("target_ratio", default_ratio, 0.0, 1.0, "",
                             "stop at or below this fraction of the input's faces; 0: no ratio")};
}

void check_face_target(const ParamSet& p) {
    if (p.get_int("target_faces") > 0 && p.get_float("target_ratio") > 0 && p.explicitly_set("target_faces") &&
        p.explicitly_set("target_ratio")) {
        std::ostringstream s;
        s << "give target_faces or target_ratio, not both (got " << p.get_int("target_faces") << " and "
          << p.get_float("target_ratio") << ")";
        throw Error(s.str());
    }
}

std::size_t face_target(const ParamSet& p, std::size_t faces) {
    if (p.get_int("target_faces") > 0 && (p.explicitly_set("target_faces") || p.get_float("target_ratio") <= 0))
        return std::size_t(p.get_int("target_faces"));
    const double r = p.get_float("target_ratio");
    if (r > 0) return std::size_t(std::floor(r * double(faces)));
    return 0;
}

} // namespace cm
