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

template <class T, class Base = std::allocator<T>>
class DefaultInitAllocator : public Base {
    using Traits = std::allocator_traits<Base>;

  public:
    template <class U>
    struct rebind {
        using other = DefaultInitAllocator<U, typename Traits::template rebind_alloc<U>>;
    };

    using Base::Base;

    template <class U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        Traits::construct(static_cast<Base&>(*this), p, std::forward<Args>(args)...);
    }
};

}  // namespace patchsim
