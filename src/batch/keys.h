// The keys of ASSETS.yaml, shared by the reader and the test that keeps
// schemas/batch.schema.json equal to it.
#pragma once
#include <string>
#include <vector>

namespace cm::batch {

inline const std::vector<std::string> kTopKeys = {"batch", "pipeline", "set", "output", "assets"};
inline const std::vector<std::string> kAssetKeys = {"name", "views", "sheet", "pipeline", "set", "memory_mib"};

} // namespace cm::batch
