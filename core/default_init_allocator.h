#pragma once
// An allocator that default-initialises what a container value-initialises: a
// `std::vector<float, DefaultInitAllocator<float>>(n)` holds n floats no one has written, where a
// plain `std::vector<float>(n)` would zero them on the calling thread.
//
// Why: a frame's output planes are written in full by the workers, row by row. Zeroing them first
// on the main thread is a serial pass that also takes every page fault of the fresh memory there
// (on a guest with paravirtualised page tables, several microseconds each); left unwritten, each
// page is first touched by the worker that fills it. Every other constructor (a size and a value,
// a copy, `assign`) behaves as std::vector's.

#include <memory>
#include <new>
#include <type_traits>
#include <utility>

namespace patchsim {

template <class T>
class DefaultInitAllocator : public std::allocator<T> {
  public:
    template <class U>
    struct rebind {
        using other = DefaultInitAllocator<U>;
    };

    using std::allocator<T>::allocator;

    template <class U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

}  // namespace patchsim
