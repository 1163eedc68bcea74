#include "plugins/plugin_abi.h"

namespace cm {
Stage* make_extract_marching_cubes();
}

CONCEPTMESH_DEFINE_PLUGIN("extract_marching_cubes", {"extract.marching_cubes", &cm::make_extract_marching_cubes})
