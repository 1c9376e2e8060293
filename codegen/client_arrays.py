"""The client arrays' tables (annotations/client_arrays.yaml), checked here and written into
glcast_client_arrays.h: which arrays each pointer command sets, and how each fixed-function
array is read back."""

SLOTS = ["vertex", "normal", "color", "secondary_color", "fog_coord", "index", "edge_flag", "tex_coord", "attrib"]
QUERIES = ["cap", "binding", "pointer", "size", "type", "stride"]


class ClientArraysError(Exception):
    pass


def camel(s):
    return "".join(w.capitalize() for w in s.split("_"))


def load(spec, plans, enums):
    deferred = {p.cmd.name for p in plans if any(w.kind == "deferred" for w in p.params)}
    set_by = spec.get("set_by") or {}
    listed = set(set_by)
    if listed != deferred:
        raise ClientArraysError("client_arrays.yaml set_by and the commands with a deferred pointer "
                                f"(commands.yaml) disagree: listed, not deferred: {sorted(listed - deferred)}; "
                                f"deferred, not listed: {sorted(deferred - listed)}")
    opcodes = {p.cmd.name: p.opcode for p in plans}
    commands = []
    for name, slots in sorted(set_by.items(), key=lambda kv: opcodes[kv[0]]):
        for s in slots or []:
            if s not in SLOTS:
                raise ClientArraysError(f"client_arrays.yaml set_by.{name}: unknown array {s!r} (one of {SLOTS})")
        if not slots:
            raise ClientArraysError(f"client_arrays.yaml set_by.{name}: names no array")
        commands.append((name, [camel(s) for s in slots]))

    fixed = []
    table = spec.get("fixed") or {}
    for name in table:
        if name not in SLOTS or name == "attrib":
            raise ClientArraysError(f"client_arrays.yaml fixed: {name!r} is not a fixed-function array")
    for name in SLOTS:  # ClientSlot order, whatever the file's
        if name not in table:
            continue
        row = table[name]
        unknown = set(row) - set(QUERIES) - {"normalized", "fixed_size", "fixed_type"}
        if unknown:
            raise ClientArraysError(f"client_arrays.yaml fixed.{name}: unknown keys {sorted(unknown)}")

        def enum(key):
            v = row.get(key)
            if v is None:
                return "0"
            if v not in enums:
                raise ClientArraysError(f"client_arrays.yaml fixed.{name}.{key}: unknown enum {v}")
            return f"0x{enums[v]:x} /* {v} */"
        for q in ("cap", "binding", "pointer", "stride"):
            if q not in row:
                raise ClientArraysError(f"client_arrays.yaml fixed.{name}: no {q}")
        for q in ("size", "type"):
            if (q in row) == (f"fixed_{q}" in row):
                raise ClientArraysError(f"client_arrays.yaml fixed.{name}: give one of {q} and fixed_{q}")
        out = {"slot": camel(name), "normalized": bool(row.get("normalized")),
               "cap": enum("cap"), "binding": enum("binding"), "pointer": enum("pointer"), "stride": enum("stride"),
               "size_query": enum("size"), "type_query": enum("type"), "size": int(row.get("fixed_size") or 0),
               "type": enum("fixed_type")}
        fixed.append(out)
    return {"commands": commands, "fixed": fixed}
