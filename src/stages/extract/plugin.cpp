// The extract family: the stages libcm_extract.so provides.
#include "plugins/plugin_abi.h"

namespace cm {
Stage* make_extract_marching_cubes();
}

CONCEPTMESH_DEFINE_PLUGIN("extract", {"extract.marching_cubes", &cm::make_extract_marching_cubes})
