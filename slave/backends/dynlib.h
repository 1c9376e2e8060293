// Run-time loading of a backend's driver library. The slave links none of libGL, libOpenGL,
// libEGL or libOSMesa: each backend opens its own library when it is chosen, so a slave that
// uses OSMesa never loads glvnd's GL and the two dispatch tables never mix.
//
// Libraries are never closed: Mesa's drivers keep thread-local state and atexit handlers that
// outlive their contexts, and unloading them under a running process is a known crash source.
#pragma once

#include <dlfcn.h>

#include <initializer_list>
#include <string>

namespace glcast::slave {

// Opens the first library of `names` that loads (RTLD_LOCAL: its gl* symbols stay private).
// nullptr with `error` set to "<backend>: cannot load <names>: <dlerror>" otherwise.
inline void* open_library(const char* backend, std::initializer_list<const char*> names,
                          std::string& error) {
    std::string tried, last;
    for (const char* n : names) {
        if (void* h = dlopen(n, RTLD_NOW | RTLD_LOCAL)) return h;
        if (const char* e = dlerror()) last = e;
        tried += tried.empty() ? n : std::string(" or ") + n;
    }
    error = std::string(backend) + ": cannot load " + tried + (last.empty() ? "" : ": " + last);
    return nullptr;
}

// Looks `name` up in `lib` into the typed pointer `fn`; false with `error` set when missing.
template <class Fn>
bool load_symbol(const char* backend, void* lib, const char* name, Fn& fn, std::string& error) {
    fn = reinterpret_cast<Fn>(dlsym(lib, name));
    if (fn) return true;
    error = std::string(backend) + ": symbol " + name + " missing from the driver library";
    return false;
}

// load_symbol for each pair of `name, fn` in turn, up to the first that is missing.
template <class Fn, class... More>
bool load_symbols(const char* backend, void* lib, std::string& error, const char* name, Fn& fn,
                  More&... more) {
    if (!load_symbol(backend, lib, name, fn, error)) return false;
    if constexpr (sizeof...(more) > 0) return load_symbols(backend, lib, error, more...);
    return true;
}

}  // namespace glcast::slave
