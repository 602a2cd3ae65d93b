// A std::vector whose vector(n) and resize(n) leave the new elements default-initialized (for the plain structs of
// kernels/types.h: uninitialized) instead of zeroing them. The BVH builders size their node arrays first and then
// write every element on several threads; a std::vector would first zero the whole array, page faults included,
// on one thread. Only for arrays whose every element is written before it is read.
#pragma once

#include <memory>
#include <utility>
#include <vector>

namespace prism {

template <class T>
struct UninitializedAllocator : std::allocator<T> {
    template <class U>
    struct rebind {
        using other = UninitializedAllocator<U>;
    };
    UninitializedAllocator() = default;
    template <class U>
    UninitializedAllocator(const UninitializedAllocator<U>&) {}
    template <class U>
    void construct(U* p) noexcept {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

template <class T>
using UninitializedVector = std::vector<T, UninitializedAllocator<T>>;

}  // namespace prism
