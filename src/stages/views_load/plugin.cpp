#include "plugins/plugin_abi.h"

namespace cm {
Stage* make_views_load();
}

CONCEPTMESH_DEFINE_PLUGIN("views_load", {"views.load", &cm::make_views_load})
