"""The header of a PLY file: format, elements and their properties.

    header = read_header(path)
    header.format             'ascii', 'binary_little_endian' or 'binary_big_endian'
    header.elements           [Element(name, count, properties, line)] in file order
    header.body_start         byte offset of the first record

Property types are kept as numpy type codes ('u1', 'i4', 'f8', ...); PLY's
names (char, uchar, short, ushort, int, uint, float, double) and the sized
ones (int8 ... uint32, float32, float64) are both accepted. Only the first
MAX_HEADER bytes are read. `comment` and `obj_info` lines may hold any bytes
(UTF-8 or not); every other header line must be ASCII. Errors name the
header line.
"""
from __future__ import annotations

import os
import re
from dataclasses import dataclass, field
from pathlib import Path

from .common import SceneFileError, excerpt, open_scene_file

MAX_HEADER = 1 << 20
FORMATS = ("ascii", "binary_little_endian", "binary_big_endian")
TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
         "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
         "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}


@dataclass
class Property:
    name: str
    type: str                      # numpy code of the value (of the items, for a list)
    count_type: str | None = None  # numpy code of a list's count; None for a scalar

    @property
    def is_list(self) -> bool:
        return self.count_type is not None


@dataclass(eq=False)
class Element:
    name: str
    count: int
    line: int                      # header line of its `element` line
    properties: list[Property] = field(default_factory=list)

    def get(self, name: str) -> Property | None:
        return next((p for p in self.properties if p.name == name), None)

    @property
    def has_lists(self) -> bool:
        return any(p.is_list for p in self.properties)

    def min_record_bytes(self, ascii: bool) -> int:
        """Fewest bytes a record can take: binary scalars their size and lists
        their count; in ASCII each value at least a digit and a separator."""
        if ascii:
            return 2 * len(self.properties)
        return sum(int(p.count_type[1] if p.is_list else p.type[1]) for p in self.properties)


@dataclass
class Header:
    path: Path
    format: str
    elements: list[Element]
    body_start: int
    file_size: int
    lines: int                     # header lines, end_header included
    newline: bytes = b"\n"         # b"\r" in a file with classic Mac OS line ends

    @property
    def ascii(self) -> bool:
        return self.format == "ascii"

    @property
    def byte_order(self) -> str:
        return {"binary_little_endian": "<", "binary_big_endian": ">"}.get(self.format, "=")

    def element(self, name: str) -> Element | None:
        return next((e for e in self.elements if e.name == name), None)


_MAGIC = re.compile(rb"(\xef\xbb\xbf)?ply[ \t]*(\r\n|\n|\r)")
_END = {b"\n": re.compile(rb"(?m)^end_header[ \t]*\r?\n"), b"\r": re.compile(rb"\rend_header[ \t]*\r")}


def read_header(path: Path) -> Header:
    """Lines end in LF, CRLF or (as classic Mac OS wrote them) CR alone, as the
    first line does; a UTF-8 byte order mark and blanks after 'ply' are allowed."""
    with open_scene_file(path) as f:
        head = f.read(MAX_HEADER)
        size = os.fstat(f.fileno()).st_size
    magic = _MAGIC.match(head)
    newline = b"\r" if magic and magic.group(2) == b"\r" else b"\n"
    end = _END[newline].search(head) if magic else None
    if end is None:
        raise SceneFileError(f"{path}: not a PLY file, or a truncated one (no 'ply' ... 'end_header' "
                             f"header in the first {MAX_HEADER >> 20} MiB)")

    def fail(lineno, message):
        raise SceneFileError(f"{path}:{lineno}: {message}")

    fmt, elements = None, []
    rows = head[magic.start(2):end.start()].split(newline)
    for lineno, raw in enumerate(rows[1:], 2):
        words = raw.split()                      # ASCII whitespace only (not 0x1c-0x1f)
        if not words or words[0] in (b"comment", b"obj_info"):
            continue
        try:
            tokens = [w.decode("ascii") for w in words]
        except UnicodeDecodeError:
            fail(lineno, f"header line {excerpt(raw.rstrip())} is not ASCII (only comments may hold other text)")
        line = " ".join(tokens)
        if tokens[0] == "format":
            if len(tokens) != 3 or tokens[1] not in FORMATS or tokens[2] != "1.0":
                fail(lineno, f"unsupported format line {excerpt(line)}; expected 'format "
                             f"<{'|'.join(FORMATS)}> 1.0'")
            fmt = tokens[1]
        elif tokens[0] == "element":
            if len(tokens) != 3 or not tokens[2].isdigit() or len(tokens[2]) > 12:
                fail(lineno, f"expected 'element <name> <count>', got {excerpt(line)}")
            elements.append(Element(tokens[1], int(tokens[2]), lineno))
        elif tokens[0] == "property" and elements:
            elements[-1].properties.append(_property(tokens, line, lambda m: fail(lineno, m)))
        else:
            fail(lineno, f"unexpected header line {excerpt(line)}")
    if fmt is None:
        raise SceneFileError(f"{path}: the header has no 'format' line")
    for e in elements:
        if not e.properties:
            fail(e.line, f"element {e.name!r} has no properties")
        names = [p.name for p in e.properties]
        dup = next((n for n in names if names.count(n) > 1), None)
        if dup:
            fail(e.line, f"element {e.name!r} has two properties named {dup!r}")
    return Header(path, fmt, elements, end.end(), size, head[:end.end()].count(newline), newline)


def _property(tokens, line, fail) -> Property:
    known = ", ".join(sorted(TYPES))
    if len(tokens) == 5 and tokens[1] == "list":
        count, item = TYPES.get(tokens[2]), TYPES.get(tokens[3])
        if count is None or count[0] == "f" or item is None:
            fail(f"bad list property {excerpt(line)}: the count type must be an integer type "
                 f"and both types one of {known}")
        return Property(tokens[4], item, count)
    if len(tokens) == 3 and tokens[1] in TYPES:
        return Property(tokens[2], TYPES[tokens[1]])
    fail(f"bad property line {excerpt(line)}; expected 'property <type> <name>' or "
         f"'property list <count type> <item type> <name>' with types from {known}")
