#include "plugins/plugin_abi.h"

namespace cm {
Stage* make_mesh_reduce();
}

CONCEPTMESH_DEFINE_PLUGIN("mesh_reduce", {"mesh.reduce", &cm::make_mesh_reduce})
