// Resource limits of one process: what a run may take before it refuses, said up front so
// a bad input ends in one clear line instead of an exhausted machine. Kept in the io layer,
// whose readers meet the inputs first; stages and the command line consult them too.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace cm {

struct ResourceLimits {
    /// Largest image (width x height) a reader decodes; checked on the header, before any
    /// pixel is allocated. 0: no limit.
    std::uint64_t max_image_pixels = 100'000'000;
    /// Most views one manifest may hold. 0: no limit.
    std::size_t max_views = 512;
    /// Most memory a stage may be estimated to need (bytes). 0: no limit. The default is
    /// set from the machine (default_max_memory()).
    std::uint64_t max_memory = 0;
};

/// The process-wide limits (the command line sets them; a library user may too).
ResourceLimits& resource_limits();

/// Physical memory of this machine in bytes (0 when it cannot be read).
std::uint64_t physical_memory_bytes();
/// The default memory limit: 80 % of physical memory.
std::uint64_t default_max_memory();

/// "1.5 GB", "320 MB": a size for messages.
std::string format_bytes(std::uint64_t bytes);

/// Throws cm::Error when `estimate` bytes exceed the memory limit; `what` names the work
/// ("hull.carve at resolution 4096"), `hint` what to change.
void check_memory_estimate(std::uint64_t estimate, const std::string& what, const std::string& hint);

} // namespace cm
