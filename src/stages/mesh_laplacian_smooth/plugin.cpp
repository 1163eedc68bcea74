#include "plugins/plugin_abi.h"

namespace cm {
Stage* make_mesh_laplacian_smooth();
}

CONCEPTMESH_DEFINE_PLUGIN("mesh_laplacian_smooth", {"mesh.laplacian_smooth", &cm::make_mesh_laplacian_smooth})
