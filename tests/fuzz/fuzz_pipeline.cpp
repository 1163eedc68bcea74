// The pipeline reader on arbitrary bytes: it either reads a pipeline or throws cm::Error.
// Anything else (another exception, a crash, a leak, a hang, unbounded memory) is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/error.h"
#include "pipeline/pipeline.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        cm::Pipeline p = cm::Pipeline::parse(text, "fuzz.yaml");
        for (const auto& n : p.nodes) (void)p.where(n);
    } catch (const cm::Error&) {}
    return 0;
}
