"""Reads the Khronos registry (gl.xml, glx.xml) unmodified into a small command model.

Nothing here knows about glcast's semantics; that lives in annotations/ and classify.py.
"""
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field


@dataclass
class Param:
    name: str
    ctype: str          # C declaration type, e.g. "const GLfloat *"
    base: str           # pointee or value type without const/stars, e.g. "GLfloat"
    stars: int          # pointer depth
    const: bool         # pointee is const (the call reads it)
    len: str | None     # gl.xml's len attribute
    group: str | None
    name_class: str | None = None  # gl.xml's class: the object namespace of a name ("texture")


@dataclass
class Command:
    name: str
    ret: str            # C return type
    params: list[Param]
    api: str            # "gl", "glx" or "egl"
    origin: str = ""    # first feature (e.g. "GL_VERSION_1_0") or extension that requires it
    origins: list = field(default_factory=list)
    alias: str | None = None  # the command this one is an alias of (same semantics)
    ret_class: str | None = None  # gl.xml's class of a returned name (glCreateProgram: "program")

    @property
    def is_core(self):
        return self.origin.startswith(("GL_VERSION_", "GLX_VERSION_"))


def _parse_decl(text, name):
    """'const GLfloat *params' -> ('const GLfloat *', 'GLfloat', 1, True)"""
    ctype = text[: text.rfind(name)].strip() if name else text.strip()
    ctype = re.sub(r"\s+", " ", ctype)
    stars = ctype.count("*")
    const = ctype.startswith("const ")
    base = re.sub(r"\bconst\b|\*|\bstruct\b", " ", ctype)
    base = re.sub(r"\s+", " ", base).strip()
    return ctype, base, stars, const


def _param(el):
    name = el.find("name").text
    ctype, base, stars, const = _parse_decl("".join(el.itertext()), name)
    return Param(name, ctype, base, stars, const, el.get("len"), el.get("group"), el.get("class"))


def _ret(proto, name):
    text = "".join(proto.itertext())
    return re.sub(r"\s+", " ", text[: text.rfind(name)]).strip()


def load(path, api):
    """Returns ([Command in registry order], {enum name: value}, {group: [enum names]})."""
    root = ET.parse(path).getroot()
    commands = []
    for el in root.find("commands").findall("command"):
        proto = el.find("proto")
        name = proto.find("name").text
        alias = el.find("alias")
        commands.append(Command(name, _ret(proto, name), [_param(p) for p in el.findall("param")], api,
                                alias=alias.get("name") if alias is not None else None,
                                ret_class=proto.get("class")))
    by_name = {c.name: c for c in commands}

    def require(owner, node):
        for req in node.findall("require"):
            if req.get("api") not in (None, api):
                continue
            for c in req.findall("command"):
                cmd = by_name.get(c.get("name"))
                if cmd is not None:
                    cmd.origins.append(owner)
                    cmd.origin = cmd.origin or owner

    for feat in root.findall("feature"):
        if feat.get("api") == api:
            require(feat.get("name"), feat)
    for ext in root.find("extensions").findall("extension"):
        if api in (ext.get("supported") or "").split("|"):
            require(ext.get("name"), ext)

    enums, groups = {}, {}
    for block in root.findall("enums"):
        for e in block.findall("enum"):
            if e.get("api") not in (None, api):
                continue
            try:
                value = int(e.get("value").rstrip("uUlL"), 0) & 0xFFFFFFFFFFFFFFFF
            except ValueError:   # glx.xml's string constants such as GLX_EXTENSION_NAME
                continue
            enums.setdefault(e.get("name"), value)
            for g in (e.get("group") or "").split(","):
                if g:
                    groups.setdefault(g, []).append(e.get("name"))
    # Commands no feature or extension of this API requires (GLES-only, etc.) are not ours.
    commands = [c for c in commands if c.origin]
    return commands, enums, groups


_SIG = re.compile(r"^\s*(?P<ret>.+?)\s*\b(?P<name>\w+)\s*\((?P<params>.*)\)\s*$")


def parse_signature(sig, api):
    """Parses a C prototype written in the annotation file (EGL has no registry in khronos-api)."""
    m = _SIG.match(sig)
    if not m:
        raise ValueError(f"cannot parse signature: {sig!r}")
    params = []
    text = m.group("params").strip()
    if text and text != "void":
        for decl in text.split(","):
            decl = decl.strip()
            pname = re.search(r"(\w+)\s*$", decl).group(1)
            ctype, base, stars, const = _parse_decl(decl, pname)
            params.append(Param(pname, ctype, base, stars, const, None, None))
    return Command(m.group("name"), m.group("ret").strip(), params, api, origin=f"{api.upper()}_glcast")
