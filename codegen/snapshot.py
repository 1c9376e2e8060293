"""The state a snapshot of live state reads back and sets again (annotations/snapshot.yaml),
checked against gl.xml and laid out for snapshot_state.cpp.j2 as C++ expressions."""
import re

FLOATS = {"GLfloat": "f", "GLclampf": "f", "GLdouble": "d", "GLclampd": "d"}


class SnapshotError(Exception):
    pass


def _query_kind(base):
    return {"f": "Float", "d": "Double"}.get(FLOATS.get(base), "Integer")


class SnapshotModel:
    def __init__(self, spec, commands, enums, get_counts):
        self.by_name = {c.name: c for c in commands}
        self.enums = enums
        self.get_counts = get_counts  # pname -> values of glGet (pnames.yaml `get`)
        self.values = {k: [self._value_setter(row, k) for row in spec[k]] for k in ("values", "values_compatibility", "values_core", "current", "pixel_store")}
        self.enables = {k: [self._enum(e, f"enables.{k}") for e in v] for k, v in spec["enables"].items()}
        self.pairs = [self._pair(name, p) for name, p in spec["pairs"].items()]

    def _enum(self, name, where):
        if name not in self.enums:
            raise SnapshotError(f"snapshot.yaml {where}: unknown enum {name}")
        return {"name": name, "value": f"0x{self.enums[name]:04x}"}

    def _command(self, name, where):
        if name not in self.by_name:
            raise SnapshotError(f"snapshot.yaml {where}: unknown command {name}")
        return self.by_name[name]

    def _value_setter(self, row, section):
        where = f"{section}: {row}"
        cmd = self._command(row[0], where)
        params = list(cmd.params)
        queries, args = [], []
        for a in row[1:]:
            m = re.fullmatch(r"(GL_\w+)\[(\d+)\]", a)
            if a.startswith("="):
                args.append(self._enum(a[1:], where)["value"])
                continue
            pname, index = (m.group(1), int(m.group(2))) if m else (a, None)
            if pname not in self.enums:
                raise SnapshotError(f"snapshot.yaml {where}: unknown enum {pname}")
            count = self.get_counts.get(pname, 1)
            if not isinstance(count, int):
                raise SnapshotError(f"snapshot.yaml {where}: {pname} has no fixed count in pnames.yaml get")
            if len(args) >= len(params):
                raise SnapshotError(f"snapshot.yaml {where}: more values than {cmd.name} takes")
            p = params[len(args)]
            if p.stars:  # a vector setter: the whole query
                kind = _query_kind(p.base)
                queries.append({"pname": pname, "value": f"0x{self.enums[pname]:04x}", "kind": kind,
                                "var": f"q{len(queries)}", "count": count})
                args.append(f"q{len(queries) - 1}")
                continue
            kind = _query_kind(p.base)
            queries.append({"pname": pname, "value": f"0x{self.enums[pname]:04x}", "kind": kind,
                            "var": f"q{len(queries)}", "count": count})
            var = f"q{len(queries) - 1}"
            take = [index] if index is not None else list(range(count))
            for i in take:
                if len(args) >= len(params):
                    raise SnapshotError(f"snapshot.yaml {where}: more values than {cmd.name} takes")
                args.append(f"{params[len(args)].ctype}({var}[{i}])")
        if len(args) != len(params):
            raise SnapshotError(f"snapshot.yaml {where}: {cmd.name} takes {len(params)} values, the row gives {len(args)}")
        return {"set": cmd.name, "queries": queries, "args": args}

    def _pair(self, name, p):
        where = f"pairs.{name}"
        setter, getter = self._command(p["set"], where), self._command(p["get"], where)
        keys = p.get("keys") or {}
        static_keys, runtime_keys = [], []
        for k, values in keys.items():
            if k not in {q.name for q in setter.params}:
                raise SnapshotError(f"snapshot.yaml {where}: {setter.name} has no parameter {k}")
            if values:
                static_keys.append({"name": k, "choices": [self._enum(v, where) for v in values]})
            else:
                ptype = next(q.ctype for q in setter.params if q.name == k)
                runtime_keys.append({"name": k, "ctype": ptype})
        pnames = [self._enum(v, where) for v in p.get("pnames") or []]
        last_set, last_get = setter.params[-1], getter.params[-1]
        tail = (1 if pnames else 0) + 1
        if len(setter.params) != len(keys) + tail:
            raise SnapshotError(f"snapshot.yaml {where}: {setter.name} does not take the keys, a pname and values")
        if len(getter.params) not in (len(keys) + tail, tail):
            raise SnapshotError(f"snapshot.yaml {where}: {getter.name} does not take [the keys,] a pname and values")
        if not last_get.stars:
            raise SnapshotError(f"snapshot.yaml {where}: {getter.name} must return its values through a pointer")
        return {"name": name, "setter": setter.name, "getter": getter.name, "per_unit": bool(p.get("per_unit")),
                "static_keys": static_keys, "runtime_keys": runtime_keys, "pnames": pnames,
                "value_type": last_get.base, "set_vector": bool(last_set.stars), "set_type": last_set.ctype,
                "getter_keys": len(getter.params) > 1 + (1 if pnames else 0)}
