#include "io/limits.h"

#include <unistd.h>
#include <cstdio>

#include "core/error.h"

namespace cm {

ResourceLimits& resource_limits() {
    static ResourceLimits limits = [] {
        ResourceLimits l;
        l.max_memory = default_max_memory();
        return l;
    }();
    return limits;
}

std::uint64_t physical_memory_bytes() {
    const long pages = ::sysconf(_SC_PHYS_PAGES);
    const long page = ::sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || page <= 0) return 0;
    return std::uint64_t(pages) * std::uint64_t(page);
}

std::uint64_t default_max_memory() { return physical_memory_bytes() / 10 * 8; }

std::string format_bytes(std::uint64_t bytes) {
    char buf[32];
    const double b = double(bytes);
    if (b >= 1e9) std::snprintf(buf, sizeof buf, "%.1f GB", b / 1e9);
    else if (b >= 1e6) std::snprintf(buf, sizeof buf, "%.0f MB", b / 1e6);
    else std::snprintf(buf, sizeof buf, "%.0f kB", b / 1e3);
    return buf;
}

void check_memory_estimate(std::uint64_t estimate, const std::string& what, const std::string& hint) {
    const std::uint64_t limit = resource_limits().max_memory;
    if (limit == 0 || estimate <= limit) return;
    throw Error(what + " would need about " + format_bytes(estimate) + ", over the memory limit of " +
                format_bytes(limit) + " (--max-memory); " + hint);
}

} // namespace cm
