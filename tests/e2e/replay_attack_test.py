#!/usr/bin/env python3
"""Malicious streams: a committed capture with one tuple edited (tests/stream_edit.cpp keeps the
framing correct, so the decoder accepts it) must be refused by the slave's own checks: exit 1
or 2, a message naming frame, call and command, no signal, bounded memory and time.

    replay_attack_test.py STREAM_EDIT GLCAST DATA_DIR OUT_DIR [--report] [CASE...]

--report prints each case's outcome without judging it (what a build without the checks does).
"""
import os
import re
import resource
import subprocess
import sys
import tempfile
import time

# name: (capture, edits, what the refusal message says[, more replay options])
CASES = {
    # reads past the arrays the stream shipped
    "buffer_data_size": ("core_scene", ["glBufferData.arg1=0x30000000"], r"glBufferData: data has \d+ elements"),
    "buffer_data_huge": ("core_scene", ["glBufferData.arg1=0x100000000"], r"glBufferData: size \d+ is over the limit buffer_bytes"),
    "buffer_subdata_size": ("core_scene", ["glBufferSubData.arg2=0x10000000"], r"glBufferSubData: data has \d+ elements"),
    "tex_image_size": ("ff_scene", ["glTexImage2D.arg3=4096", "glTexImage2D.arg4=4096"],
                       r"glTexImage2D: pixels has 12288 elements, the call reads 50331648"),
    # the slave's own pixel-store state makes the upload read more than shipped
    "tex_image_row_length": ("ff_scene", ["glBindTexture:after=glPixelStorei(0x0cf2,100000)"],
                             r"glTexImage2D: pixels has 12288 elements, the call reads \d+"),
    # an array sized by its pname (4 floats for GL_POSITION), one shipped
    "light_params_short": ("ff_scene", ["glClear:after=glLightfv(0x4000,0x1203,d:0000803f)"],
                           r"glLightfv: params has 1 elements, the call reads 4"),
    # indices in the element buffer, past its end
    "draw_elements_buffer_end": ("core_scene", ["glDrawElements.arg1=1000000"],
                                 r"glDrawElements: indices reads or writes bytes 72\.\.2000072 of the bound buffer, which has \d+"),
    "draw_arrays_count": ("ff_scene", ["glDrawArrays.arg2=1000000"], r"glDrawArrays: the draw reads vertices"),
    "draw_arrays_first": ("ff_scene", ["glDrawArrays.arg1=1000000"], r"glDrawArrays: the draw reads vertices"),
    "draw_elements_indices": ("ff_scene", ["glDrawElements.arg3:fill=0x7f"], r"glDrawElements: the draw reads vertices"),
    "delete_textures_n": ("ff_scene", ["glClear:after=glDeleteTextures(0x7fffffff,d:01000000)"],
                          r"glDeleteTextures: textures has 1 elements, the call reads 2147483647"),
    "draw_buffers_n": ("core_scene", ["glClear:after=glDrawBuffers(100000,d:05040000)"],
                       r"glDrawBuffers: bufs has 1 elements, the call reads 100000"),
    "shader_source_count": ("core_scene", ["glShaderSource.arg1=100000"], r"glShaderSource: glShaderSource of 100000 strings"),
    # lengths past the strings shipped (the driver, or a shader's patch, would read that far)
    "shader_source_lengths": ("core_scene", ["glShaderSource.arg3:fill=0x7f"],
                              r"glShaderSource: string 0 is 2139062143 bytes long by its lengths, the stream holds \d+"),
    "call_lists_n": ("glxgears", ["glClear:after=glCallLists(0x7fffffff,0x1405,d:01000000)"],
                     r"glCallLists: glCallLists of 2147483647 lists"),
    # writes to addresses the stream chooses
    "get_integer_offset": ("glfw_dynamic", ["glGetIntegerv.arg1:offset=0x414141410000"],
                           r"glGetIntegerv: data is a buffer offset, but it takes none"),
    "read_pixels_offset": ("ff_scene", ["glClear:after=glReadPixels(0,0,4,4,0x1908,0x1401,o:0x414141410000)"],
                           r"glReadPixels: pixels is buffer offset \d+ with no buffer bound"),
    "get_buffer_subdata_offset": ("core_scene", ["glClear:after=glGetBufferSubData(0x8892,0,64,o:0x414141410000)"],
                                  r"glGetBufferSubData: data is a buffer offset, but it takes none"),
    # an answer larger than the master's reply: the slave sizes it by its own state (--verify
    # executes reply-only calls)
    "get_tex_image_reply": ("ff_scene", ["glTexImage2D:after=glGetTexImage(0x0de1,0,0x1908,0x1401,r:16)"],
                            r"glGetTexImage: pixels: the master's reply has 16 elements, the slave's state says the call writes 16384",
                            ["--verify"]),
    "gen_textures_n": ("ff_scene", ["glGenTextures.arg0=100000"], r"glGenTextures: textures: the call generates 100000"),
    "gen_buffers_n": ("core_scene", ["glGenBuffers.arg0=100000"], r"glGenBuffers: buffers: the call generates 100000"),
    # tests/apps_extra/client_draws.c: instanced draws with a per-instance client array, indices in an
    # element buffer over client vertices, multi-draws
    "instance_count": ("client_draws", ["glDrawElementsInstanced.arg4=1000"],
                       r"glDrawElementsInstanced: the draw reads elements 0\.\.999 of a per-instance array"),
    "base_instance": ("client_draws", ["glDrawArraysInstancedBaseInstance.arg4=100000"],
                      r"glDrawArraysInstancedBaseInstance: the draw reads elements 100000\.\.100001 of a per-instance array"),
    "element_buffer_indices": ("client_draws", ["glBufferData.arg2:fill=0x7f"],
                               r"glDrawElements: the draw reads vertices 32639\.\.32639, the client arrays shipped hold 0\.\.9"),
    # an element buffer left bound (the unbind's target edited away): the client index arrays
    # shipped as data would be taken for offsets into it (found by the replay fuzzer)
    "index_data_under_buffer": ("client_draws", ["glBindBuffer#3.arg0=0"],
                                r"glMultiDrawElements: indices is data from the stream, but a buffer is bound"),
    # indices retagged NULL with no element buffer bound: GL reads client memory at address 0
    # (found by the replay fuzzer)
    "null_indices_no_buffer": ("client_draws", ["glDrawElementsInstanced.arg3:null=0"],
                               r"glDrawElementsInstanced: indices is NULL, the call reads 48 elements"),
    # a count whose length expression overflowed 32 bits before it was checked (found by the
    # replay fuzzer; UBSan)
    "uniform_count_overflow": ("core_scene", ["glUniformMatrix3fv.arg1=0x80000000"],
                               r"glUniformMatrix3fv: value: the slave cannot compute how much the call reads"),
    # an input array retagged as a client address (data that never travels): GL got NULL
    # (found by the replay fuzzer)
    "client_address_input": ("core_scene", ["glUniformMatrix4fv.arg3:client=0xffffffffffffffff"],
                             r"glUniformMatrix4fv: value is a client address, not data"),
    "multi_draw_drawcount": ("client_draws", ["glMultiDrawElements.arg4=1000"],
                             r"glMultiDrawElements: count has 2 elements, the call reads 1000"),
    "multi_draw_index_count": ("client_draws", ["glMultiDrawElements.arg1:fill=0x7f"],
                               r"glMultiDrawElements: index array 0 has 24 bytes, the draw reads \d+"),
    "multi_draw_arrays_count": ("client_draws", ["glMultiDrawArrays.arg2:fill=0x01"],
                                r"glMultiDrawArrays: the draw reads vertices 0\.\.16843008"),
    "client_first_byte": ("ff_scene", ["client_arrays#1.first_byte=0x40000000"], r"glDrawArrays: the draw reads vertices"),
    # allocations and loops without bound
    "gen_lists_range": ("ff_scene", ["glGenLists.arg0=0x10000000"], r"glGenLists: list range \d+ is over"),
    "delete_lists_range": ("glxgears", ["glClear:after=glDeleteLists(1,0x7fffffff)"], r"glDeleteLists: list range \d+ is over"),
    "null_strings": ("core_scene", ["glShaderSource.arg2:nulls=0x4000000"], r"array list of 67108864 entries is over the limit"),
    "drawable_size": ("glxgears", ["drawable_size.width=30000", "drawable_size.height=30000"],
                      r"glcast.drawable_size: drawable of 30000x30000 is over"),
    "contexts": ("glxgears", ["context:repeat=3000"], r"glcast.context: context \d+ would be one more than the limit"),
    # data stores: one texture of 4 GiB, and a limit below what the capture's textures take
    "texture_store": ("ff_scene", ["glClear:after=glTexImage2D(0x0de1,0,0x8814,16384,16384,0,0x1908,0x1406,n)"],
                      r"glTexImage2D: a data store of 4294967296 bytes would bring the live objects' stores to \d+ "
                      r"bytes, over the limit object_bytes=4294967296"),
    "object_bytes_limit": ("ff_scene", [], r"glTexImage2D: a data store of \d+ bytes would bring the live objects' "
                           r"stores to \d+ bytes, over the limit object_bytes=20000", ["--limit", "object_bytes=20000"]),
    # a copy evicted under a small cache: the draw after the refused tuple must not read it
    "client_cache_evicted": ("ff_scene", [], r"glDrawElements: the client arrays of the draw were refused",
                             ["--limit", "client_array_bytes=30000"]),
}

