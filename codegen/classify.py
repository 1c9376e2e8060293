"""Decides, for every command, how each parameter and the return value travel on the wire.

Registry facts come from registry.py; everything gl.xml does not say comes from the
annotation files. A command whose parameters cannot all be encoded is *not serializable*:
it keeps an opcode and an entry point (forwarded and counted at run time) and is listed by
`--report` with the reason.
"""
import fnmatch
import re
from dataclasses import dataclass, field

# C value type -> wire type. Handles, X ids and pointers-as-values travel as u64.
SCALARS = {
    "GLenum": "u32", "GLboolean": "u8", "GLbitfield": "u32", "GLbyte": "i8", "GLubyte": "u8",
    "GLshort": "i16", "GLushort": "u16", "GLint": "i32", "GLuint": "u32", "GLsizei": "i32",
    "GLfloat": "f32", "GLclampf": "f32", "GLdouble": "f64", "GLclampd": "f64", "GLchar": "i8",
    "GLcharARB": "i8", "GLhalfNV": "u16", "GLhalf": "u16", "GLhalfARB": "u16", "GLfixed": "i32", "GLclampx": "i32",
    "GLintptr": "i64", "GLsizeiptr": "i64", "GLintptrARB": "i64", "GLsizeiptrARB": "i64",
    "GLint64": "i64", "GLuint64": "u64", "GLint64EXT": "i64", "GLuint64EXT": "u64",
    "GLhandleARB": "u32", "GLvdpauSurfaceNV": "i64", "int": "i32", "unsigned int": "u32",
    "Bool": "i32", "unsigned long": "u64", "long": "i64", "int64_t": "i64", "int32_t": "i32",
    "char": "i8", "float": "f32", "GLbooleanARB": "u8",
    "EGLint": "i32", "EGLBoolean": "u32", "EGLenum": "u32", "EGLAttrib": "i64",
}
WIRE_BYTES = {"u8": 1, "i8": 1, "u16": 2, "i16": 2, "u32": 4, "i32": 4, "u64": 8, "i64": 8,
              "f32": 4, "f64": 8}
TEXT_TYPES = {"GLchar", "GLcharARB", "char", "GLubyte"}


class Unserializable(Exception):
    pass


@dataclass
class Wire:
    """How one parameter (or the return value) is encoded."""
    kind: str            # value | in | out | string | out_string | string_array | address |
                         # deferred | attrib_list | visual_attribs | visualinfo
    wire: str = "u64"    # element wire type (u8 for void data)
    len: str | None = None        # C++ element count expression
    source: str | None = None     # binding enum: non-zero means the pointer is a buffer offset
    count: str | None = None      # string_array
    lengths: str | None = None    # string_array
    terminator: str | None = None # attrib_list: the key that ends the list (default 0)
    display: str = ""             # enum | bitfield | bool | handle | text | ""


@dataclass
class Plan:
    cmd: object
    opcode: int
    params: list = field(default_factory=list)   # [Wire] parallel to cmd.params
    ret: Wire | None = None
    reason: str = ""          # why not serializable ("" when it is)
    handwritten: bool = False
    reply_only: bool = False
    draw: dict | None = None
    reads_buffers: bool = False  # may read a buffer's memory: persistent mappings ship first

    @property
    def serializable(self):
        return not self.reason


