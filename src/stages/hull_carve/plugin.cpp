#include "plugins/plugin_abi.h"

namespace cm {
Stage* make_hull_carve();
}

CONCEPTMESH_DEFINE_PLUGIN("hull_carve", {"hull.carve", &cm::make_hull_carve})