BACKENDS = ["egl", "osmesa"]
TIMEOUT_S = 60
MAX_RSS_KIB = 1536 * 1024


def run(cmd):
    """(rc or -signal, stderr, max RSS in KiB, seconds, timed out)"""
    start = time.time()
    # stderr into a file, read when the child is done: wait4 reaps it with its rusage, and a
    # pipe nobody reads would block a child that reports thousands of refusals
    log = tempfile.TemporaryFile()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=log)
    timed_out = False
    while True:
        pid, status, usage = os.wait4(p.pid, os.WNOHANG)
        if pid:
            break
        if time.time() - start > TIMEOUT_S:
            p.kill()
            timed_out = True
            pid, status, usage = os.wait4(p.pid, 0)
            break
        time.sleep(0.05)
    log.seek(0)
    err = log.read().decode(errors="replace")
    p.returncode = 0  # reaped by wait4
    rc = -os.WTERMSIG(status) if os.WIFSIGNALED(status) else os.WEXITSTATUS(status)
    return rc, err, usage.ru_maxrss, time.time() - start, timed_out


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    report = "--report" in sys.argv
    edit, glcast, data_dir, out_dir = args[:4]
    names = args[4:] or list(CASES)
    os.makedirs(out_dir, exist_ok=True)
    failures = 0
    for name in names:
        capture, edits, expected = CASES[name][:3]
        extra = CASES[name][3] if len(CASES[name]) > 3 else []
        edited = os.path.join(out_dir, name + ".glcs")
        subprocess.run([edit, os.path.join(data_dir, capture + ".glcs"), edited] + edits, check=True)
        for backend in BACKENDS:
            rc, err, rss, secs, timed_out = run([glcast, "replay", edited, "--backend", backend] + extra)
            outcome = ("timeout after %ds" % TIMEOUT_S if timed_out else
                       "signal %d" % -rc if rc < 0 else "exit %d" % rc)
            line = "%-22s %-7s %-18s rss %7d MiB %6.1fs" % (name, backend, outcome, rss // 1024, secs)
            problems = []
            if not report:
                if timed_out or rc < 0 or rc not in (1, 2):
                    problems.append(outcome)
                if rss > MAX_RSS_KIB:
                    problems.append("rss %d MiB" % (rss // 1024))
                if not re.search(expected, err):
                    problems.append("no message /%s/" % expected)
                if not re.search(r"(frame \d+, call \d+|at byte \d+)", err):
                    problems.append("no frame and call in the message")
            first = next((l for l in err.splitlines() if "glcast replay" in l), "")
            print(line + ("  FAIL: " + "; ".join(problems) if problems else "") + "\n    " + first[:200])
            failures += bool(problems)
    return 1 if failures else 0


if __name__ == "__main__":
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    sys.exit(main())
