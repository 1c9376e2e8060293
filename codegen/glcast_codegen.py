#!/usr/bin/env python3
"""glcast's code generator: Khronos registry + annotations -> C++ in the build tree.

    glcast_codegen.py --out DIR            generate every file
    glcast_codegen.py --report             coverage per GL version and for extensions
    glcast_codegen.py --print-cmake-outputs / --print-cmake-dependencies
"""
import argparse
import collections
import glob
import hashlib
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

try:
    import jinja2
    import yaml
except ImportError as e:  # CMake turns this into a configure error
    sys.exit(f"glcast-codegen: {e}; install python3-jinja2 and python3-yaml (scripts/setup.sh)")

import registry
from classify import Classifier, WIRE_BYTES
import synthetic
import client_arrays
from semantics import Semantics, SemanticsError
from slave_plan import SlavePlanner, ns_id
from snapshot import SnapshotModel, SnapshotError

REGISTRY_DIR = os.environ.get("GLCAST_REGISTRY_DIR", "/usr/share/khronos-api")
TEMPLATES = os.path.join(HERE, "templates")
OUTPUTS = {  # template -> generated file
    "commands.h.j2": "glcast_commands.h",
    "commands.cpp.j2": "glcast_commands.cpp",
    "encode.h.j2": "glcast_encode.h",
    "encode.cpp.j2": "glcast_encode.cpp",
    "pnames.h.j2": "glcast_pnames.h",
    "pnames.cpp.j2": "glcast_pnames.cpp",
    "entrypoints.cpp.j2": "glcast_entrypoints.cpp",
    "special.h.j2": "glcast_special.h",
    "roundtrip_test.cpp.j2": "glcast_roundtrip_test.cpp",
    "slave_dispatch.h.j2": "glcast_slave_dispatch.h",
    "slave_dispatch.cpp.j2": "glcast_slave_dispatch.cpp",
    "gl_api.h.j2": "glcast_gl_api.h",
    "gl_api.cpp.j2": "glcast_gl_api.cpp",
    "synthetic.h.j2": "glcast_synthetic.h",
    "synthetic.cpp.j2": "glcast_synthetic.cpp",
    "synthetic_encode.h.j2": "glcast_synthetic_encode.h",
    "snapshot_state.h.j2": "glcast_snapshot_state.h",
    "snapshot_state.cpp.j2": "glcast_snapshot_state.cpp",
    "recording_gl.cpp.j2": "glcast_recording_gl.cpp",
    "client_arrays.h.j2": "glcast_client_arrays.h",
}


