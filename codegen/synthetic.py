"""glcast's own tuples (annotations/synthetic.yaml): validated here, laid out by the
synthetic.*.j2 templates into opcodes, writers, readers and the dump."""
import re

SCALARS = {"u8": ("uint8_t", 1), "u32": ("uint32_t", 4), "i32": ("int32_t", 4), "u64": ("uint64_t", 8)}
VARIABLE = {"bytes", "record", "text", "repeat"}
SHOWS = {None, "enum", "hex", "opcode"}


class SyntheticError(Exception):
    pass


def camel(s):
    return "".join(w.capitalize() for w in s.split("_"))


def _fields(fields, where, top):
    seen = []
    out = []
    for f in fields:
        name, kind = f.get("name"), f.get("type")
        if not name or not re.fullmatch(r"[a-z_][a-z0-9_]*", name):
            raise SyntheticError(f"synthetic.yaml {where}: a field needs a lower_case name, got {name!r}")
        if kind not in SCALARS and kind not in VARIABLE:
            raise SyntheticError(f"synthetic.yaml {where}.{name}: unknown type {kind!r}")
        if kind == "repeat" and not top:
            raise SyntheticError(f"synthetic.yaml {where}.{name}: repeat groups do not nest")
        if f.get("show") not in SHOWS:
            raise SyntheticError(f"synthetic.yaml {where}.{name}: unknown show {f.get('show')!r}")
        unless = f.get("unless")
        if unless and unless not in [s["name"] for s in seen if s["type"] in SCALARS]:
            raise SyntheticError(f"synthetic.yaml {where}.{name}: unless names no earlier scalar field: {unless}")
        g = {"name": name, "type": kind, "show": f.get("show"), "names": f.get("names") or [], "unless": unless,
             "ctype": SCALARS[kind][0] if kind in SCALARS else None}
        if kind == "repeat":
            g["fields"] = _fields(f.get("fields") or [], f"{where}.{name}", False)
            g["min_bytes"] = sum(SCALARS[x["type"]][1] for x in g["fields"] if x["type"] in SCALARS and not x["unless"])
            if g["min_bytes"] == 0:
                raise SyntheticError(f"synthetic.yaml {where}.{name}: a repeated item must have a fixed part")
        seen.append(g)
        out.append(g)
    return out


def load(spec):
    tuples = []
    opcodes = set()
    for name, t in spec.items():
        op = t.get("opcode")
        if not isinstance(op, int) or op <= 0 or op in opcodes:
            raise SyntheticError(f"synthetic.yaml {name}: opcode must be a unique positive number, got {op!r}")
        opcodes.add(op)
        tuples.append({"name": name, "camel": camel(name), "opcode": op, "doc": t.get("doc", ""),
                       "fields": _fields(t.get("fields") or [], name, True)})
    return sorted(tuples, key=lambda t: t["opcode"])
