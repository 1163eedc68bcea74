// The eval family: the stages libcm_eval.so provides.
#include "plugins/plugin_abi.h"

namespace cm {
Stage* make_eval_silhouette_error();
Stage* make_eval_preview();
} // namespace cm

CONCEPTMESH_DEFINE_PLUGIN("eval", {"eval.silhouette_error", &cm::make_eval_silhouette_error},
                          {"eval.preview", &cm::make_eval_preview})