class Model:
    def __init__(self):
        ann_dir = os.path.join(HERE, "annotations")
        with open(os.path.join(ann_dir, "commands.yaml")) as f:
            self.annotations = yaml.safe_load(f)
        with open(os.path.join(ann_dir, "pnames.yaml")) as f:
            self.pnames = yaml.safe_load(f)["tables"]
        with open(os.path.join(ann_dir, "semantics.yaml")) as f:
            self.semantics_spec = yaml.safe_load(f)
        with open(os.path.join(ann_dir, "synthetic.yaml")) as f:
            try:
                self.synthetic = synthetic.load(yaml.safe_load(f))
            except synthetic.SyntheticError as e:
                sys.exit(f"glcast-codegen: {e}")
        with open(os.path.join(ann_dir, "handwritten.txt")) as f:
            self.handwritten = [l.split("#")[0].strip() for l in f if l.split("#")[0].strip()]

        gl, gl_enums, gl_groups = registry.load(os.path.join(REGISTRY_DIR, "gl.xml"), "gl")
        glx, glx_enums, _ = registry.load(os.path.join(REGISTRY_DIR, "glx.xml"), "glx")
        egl = [registry.parse_signature(s, "egl") for s in self.annotations["egl"]]
        unavailable = set(self.annotations.get("unavailable_types") or [])
        self.commands = [c for c in gl + glx + egl if not any(p.base in unavailable for p in c.params)]
        self.enums, self.groups = gl_enums, gl_groups
        self.glx_enums = glx_enums
        self.check_handwritten()

        classifier = Classifier(self.annotations, self.pnames, {**gl_enums, **glx_enums})
        self.plans = [classifier.plan(c, i, set(self.handwritten)) for i, c in enumerate(self.commands)]
        self.add_sample_pnames(classifier)
        try:
            self.semantics = Semantics(self.semantics_spec, self.commands, {**gl_enums, **glx_enums}, ns_id)
            for p in self.plans:
                self.semantics.plan(p)
            self.semantics.check_patterns()
        except SemanticsError as e:
            sys.exit(f"glcast-codegen: {e}")
        self.slave = SlavePlanner(self.annotations)
        try:
            for p in self.plans:
                self.slave.plan(p)
            self.slave.check_limits()
            self.slave.check_may_be_null()
        except ValueError as e:
            sys.exit(f"glcast-codegen: {e}")
        self.check_annotations()
        self.check_slave_handwritten()
        with open(os.path.join(ann_dir, "client_arrays.yaml")) as f:
            try:
                self.client_arrays = client_arrays.load(yaml.safe_load(f), self.plans, self.enums)
            except client_arrays.ClientArraysError as e:
                sys.exit(f"glcast-codegen: {e}")
        with open(os.path.join(ann_dir, "snapshot.yaml")) as f:
            try:
                self.snapshot = SnapshotModel(yaml.safe_load(f), self.commands, self.enums, self.get_counts())
            except SnapshotError as e:
                sys.exit(f"glcast-codegen: {e}")
        serializable = {p.cmd.name for p in self.plans if p.serializable}
        for section in self.snapshot.values.values():
            for r in section:
                if r["set"] not in serializable:
                    sys.exit(f"glcast-codegen: snapshot.yaml: {r['set']} is not serializable")
        for pair in self.snapshot.pairs:
            if pair["setter"] not in serializable:
                sys.exit(f"glcast-codegen: snapshot.yaml: {pair['set']} is not serializable")

    def get_counts(self):
        """pname -> values of glGet (pnames.yaml `get`; 1 for the rest of its groups)."""
        spec = self.pnames["get"]
        counts = {e: 1 for g in spec.get("groups_default_1") or [] for e in self.groups.get(g, [])}
        counts.update(spec.get("counts") or {})
        return counts

    def add_sample_pnames(self, classifier):
        """For the round-trip test: a pname each table knows, so enum-sized arrays encode."""
        first = {}
        for t in self.pname_tables():
            for body, names in t["cases"]:
                if body != "-1":
                    first.setdefault(t["name"], names[0][0])
        for p in self.plans:
            table = classifier.lookup(classifier.table_of, p.cmd)
            p.sample_pname = first.get(table) if table else None
            names = [q.name for q in p.cmd.params]
            p.sample_param = next((k for k in ("pname", "query", "buffer", "target") if k in names), None)

    def check_handwritten(self):
        names = {c.name for c in self.commands}
        missing = [h for h in self.handwritten if h not in names]
        if missing:
            sys.exit(f"glcast-codegen: handwritten.txt names commands the registry does not have: {missing}")
        special = os.path.join(HERE, "..", "interceptor", "special")
        defined = set()
        for path in glob.glob(os.path.join(special, "*.cpp")):
            with open(path) as f:
                defined |= set(re.findall(r"^\S.*\bspecial::(\w+)\(", f.read(), re.M))
        if os.path.isdir(special) and defined != set(self.handwritten):
            sys.exit("glcast-codegen: interceptor/special/*.cpp and handwritten.txt disagree:\n"
                     f"  listed, not defined: {sorted(set(self.handwritten) - defined)}\n"
                     f"  defined, not listed: {sorted(defined - set(self.handwritten))}")

    def check_slave_handwritten(self):
        """The slave's hand-written replay (commands.yaml slave.handwritten) against the
        `replay_special::NAME` functions slave/special/*.cpp defines, as for the shim."""
        listed = set(self.slave.handwritten)
        names = {c.name for c in self.commands}
        if listed - names:
            sys.exit(f"glcast-codegen: commands.yaml slave.handwritten names unknown commands: {sorted(listed - names)}")
        special = os.path.join(HERE, "..", "slave", "special")
        if not os.path.isdir(special):
            return
        defined = set()
        for path in glob.glob(os.path.join(special, "*.cpp")):
            with open(path) as f:
                defined |= set(re.findall(r"^void (gl\w+)\(CallReplay& \w+, const Call& \w+\)", f.read(), re.M))
        if defined != listed:
            sys.exit("glcast-codegen: slave/special/*.cpp and commands.yaml slave.handwritten disagree:\n"
                     f"  listed, not defined: {sorted(listed - defined)}\n"
                     f"  defined, not listed: {sorted(defined - listed)}")

    def check_annotations(self):
        names = {c.name: c for c in self.commands}
        for key in list(self.annotations.get("params") or {}) + list(self.annotations.get("egl_params") or {}):
            cmd, _, param = key.partition(".")
            if cmd in names and param not in {p.name for p in names[cmd].params}:
                sys.exit(f"glcast-codegen: commands.yaml: {key}: {cmd} has no parameter '{param}'")
        for table, cmds in self.annotations["pname_tables"].items():
            for c in cmds:
                if c not in names:
                    sys.exit(f"glcast-codegen: commands.yaml pname_tables.{table}: unknown command {c}")

    def shim_answers(self):
        """commands.yaml answered_by_shim: [(value, name, count or None for a list)], checked."""
        spec = self.annotations.get("answered_by_shim") or {}
        names = {c.name: c for c in self.commands}
        for c in spec.get("commands") or []:
            cmd = names.get(c)
            if not cmd or len(cmd.params) != 2 or cmd.params[0].name != "pname":
                sys.exit(f"glcast-codegen: commands.yaml answered_by_shim: {c} is not a glGet*(pname, data) command")
        out = []
        for e, answer in (spec.get("pnames") or {}).items():
            if e not in self.enums:
                sys.exit(f"glcast-codegen: commands.yaml answered_by_shim: unknown enum {e}")
            if answer != [] and not isinstance(answer, int):
                sys.exit(f"glcast-codegen: commands.yaml answered_by_shim.{e}: an integer or [], not {answer!r}")
            out.append((self.enums[e], e, None if answer == [] else answer))
        return out

    def shim_answer_commands(self):
        return set((self.annotations.get("answered_by_shim") or {}).get("commands") or [])

    # -- derived data for templates ------------------------------------------------------
    def table_hash(self):
        h = hashlib.sha256()
        for p in self.plans:
            h.update(f"{p.cmd.name}({','.join(p.cmd.params and [q.ctype for q in p.cmd.params])})"
                     f"{'S' if p.serializable else 'U'}"
                     f"{[(w.kind, w.wire) for w in p.params]}{p.ret and (p.ret.kind, p.ret.wire)};".encode())
        return int.from_bytes(h.digest()[:8], "little")

    def enum_groups(self):
        """The gl.xml groups parameters refer to: [(group, [(value, preferred name)])], with
        each plan's params given a `group` index into that list."""
        used = sorted({q.group for p in self.plans for q in p.cmd.params if q.group in self.groups})
        index = {g: i for i, g in enumerate(used)}
        for p in self.plans:
            p.groups = [index.get(q.group, -1) for q in p.cmd.params]
        out = []
        for g in used:
            best = {}
            for name in self.groups[g]:
                value = self.enums.get(name)
                if value is None or value > 0xFFFFFFFF:
                    continue
                rank = (self.is_extension_name(name), len(name))
                if value not in best or rank < best[value][0]:
                    best[value] = (rank, name)
            out.append((g, sorted((v, n) for v, (r, n) in best.items())))
        return out

    @staticmethod
    def is_extension_name(name):
        return bool(re.search(r"_(ARB|EXT|NV|AMD|ATI|SGIX?|SGIS|OES|KHR|MESA|APPLE|IBM|INTEL|3DFX|"
                              r"HP|IMG|OML|PGI|QCOM|REND|S3|SUN|SUNX|WIN|GREMEDY|INGR|OVR|MESAX|ANGLE)$", name))

    def enum_names(self):
        """value -> preferred name: core names before extension suffixes, first seen wins."""
        best = {}
        for name, value in list(self.enums.items()):
            # 0 and 1 have dozens of names (GL_NONE, GL_ZERO, GL_POINTS, ...): only a group can say which
            if value > 0xFFFFFFFF or value in (0, 1):
                continue
            rank = (self.is_extension_name(name), len(name))
            if value not in best or rank < best[value][0]:
                best[value] = (rank, name)
        return sorted((v, n) for v, (r, n) in best.items())

    def pname_tables(self):
        tables = []
        for tname, spec in self.pnames.items():
            # explicit counts first: a group's default must not win through an alias
            entries = dict(spec.get("counts") or {})
            for g in spec.get("groups_default_1") or []:
                for e in self.groups.get(g, []):
                    entries.setdefault(e, 1)
            rows = collections.OrderedDict()
            for e, count in entries.items():
                if e not in self.enums:
                    sys.exit(f"glcast-codegen: pnames.yaml table {tname}: unknown enum {e}")
                v = self.enums[e]
                if isinstance(count, str) and count.startswith("query:"):
                    q = count[len("query:"):]
                    if q not in self.enums:
                        sys.exit(f"glcast-codegen: pnames.yaml {tname}.{e}: unknown query enum {q}")
                    answered = {name: n for _, name, n in self.shim_answers() if n is not None}
                    if q in answered:  # the count is the shim's answer, not the driver's
                        rows.setdefault(v, (e, str(answered[q])))
                    else:
                        rows.setdefault(v, (e, f"sz.driver_count(0x{self.enums[q]:04x} /* {q} */)"))
                elif count == "unknown":
                    rows.setdefault(v, (e, "-1"))
                else:
                    rows.setdefault(v, (e, str(int(count))))
            # identical bodies share a case label list; numeric labels, since the system's
            # glext.h may predate the registry
            by_body = collections.defaultdict(list)
            for v, (e, body) in rows.items():
                by_body[body].append((v, e))
            tables.append({"name": tname, "cases": sorted(by_body.items())})
        return tables

    def report(self):
        out = []
        groups = collections.OrderedDict()
        for p in self.plans:
            key = p.cmd.origin if p.cmd.is_core else ("GLX extensions" if p.cmd.api == "glx" else
                                                      "EGL" if p.cmd.api == "egl" else "GL extensions")
            groups.setdefault(key, []).append(p)
        out.append(f"{'feature':28} {'serializable':>12} {'total':>6}")
        core_total = core_ok = 0
        for key, plans in groups.items():
            ok = sum(p.serializable for p in plans)
            out.append(f"{key:28} {ok:12} {len(plans):6}")
            if key.startswith(("GL_VERSION", "GLX_VERSION")):
                core_total += len(plans)
                core_ok += ok
        out.append(f"{'GL 1.0-4.6 + GLX 1.4':28} {core_ok:12} {core_total:6}")
        out.append(f"{'all':28} {sum(p.serializable for p in self.plans):12} {len(self.plans):6}")
        out.append("")
        out.append("not serializable (forwarded and counted at run time):")
        for p in self.plans:
            if not p.serializable:
                out.append(f"  {p.cmd.name:48} {p.cmd.origin:32} {p.reason}")
        return "\n".join(out)


