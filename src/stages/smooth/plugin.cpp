// The smooth family: the stages libcm_smooth.so provides.
#include "plugins/plugin_abi.h"

namespace cm {
Stage* make_mesh_laplacian_smooth();
Stage* make_mesh_taubin_smooth();
} // namespace cm

CONCEPTMESH_DEFINE_PLUGIN("smooth", {"mesh.laplacian_smooth", &cm::make_mesh_laplacian_smooth},
                          {"mesh.taubin_smooth", &cm::make_mesh_taubin_smooth})
