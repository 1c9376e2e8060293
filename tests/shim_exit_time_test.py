#!/usr/bin/env python3
"""The shim registers nothing to run at exit but the drain and the close of its stream.

A program calls GL from its exit handlers, its libraries' destructors and its threads' exits, in an
order nobody controls; a global of the shim's destroyed before such a call is freed memory under
it (Mesa's piglit tests aborted at exit on glibc's heap checks, and their captures were empty).
So every object of the shim that such a call can reach is Immortal (common/immortal.h), and its
per-thread state is freed by a pthread key (interceptor/lifetime.cpp). This test reads the
shim's machine code: the only functions that may register an exit-time function are the shim's
own destructor (interceptor/lifetime.cpp's shim_fini, which registers the stream's close) and its
constructor (shim_init, which registers the drain before the libraries' destructors), and no
thread_local object may have a destructor (__cxa_thread_atexit_impl). A new global std::map, a
function-local static std::string or a thread_local with a destructor anywhere in the shim fails
it, naming the function that registers it.

    shim_exit_time_test.py LIBGLCAST_SO
"""
import re
import subprocess
import sys

ALLOWED = {"glcast::shim_fini()", "glcast::shim_init()"}


def registrations(path):
    """{function: [registering calls]} from objdump's disassembly of `path`."""
    text = subprocess.run(["objdump", "-d", "--no-show-raw-insn", "-C", path], capture_output=True, text=True,
                          check=True).stdout
    found = {}
    function = None
    for line in text.splitlines():
        m = re.match(r"^[0-9a-f]+ <(.*)>:$", line)
        if m:
            function = re.sub(r"\.cold$", "", m.group(1))
            continue
        m = re.search(r"\b(call|jmp)\s+[0-9a-f]+ <(__cxa_atexit|__cxa_thread_atexit_impl|__cxa_thread_atexit|atexit)@plt>",
                      line)
        if m and function and not function.endswith("@plt"):
            found.setdefault(function, []).append(m.group(2))
    return found


def main():
    found = registrations(sys.argv[1])
    wrong = {f: calls for f, calls in found.items() if f not in ALLOWED}
    for f, calls in sorted(wrong.items()):
        print(f"shim_exit_time: {f} registers {', '.join(sorted(set(calls)))}: an object destroyed at exit "
              f"(make it Immortal, common/immortal.h)")
    missing = ALLOWED - set(found)
    for f in sorted(missing):
        print(f"shim_exit_time: {f} registers nothing: the stream is no longer closed at exit")
    print(f"{len(found)} functions register exit-time calls; allowed {len(ALLOWED)}")
    failed = bool(wrong or missing)
    print(f"{0 if failed else 1} passed, {1 if failed else 0} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
