"""How the slave replays each command: which parameters are object names (and of which
namespace), which calls generate or delete names, and which are not repeated at all.

Object names come from gl.xml's `class` attributes, completed by commands.yaml `slave:`.
"""
import fnmatch
import re

NOT_REPLAYED = {"reply_only": 1, "skip": 2, "window_system": 3, "unserializable": 5}


def ns_id(name):
    return re.sub(r"\W+", "_", name)


class SlavePlanner:
    def __init__(self, annotations):
        s = annotations["slave"]
        self.name_classes = s.get("name_classes") or {}
        self.name_classes_by = s.get("name_classes_by") or {}
        self.namespaces = s["namespaces"]
        self.uniform_patterns = s.get("uniform_locations") or []
        self.handwritten = set(s.get("handwritten") or [])
        self.skip = s.get("skip") or []
        self.may_be_null = s.get("may_be_null") or []
        self.used_null_patterns = set()
        self.limits = s.get("limits") or {}
        self.stores = s.get("stores") or {}
        self.used_limit_patterns = set()

    def namespace(self, cls):
        """gl.xml class -> the name map it lives in (shader names share the program map)."""
        if cls is None:
            return None
        spec = self.namespaces.get(cls)
        if spec is None:
            raise ValueError(f"gl.xml class '{cls}' has no namespace in commands.yaml slave.namespaces")
        return ns_id((spec or {}).get("same_as", cls))

    def namespace_table(self):
        return [(ns_id(n), bool((spec or {}).get("per_context"))) for n, spec in self.namespaces.items()
                if not (spec or {}).get("same_as")]

    @staticmethod
    def need(role, w):
        """The element count the driver reads from (or, for a generator, writes to) the array,
        as a C++ expression of the replay function's locals: the shim's length expression, its
        `sz.` answered by the slave's own driver (slave/replay_sizes.h). The slave refuses a
        record that is shorter and sizes outputs by it."""
        if role not in ("in", "names_in", "names_delete", "gen_out", "out", "out_string") or not w.len:
            return None
        return w.len

    def name_class_by(self, name, twin, param, param_names):
        """commands.yaml slave.name_classes_by for the parameter (by the command's name or its core
        twin's): {"index": the deciding parameter's index, "cases": [(GL enum, ns)], "default": ns
        or None}, or None."""
        spec = self.name_classes_by.get(f"{name}.{param}") or self.name_classes_by.get(f"{twin}.{param}")
        if not spec:
            return None
        if spec["by"] not in param_names:
            raise ValueError(f"commands.yaml slave.name_classes_by {name}.{param}: no parameter '{spec['by']}'")
        cases = [(k, self.namespace(v)) for k, v in spec.items() if k not in ("by", "else")]
        default = self.namespace(spec["else"]) if "else" in spec else None
        return {"index": param_names.index(spec["by"]), "cases": cases, "default": default}

    def null_ok(self, name, twin, param):
        """Whether the parameter is on commands.yaml's slave.may_be_null list (by the command's
        name or its core twin's)."""
        hits = [pat for pat in self.may_be_null for n in (name, twin) if n and fnmatch.fnmatchcase(f"{n}.{param}", pat)]
        self.used_null_patterns.update(hits)
        return bool(hits)

    def plan(self, p):
        """Adds p.replay (how, or None when not replayed), p.replay_fn and p.replay_params.
        Reads p.sem (semantics.py): a twin of a hand-written command shares its function."""
        cmd = p.cmd
        twin = p.sem["twin"]
        p.replay = "generated"
        p.replay_fn = "replay_" + cmd.name
        if not p.serializable:
            p.replay = "unserializable"
        elif cmd.api != "gl":
            p.replay = "window_system"
        elif cmd.name in self.handwritten or twin in self.handwritten:
            p.replay = "handwritten"
            p.replay_fn = "replay_special::" + (cmd.name if cmd.name in self.handwritten else twin)
        elif any(fnmatch.fnmatchcase(cmd.name, pat) for pat in self.skip):
            p.replay = "skip"
        elif p.reply_only:
            p.replay = "reply_only"
        p.replay_params = []
        p.replay_ret = None
        p.replay_limits = []
        p.replay_store = None
        p.replay_sized = False
        if p.replay not in ("generated", "reply_only"):
            return
        deleting = p.sem["deletes"]
        uniform = any(fnmatch.fnmatchcase(cmd.name, pat) for pat in self.uniform_patterns)
        param_names = [x.name for x in cmd.params]
        for i, (q, w) in enumerate(zip(cmd.params, p.params)):
            cls = self.name_classes.get(f"{cmd.name}.{q.name}", q.name_class)
            ns = self.namespace(cls)
            role = w.kind
            by = self.name_class_by(cmd.name, twin, q.name, param_names)
            if by and w.kind == "value":
                role = "name_by"
            elif uniform and q.name == "location" and w.kind == "value":
                role = "uniform_location"
            elif ns and w.kind == "value":
                role = "name_delete" if deleting else "name"
            elif ns and w.kind == "in":
                role = "names_delete" if deleting else "names_in"
            elif ns and w.kind == "out":
                role = "gen_out"
            use = "Use"
            if role in ("name", "names_in") and (ns in p.sem["first_use_namespaces"] or p.sem["created_param"] == i):
                use = "CreateAtFirstUse"
            elif role in ("name_delete", "names_delete"):
                use = "Delete"
            elif role == "name" and p.sem["asks_about"]:
                use = "AskAbout"
            p.replay_params.append({"role": role, "ns": ns, "ctype": q.ctype, "name": q.name, "base": q.base,
                                    "use": use, "source": w.source, "need": self.need(role, w),
                                    "count": w.count, "lengths": w.lengths,
                                    "lengths_index": ([x.name for x in cmd.params].index(w.lengths)
                                                      if w.lengths in [x.name for x in cmd.params] else -1),
                                    "null_ok": self.null_ok(cmd.name, twin, q.name), "by": by})
        p.replay_limits = self.limits_of(p)
        p.replay_store = self.store_of(p)
        p.replay_sized = (any("sz." in (a["need"] or "") for a in p.replay_params) or bool(p.draw)
                          or "sz." in ((p.replay_store or {}).get("bytes") or ""))
        if p.ret and cmd.ret_class:
            p.replay_ret = self.namespace(self.name_classes.get(f"{cmd.name}.return", cmd.ret_class))
        has_program = "program" in [q.name for q in cmd.params]
        p.uniform_program = "program" if (uniform and has_program) else None

    def limits_of(self, p):
        """[(parameter index, limit)] from commands.yaml slave.limits: values the slave checks
        against ReplayLimits before the call. A twin is matched by its core command's name."""
        out = []
        names = [q.name for q in p.cmd.params]
        candidates = [p.cmd.name] + ([p.sem["twin"]] if p.sem.get("twin") else [])
        for limit, table in self.limits.items():
            for pattern, params in table.items():
                if not any(fnmatch.fnmatchcase(n, pattern) for n in candidates):
                    continue
                self.used_limit_patterns.add(pattern)
                for q in params:
                    if q not in names:
                        raise ValueError(f"commands.yaml slave.limits.{limit}: {p.cmd.name} has no parameter '{q}'")
                    out.append((names.index(q), limit))
        return out

    def check_may_be_null(self):
        unused = sorted(set(self.may_be_null) - self.used_null_patterns)
        if unused:
            raise ValueError("commands.yaml slave.may_be_null: entries that name no replayed command's array: " +
                             ", ".join(unused))

    def check_limits(self):
        unused = sorted({pat for t in self.limits.values() for pat in t} - self.used_limit_patterns)
        if unused:
            raise ValueError("commands.yaml slave.limits: patterns that match no replayed command: " + ", ".join(unused))

    def store_of(self, p):
        """commands.yaml slave.stores for this command or its twin: {bytes, key} as C++, where key
        names the image the call replaces (kWholeStore: the object's whole store)."""
        names = [p.cmd.name] + ([p.sem["twin"]] if p.sem.get("twin") else [])
        spec = next((self.stores[n] for n in names if n in self.stores), None)
        if spec is None:
            return None
        if p.sem.get("writes") is None:
            raise ValueError(f"commands.yaml slave.stores: {p.cmd.name} writes no object in semantics.yaml writes")
        params = [q.name for q in p.cmd.params]
        image = spec.get("image") or []
        for q in image:
            if q not in params:
                raise ValueError(f"commands.yaml slave.stores: {p.cmd.name} has no parameter '{q}'")
        key = f"store_key({image[0]}, {image[1]})" if image else "kWholeStore"
        return {"bytes": str(spec["bytes"]), "key": key}
