"""What each command means (annotations/semantics.yaml), resolved per plan into `p.sem`.

Every list takes fnmatch patterns and matches a command by its own name or by its twin's (a
gl.xml alias, or an entry of `twins`); parameters are named as the matching entry names them,
and a twin's parameters are found by position when it names them differently.
"""
import fnmatch
import re

from slave_plan import ns_id

VENDOR_SUFFIX = re.compile(r"(ARB|EXT|OES|NV|KHR|AMD|APPLE|ATI|SGIS|SGIX|MESA|INTEL|IBM)$")

MATRIX_OPS = ["mode", "push", "pop", "load", "multiply"]
REDRAW_KINDS = ["state", "draw", "begin", "end", "new_list", "end_list", "pixels", "program_state", "copy", "clear"]
WINDOW_KINDS = ["viewport", "scissor", "viewport_indexed", "scissor_indexed", "viewport_array", "scissor_array",
                "line_width", "point_size", "pixel_zoom", "blit", "draw_framebuffer"]
OBJECT_ACCESS = ["bound", "named"]
CONTEXT_OPS = ["create", "make_current", "swap", "destroy"]
LIST_OPS = ["new", "call", "call_many"]


class SemanticsError(Exception):
    pass


class Semantics:
    def __init__(self, spec, commands, enums, ns_id):
        self.spec = spec
        self.by_name = {c.name: c for c in commands}
        self.enums = enums
        self.ns_id = ns_id
        self.twins = dict(spec.get("twins") or {})
        self.not_twins = dict(spec.get("not_twins") or {})
        self.state_groups = list(spec["state"])
        self.used_patterns = set()
        self.check_twins()

    # -- twins ------------------------------------------------------------------------
    def check_twins(self):
        for ext, core in self.twins.items():
            for n in (ext, core):
                if n not in self.by_name:
                    raise SemanticsError(f"semantics.yaml twins: unknown command {n}")
            a, b = self.by_name[ext], self.by_name[core]
            if [p.ctype for p in a.params] != [p.ctype for p in b.params]:
                raise SemanticsError(f"semantics.yaml twins: {ext} and {core} take different parameters")
        for n in self.not_twins:
            if n not in self.by_name:
                raise SemanticsError(f"semantics.yaml not_twins: unknown command {n}")
        silent = []
        for c in self.by_name.values():
            m = VENDOR_SUFFIX.search(c.name)
            if c.api != "gl" or not m or c.alias or c.name in self.twins or c.name in self.not_twins:
                continue
            if c.name[:m.start()] in self.by_name:
                silent.append(c.name)
        if silent:
            raise SemanticsError("semantics.yaml: extension commands named like a core command that gl.xml does not "
                                 "alias; list each under twins or not_twins: " + ", ".join(sorted(silent)))

    def twin_of(self, cmd):
        return cmd.alias or self.twins.get(cmd.name)

    # -- matching ---------------------------------------------------------------------
    def matches(self, cmd, pattern):
        names = [cmd.name] + ([self.twin_of(cmd)] if self.twin_of(cmd) else [])
        for n in names:
            if fnmatch.fnmatchcase(n, pattern):
                self.used_patterns.add(pattern)
                return n
        return None

    def find(self, cmd, entries):
        """The first pattern of `entries` (a list, or a dict's keys) matching cmd: (pattern, matched name)."""
        for pat in entries:
            n = self.matches(cmd, pat)
            if n:
                return pat, n
        return None, None

    def param_index(self, cmd, matched_name, param, where):
        names = [p.name for p in cmd.params]
        if param in names:
            return names.index(param)
        ref = self.by_name.get(matched_name)
        if ref is not None and param in [p.name for p in ref.params]:
            i = [p.name for p in ref.params].index(param)
            if i < len(names):
                return i
        raise SemanticsError(f"semantics.yaml {where}: {cmd.name} has no parameter '{param}'")

    def params_of(self, cmd, table, where):
        pat, n = self.find(cmd, table)
        if pat is None:
            return None
        return [self.param_index(cmd, n, q, where) for q in (table[pat] or [])]

    # -- the per-command record -------------------------------------------------------
    def plan(self, p):
        cmd = p.cmd
        s = self.spec
        sem = {"twin": self.twin_of(cmd) if self.twin_of(cmd) in self.by_name else None}
        sem["matrix"] = next((op for op in MATRIX_OPS if self.find(cmd, s["matrix"].get(op, []))[0]), None)
        # The parameters naming what the call acts on: the matrix stack, the display list, the
        # program linked (a command is at most one of these).
        sem["subject_params"] = []
        mode = s["matrix"]["mode"]
        if sem["matrix"] == "mode":
            sem["subject_params"] = self.params_of(cmd, mode, "matrix.mode")
        sem["list"] = None
        for k in LIST_OPS:
            idx = self.params_of(cmd, s["lists"].get(k) or {}, f"lists.{k}")
            if idx is not None:
                sem["list"], sem["subject_params"] = k, idx
                break
        names = s["names"]
        sem["deletes"] = bool(self.find(cmd, names["deletes"])[0])
        sem["asks_about"] = bool(self.find(cmd, names["asks_about"])[0])
        first_use = names["created_at_first_use"]
        sem["first_use_namespaces"] = ([self.ns_id(n) for n in first_use["namespaces"]]
                                       if self.find(cmd, first_use["commands"])[0] else [])
        created = self.params_of(cmd, {k: [v] for k, v in names["created_by"].items()}, "names.created_by")
        sem["created_param"] = created[0] if created else -1
        progs = s["programs"]
        use = self.params_of(cmd, {k: [v] for k, v in progs["use"].items()}, "programs.use")
        sem["program_use"] = use[0] if use else -1
        link = self.params_of(cmd, {k: [v] for k, v in progs["link"].items()}, "programs.link")
        sem["links_program"] = link is not None
        if link is not None:
            sem["subject_params"] = link
        if len(sem["subject_params"]) > 2:
            raise SemanticsError(f"semantics.yaml: {cmd.name} names more than 2 parameters it acts on")
        st = self.params_of(cmd, {k: [v] for k, v in progs["shader_type"].items()}, "programs.shader_type")
        sem["shader_type"] = st[0] if st else -1

        redraw = s["redraw"]
        kind = "draw" if p.draw else next((k for k in REDRAW_KINDS if self.find(cmd, redraw.get(k, []))[0]), None)
        sem["redraw"] = kind
        # A draw's primitive mode, from gl.xml's group (lines and points are drawn over a scene's
        # surfaces, not surfaces: slave/scene/scene_classifier.h, marks); -1: none, or an array.
        sem["primitive_param"] = next((i for i, q in enumerate(cmd.params) if q.group == "PrimitiveType" and not q.stars),
                                      -1) if kind in ("draw", "begin") else -1
        pat, _ = self.find(cmd, redraw.get("state_if_first_is") or {})
        sem["redraw_first_values"] = []
        if pat:
            for e in redraw["state_if_first_is"][pat]:
                if e not in self.enums:
                    raise SemanticsError(f"semantics.yaml redraw.state_if_first_is: unknown enum {e}")
                sem["redraw_first_values"].append((self.enums[e], e))

        sem["window"], sem["window_params"] = None, []
        for k in WINDOW_KINDS:
            idx = self.params_of(cmd, s["window"].get(k) or {}, f"window.{k}")
            if idx is not None:
                sem["window"], sem["window_params"] = k, idx
                break
        if len(sem["window_params"]) > 10:
            raise SemanticsError(f"semantics.yaml window: {cmd.name} names more than 10 parameters")

        p.window_query = bool(self.find(cmd, s["window_system_pnames"]["commands"])[0])
        sem["frame_only"] = bool(p.draw) or bool(self.find(cmd, s["frame_only"])[0])

        sem["state"], sem["state_key"] = None, []
        for g in self.state_groups:
            idx = self.params_of(cmd, s["state"][g] or {}, f"state.{g}")
            if idx is not None:
                sem["state"], sem["state_key"] = g, idx[:2]
                break

        sem["writes"], sem["writes_ns"], sem["writes_param"] = None, None, -1
        for access in OBJECT_ACCESS:
            for ns, table in (s["writes"].get(access) or {}).items():
                idx = self.params_of(cmd, table, f"writes.{access}.{ns}")
                if idx is not None and sem["writes"] is None:
                    sem["writes"], sem["writes_ns"], sem["writes_param"] = access, self.ns_id(ns), idx[0]
        sem["context"], sem["context_param"] = None, -1
        for k in CONTEXT_OPS:
            idx = self.params_of(cmd, s["contexts"][k], f"contexts.{k}")
            if idx is not None:
                sem["context"], sem["context_param"] = k, (idx[0] if idx else -1)
                break
        p.sem = sem

    def window_system_pnames(self):
        out = []
        for e in self.spec["window_system_pnames"]["pnames"]:
            if e not in self.enums:
                raise SemanticsError(f"semantics.yaml window_system_pnames: unknown enum {e}")
            out.append((self.enums[e], e))
        return out

    def name_pnames(self, namespaces):
        """[(value, enum, namespace id)] of name_pnames, one per value (gl.xml's aliases share one);
        `namespaces`: the names of commands.yaml slave.namespaces."""
        out, seen = [], {}
        for ns, pnames in self.spec["name_pnames"].items():
            if ns not in namespaces:
                raise SemanticsError(f"semantics.yaml name_pnames: unknown namespace {ns}")
            for e in pnames:
                if e not in self.enums:
                    raise SemanticsError(f"semantics.yaml name_pnames.{ns}: unknown enum {e}")
                v = self.enums[e]
                if v in seen:
                    if seen[v] != ns:
                        raise SemanticsError(f"semantics.yaml name_pnames: {e} is in {seen[v]} and {ns}")
                    continue
                seen[v] = ns
                out.append((v, e, ns_id(ns)))
        return out

    def check_patterns(self):
        """Every pattern must name something: a typo would silently drop a property."""
        s = self.spec
        pats = []
        for section in ("matrix", "redraw", "lists"):
            for v in s[section].values():
                pats += list(v)
        pats += s["names"]["deletes"] + s["names"]["asks_about"] + s["names"]["created_at_first_use"]["commands"] + list(s["names"]["created_by"])
        pats += list(s["programs"]["use"]) + list(s["programs"]["link"]) + list(s["programs"]["shader_type"])
        for v in s["window"].values():
            pats += list(v)
        pats += s["frame_only"] + s["window_system_pnames"]["commands"]
        for v in s["contexts"].values():
            pats += list(v)
        for v in s["state"].values():
            pats += list(v)
        for access in s["writes"].values():
            for v in access.values():
                pats += list(v)
        unused = sorted(set(pats) - self.used_patterns)
        if unused:
            raise SemanticsError("semantics.yaml: patterns that match no command of the registry: " + ", ".join(unused))
        for ns, gen in s["names"]["generators"].items():
            if gen not in self.by_name:
                raise SemanticsError(f"semantics.yaml names.generators.{ns}: unknown command {gen}")

    def generators(self):
        """[(ns id, generator command, returns the name)]"""
        return [(self.ns_id(ns), gen, self.by_name[gen].ret not in (None, "void"))
                for ns, gen in self.spec["names"]["generators"].items()]
