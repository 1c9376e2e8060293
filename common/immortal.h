// An object built once and never destroyed. Code that runs inside another program (the shim) is
// called from that program's exit handlers, static destructors and thread exits, in an order
// nobody controls: a global with a destructor is destroyed at some point of that sequence, and a
// call that comes after it reads freed memory. An Immortal's destructor is trivial, so the
// compiler registers nothing to run at exit; the object lives until the process is gone, and the
// operating system takes back its memory.
#pragma once

#include <new>
#include <utility>

namespace glcast {

template <class T>
class Immortal {
public:
    template <class... Args>
    explicit Immortal(Args&&... args) {
        new (storage_) T(std::forward<Args>(args)...);
    }
    Immortal(const Immortal&) = delete;
    Immortal& operator=(const Immortal&) = delete;

    T& operator*() { return *get(); }
    T* operator->() { return get(); }
    const T& operator*() const { return *get(); }
    const T* operator->() const { return get(); }

private:
    T* get() { return std::launder(reinterpret_cast<T*>(storage_)); }
    const T* get() const { return std::launder(reinterpret_cast<const T*>(storage_)); }
    alignas(T) unsigned char storage_[sizeof(T)];
};

}  // namespace glcast
