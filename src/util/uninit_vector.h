// A vector whose resize() leaves trivial elements uninitialised, for large arrays that are
// filled right after (side by side: each thread's first write maps its own pages, where a
// zero fill in the constructor would map them all on one thread first).
#pragma once
#include <memory>
#include <utility>
#include <vector>

namespace cm {

/// An allocator whose resize() leaves trivial elements uninitialised, for large arrays
/// that are filled right after (no pass of zeros over hundreds of megabytes).
template <typename T>
struct UninitAllocator : std::allocator<T> {
    template <typename U>
    struct rebind {
        using other = UninitAllocator<U>;
    };
    UninitAllocator() = default;
    template <typename U>
    UninitAllocator(const UninitAllocator<U>&) noexcept {}
    template <typename U>
    void construct(U* p) noexcept {
        ::new (static_cast<void*>(p)) U;
    }
    template <typename U, typename... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};
template <typename T>
using UninitVector = std::vector<T, UninitAllocator<T>>;

} // namespace cm
