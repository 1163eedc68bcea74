#include "decimate_stage.h"

#include <cmath>
#include <sstream>

#include "core/error.h"

namespace cm {

void FaceTarget::declare(ParamBinder& b, double default_ratio) {
    b.add(faces,
          ParamSpec::Int("target_faces", 0, 0, 2e9, "faces", "stop at or below this many faces; 0: no face count"));
    b.add(ratio, ParamSpec::Float("target_ratio", default_ratio, 0.0, 1.0, "",
                                  "stop at or below this fraction of the input's faces; 0: no ratio"));
}

void FaceTarget::check() const {
    if (faces > 0 && ratio > 0 && faces.given && ratio.given) {
        std::ostringstream s;
        s << "give target_faces or target_ratio, not both (got " << faces.value << " and " << ratio.value << ")";
        throw Error(s.str());
    }
}

std::size_t FaceTarget::count(std::size_t input_faces) const {
    if (faces > 0 && (faces.given || ratio <= 0)) return std::size_t(faces.value);
    if (ratio > 0) return std::size_t(std::floor(ratio * double(input_faces)));
    return 0;
}

} // namespace cm
