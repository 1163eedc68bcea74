// The views-manifest reader on arbitrary bytes: a manifest or cm::Error, nothing else.
#include <cstddef>
#include <cstdint>

#include "core/error.h"
#include "fuzz_support.h"
#include "io/manifest.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto file = cm::fuzz::as_file(data, size, "views.yaml");
    try {
        (void)cm::read_manifest(file);
    } catch (const cm::Error&) {}
    return 0;
}
