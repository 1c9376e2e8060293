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
        self.namespaces = s["namespaces"]
        self.uniform_patterns = s.get("uniform_locations") or []
        self.handwritten = set(s.get("handwritten") or [])
        self.skip = s.get("skip") or []
        self.never_null = s.get("never_null") or []

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
        as a C++ expression of the replay function's locals: the slave refuses a record that
        is shorter. None where the count needs the driver's state (`sz.`, the master's size
        queries); slave/bounds.cpp checks the families of those that matter by hand."""
        if role not in ("in", "names_in", "names_delete", "gen_out") or not w.len or "sz." in w.len:
            return None
        return w.len

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
        if p.replay not in ("generated", "reply_only"):
            return
        deleting = p.sem["deletes"]
        uniform = any(fnmatch.fnmatchcase(cmd.name, pat) for pat in self.uniform_patterns)
        for i, (q, w) in enumerate(zip(cmd.params, p.params)):
            cls = self.name_classes.get(f"{cmd.name}.{q.name}", q.name_class)
            ns = self.namespace(cls)
            role = w.kind
            if uniform and q.name == "location" and w.kind == "value":
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
            p.replay_params.append({"role": role, "ns": ns, "ctype": q.ctype, "name": q.name, "base": q.base,
                                    "use": use, "source": w.source, "need": self.need(role, w),
                                    "null_ok": not any(fnmatch.fnmatchcase(cmd.name, pat) for pat in self.never_null)})
        if p.ret and cmd.ret_class:
            p.replay_ret = self.namespace(self.name_classes.get(f"{cmd.name}.return", cmd.ret_class))
        has_program = "program" in [q.name for q in cmd.params]
        p.uniform_program = "program" if (uniform and has_program) else None