class Classifier:
    def __init__(self, annotations, pname_tables, enums):
        self.a = annotations
        self.enums = enums
        self.opaque = set(annotations["opaque_types"])
        self.table_of = {c: t for t, cmds in annotations["pname_tables"].items() for c in cmds}
        self.known_tables = set(pname_tables)
        self.overrides = dict(annotations.get("params") or {})
        self.overrides.update(annotations.get("egl_params") or {})

    # -- value types -------------------------------------------------------------------
    def scalar(self, base):
        if base in SCALARS:
            return SCALARS[base]
        if base in self.opaque or base.startswith("PFN") or base.endswith("PROC"):
            return "u64"
        raise Unserializable(f"unknown value type {base}")

    def display(self, p):
        if p.base == "GLenum" or p.base == "EGLenum":
            return "enum"
        if p.base == "GLbitfield":
            return "bitfield"
        if p.base in ("GLboolean", "Bool", "EGLBoolean"):
            return "bool"
        if p.base in self.opaque:
            return "handle"
        return ""

    # -- lengths -----------------------------------------------------------------------
    def lookup(self, table, cmd, suffix=""):
        """An annotation for cmd, or for the command it aliases (an ARB/EXT twin of a core command)."""
        for name in (cmd.name, cmd.alias):
            if name and name + suffix in table:
                return table[name + suffix]
        return None

    def length(self, cmd, p, direction):
        over = self.lookup(self.overrides, cmd, "." + p.name) or {}
        expr = over.get("len") or p.len
        if expr is None:
            if self.lookup(self.table_of, cmd):   # DSA twins whose len gl.xml left out
                return self.pname_length(cmd, p, "")
            return None
        expr = str(expr)
        m = re.fullmatch(r"COMPSIZE\((.*)\)", expr)
        if m:
            args = m.group(1).replace(" ", "")
            if args in ("pname", "target", "buffer", "query") or self.lookup(self.table_of, cmd):
                return self.pname_length(cmd, p, args)
            rule = self.a["compsize"].get(args)
            if rule is None:
                raise Unserializable(f"no size rule for COMPSIZE({args}) of {p.name}")
            expr = rule
        elem = WIRE_BYTES.get(self.elem_wire(p), 1)
        per_count = self.lookup(self.a.get("per_count") or {}, cmd)
        if "$per_count" in expr:
            if per_count is None:
                raise Unserializable(f"COMPSIZE(count) of {p.name}: no per_count entry")
            expr = expr.replace("$per_count", str(per_count))
        expr = expr.replace("$dir", "Dir::In" if direction == "in" else "Dir::Out")
        expr = expr.replace("$elem_bytes", str(elem))
        self.check_expr(cmd, expr, p.name)
        return self.widened(cmd, expr)

    @staticmethod
    def widened(cmd, expr):
        """Arithmetic of parameters in 64 bits: `count*9` with count 2^31 overflows a GLsizei
        (undefined behaviour, found by the replay fuzzer), int64_t(count)*9 does not. Expressions
        that call size queries return int64_t already."""
        # only operands joined by binary operators: not `n ? *n : 0`, not calls
        if not re.fullmatch(r"\s*\w+(\s*[*+\-/]\s*\w+)+\s*", expr):
            return expr
        names = {q.name for q in cmd.params}
        return re.sub(r"\b[A-Za-z_]\w*\b", lambda m: f"int64_t({m.group(0)})" if m.group(0) in names else m.group(0),
                      expr)

    @staticmethod
    def check_expr(cmd, expr, what, extra=()):
        """Every identifier of an annotation expression must be a parameter of cmd (aliases
        inherit annotations, and an alias may name its parameters differently)."""
        names = {q.name for q in cmd.params} | set(extra)
        for ident in re.findall(r"\b[a-zA-Z_]\w*\b", re.sub(r"sz\.\w+|Dir::\w+|PnameTable::\w+|GL_\w+|\bint64_t\b", "", str(expr))):
            if ident not in names and not ident.isdigit():
                raise Unserializable(f"annotation '{expr}' of {what} names unknown '{ident}'")

    def pname_length(self, cmd, p, args):
        table = self.lookup(self.table_of, cmd)
        if table is None:
            raise Unserializable(f"COMPSIZE({args}) of {p.name}: no pname table")
        if table not in self.known_tables:
            raise Unserializable(f"pname table '{table}' missing from pnames.yaml")
        names = [q.name for q in cmd.params]
        key = next((k for k in ("pname", "query", "buffer", "target") if k in names), None)
        if key is None:
            raise Unserializable(f"{p.name}: pname table '{table}' but no pname parameter")
        count = f"sz.pname_count(PnameTable::{table}, {key})"
        return f"uniformCount * {count}" if "uniformCount" in names else count

    def elem_wire(self, p):
        if p.base == "void" or p.base == "GLvoid":
            return "u8" if p.stars == 1 else "u64"
        if p.stars >= 2:
            return "u64"
        try:
            return self.scalar(p.base)
        except Unserializable:
            return "u8"

    # -- one parameter -----------------------------------------------------------------
    def param(self, cmd, p):
        over = self.lookup(self.overrides, cmd, "." + p.name) or {}
        kind = over.get("kind")
        if p.stars == 0 and p.base in ("XVisualInfo",):
            raise Unserializable(f"{p.name}: XVisualInfo by value")
        if p.stars == 0:
            return Wire("value", self.scalar(p.base), display=self.display(p))
        if kind in ("address", "deferred"):
            return Wire(kind, "u64")
        if kind in ("attrib_list", "visual_attribs"):
            return Wire(kind, "i64" if p.base == "EGLAttrib" else "i32", terminator=over.get("terminator"))
        if kind in ("string_array", "index_arrays"):
            self.check_expr(cmd, over["count"], p.name)
            self.check_expr(cmd, over.get("lengths") or over.get("counts") or "", p.name, extra=("i",))
        if kind == "string_array":
            return Wire("string_array", "i8", count=str(over["count"]), lengths=over.get("lengths"))
        if kind == "index_arrays":
            return Wire("index_arrays", "u8", count=str(over["count"]), lengths=str(over["counts"]),
                        source="GL_ELEMENT_ARRAY_BUFFER_BINDING")
        if p.base in self.opaque and p.base not in ("GLsync",) and p.stars == 1 and p.base in (
                "Display", "EGLNativeWindowType", "EGLNativePixmapType"):
            return Wire("address")
        if p.base == "XVisualInfo" and p.stars == 1:
            return Wire("visualinfo", "u8")
        if p.base in ("__GLXextFuncPtr",) or p.base.startswith("GLDEBUGPROC"):
            return Wire("address")
        if kind == "string" or (p.const and p.stars == 1 and p.base in TEXT_TYPES and p.len is None
                                and "len" not in over) or (
                p.const and p.stars == 1 and p.base in TEXT_TYPES and (p.len or "").startswith("COMPSIZE(name")):
            return Wire("string", "i8", display="text")
        direction = "in" if p.const else "out"
        if p.stars >= 2 and p.const:
            raise Unserializable(f"{p.name}: array of pointers ({p.ctype})")
        n = self.length(cmd, p, direction)
        if n is None:
            raise Unserializable(f"{p.name}: pointer with no known length ({p.ctype})")
        if direction == "out" and p.base in TEXT_TYPES and p.stars == 1 and p.base != "GLubyte":
            return Wire("out_string", "i8", len=n, source=over.get("source"), display="text")
        return Wire(direction, self.elem_wire(p), len=n, source=over.get("source"),
                    display=self.display(p))

    def ret(self, cmd):
        r = re.sub(r"\s+", " ", cmd.ret).strip()
        if r in ("void", ""):
            return None
        base = re.sub(r"\bconst\b|\*", " ", r).strip()
        stars = r.count("*")
        if stars == 0:
            d = ("enum" if base in ("GLenum", "EGLenum") else "bool" if base in ("GLboolean", "Bool", "EGLBoolean")
                 else "handle" if base in self.opaque else "")
            return Wire("value", self.scalar(base), display=d)
        if base in TEXT_TYPES:
            return Wire("string", "i8", display="text")
        if base == "XVisualInfo":
            return Wire("visualinfo", "u8")
        arr = self.lookup(self.a.get("returns") or {}, cmd)
        if arr:
            return Wire("out", "u64", len=arr)
        return Wire("address")

    def plan(self, cmd, opcode, handwritten):
        plan = Plan(cmd, opcode, handwritten=cmd.name in handwritten)
        plan.reply_only = any(fnmatch.fnmatchcase(cmd.name, pat) for pat in self.a["reply_only"])
        plan.draw = self.lookup(self.a.get("draws") or {}, cmd)
        try:
            plan.params = [self.param(cmd, p) for p in cmd.params]
            plan.ret = self.ret(cmd)
            for key, expr in (plan.draw or {}).items():
                self.check_expr(cmd, expr, f"draw range ({key})")
            plan.reads_buffers = bool(plan.draw) or any(w.source for w in plan.params) or any(
                fnmatch.fnmatchcase(cmd.name, pat) for pat in self.a.get("reads_mapped_memory") or [])
        except Unserializable as e:
            plan.reason = str(e)
            plan.params = []
        return plan
