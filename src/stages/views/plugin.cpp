// The views family: the stages libcm_views.so provides.
#include "plugins/plugin_abi.h"

namespace cm {
Stage* make_views_load();
}

CONCEPTMESH_DEFINE_PLUGIN("views", {"views.load", &cm::make_views_load})