def cpp_type(ctype):
    return ctype


def make_env():
    env = jinja2.Environment(loader=jinja2.FileSystemLoader(TEMPLATES), trim_blocks=True,
                             lstrip_blocks=True, undefined=jinja2.StrictUndefined,
                             keep_trailing_newline=True, line_comment_prefix="//*")

    def do_assert(cond, msg):
        if not cond:
            raise jinja2.TemplateError(msg)
        return ""
    env.globals["assert"] = do_assert
    env.globals["wire_bytes"] = WIRE_BYTES
    env.filters["cap"] = lambda s: s[:1].upper() + s[1:]
    env.filters["camel"] = lambda s: "".join(w.capitalize() for w in s.split("_"))
    return env


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", help="output directory (the build tree)")
    ap.add_argument("--report", action="store_true")
    ap.add_argument("--print-cmake-outputs", action="store_true")
    ap.add_argument("--print-cmake-dependencies", action="store_true")
    args = ap.parse_args()

    if args.print_cmake_outputs:
        print(";".join(OUTPUTS.values()))
        return
    if args.print_cmake_dependencies:
        deps = [os.path.join(REGISTRY_DIR, "gl.xml"), os.path.join(REGISTRY_DIR, "glx.xml")]
        deps += sorted(glob.glob(os.path.join(HERE, "*.py")) + glob.glob(os.path.join(HERE, "annotations", "*"))
                       + glob.glob(os.path.join(TEMPLATES, "*.j2"))
                       + glob.glob(os.path.join(HERE, "..", "interceptor", "special", "*.cpp"))
                       + glob.glob(os.path.join(HERE, "..", "slave", "special", "*.cpp")))
        print(";".join(os.path.abspath(d) for d in deps))
        return

    model = Model()
    if args.report:
        print(model.report())
        return
    if not args.out:
        ap.error("--out DIR is required")
    env = make_env()
    ctx = {"plans": model.plans, "enum_groups": model.enum_groups(), "table_hash": model.table_hash(),
           "enum_names": model.enum_names(), "namespaces": model.slave.namespace_table(),
           "pname_tables": model.pname_tables(), "opcode_count": len(model.plans),
           "opcodes": {p.cmd.name: p.opcode for p in model.plans},
           "generators": model.semantics.generators(),
           "window_system_pnames": model.semantics.window_system_pnames(),
           "name_pnames": model.semantics.name_pnames(model.slave.namespaces),
           "state_groups": model.semantics.state_groups, "synthetic": model.synthetic,
           "snapshot": model.snapshot, "shim_answers": model.shim_answers(),
           "shim_answer_commands": model.shim_answer_commands(),
           "client_arrays": model.client_arrays}
    os.makedirs(args.out, exist_ok=True)
    for template, name in OUTPUTS.items():
        text = env.get_template(template).render(**ctx)
        path = os.path.join(args.out, name)
        if not os.path.exists(path) or open(path).read() != text:
            with open(path, "w") as f:
                f.write(text)
    with open(os.path.join(args.out, "codegen_report.txt"), "w") as f:
        f.write(model.report() + "\n")


if __name__ == "__main__":
    main()
