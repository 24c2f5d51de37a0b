"""The records of a PLY file's elements, read in bounded chunks.

    body = Body(f, header)                  # f positioned at header.body_start
    for first, columns in body.scalars(element, ["x", "y", "z"]): ...
    for first, values, counts in body.lists(element, "vertex_indices"): ...
    body.skip(element)

Elements must be read (or skipped) in file order. Memory stays bounded by a
chunk (CHUNK_BYTES of binary data, ASCII_LINES lines of text) plus what the
caller keeps, however large the file:

* binary, scalars only: records are fixed-size, read CHUNK_BYTES at a time
  as a numpy structured array (skipped with a seek);
* binary with lists: records like the first one (same list lengths, as in an
  all-triangle mesh) are viewed as one structured array; where the lengths
  vary a Python loop finds the record boundaries and numpy gathers the items.
  A record longer than a chunk (a long triangle strip) is read whole; a list
  longer than the rest of the file is refused before anything is allocated;
* ASCII: one record per line (as Turk's ply.c reads it), ASCII_BYTES of
  text at a time, parsed with
  numpy.loadtxt where the lines have equal widths, line by line otherwise;
  a line longer than MAX_LINE bytes is refused.

Errors name the file, the element, the record and (ASCII) the line, and say
what was expected.
"""
from __future__ import annotations

import struct

import numpy as np

from .common import SceneFileError, excerpt
from .ply_header import TYPES, Element, Header

PLY_NAMES = {code: name for name, code in reversed(list(TYPES.items()))}   # (the first name of each)

CHUNK_BYTES = 1 << 23           # binary data read at a time
ASCII_BYTES = 1 << 20            # text read at a time (its lines take several times that as objects)
ASCII_LINES = 1 << 16
MAX_LINE = 1 << 26
_SLOW_BATCH = 1 << 15            # records per Python-loop batch
_FAST_RUN = 16                   # records alike that make the structured view worth it


class Body:
    def __init__(self, f, header: Header):
        self.f, self.h = f, header
        self.line = header.lines + 1          # ASCII: the line of the next record
        self.first_line = {}                  # ASCII: element name -> line of its first record
        self._text, self._rows, self._row = b"", [], 0

    def where(self, e: Element, record: int) -> str:
        """"element 'face' record 12", with its line in an ASCII file."""
        line = self.first_line.get(e.name)
        return f"element {e.name!r} record {record}" + (f" (line {line + record})" if line else "")

    def fail(self, e: Element, record: int, message: str):
        raise SceneFileError(f"{self.h.path}: {self.where(e, record)}: {message}")

    def _truncated(self, e, record):
        self.fail(e, record, f"the file ends here, but the header declares {e.count} records "
                             "(truncated file?)")

    # -- scalar elements -------------------------------------------------------------
    def scalars(self, e: Element, names):
        """Chunks (first record, {name: values}) of an element without lists."""
        if self.h.ascii:
            columns = [(i, p.name) for i, p in enumerate(e.properties) if p.name in names]
            for first, rows in self._ascii(e):
                values = self._numbers(e, first, rows, len(e.properties))
                for i, p in enumerate(e.properties):
                    self._in_range(e, first, p.name, p.type, values[:, i])
                yield first, {name: values[:, i] for i, name in columns}
            return
        dtype = np.dtype([(p.name, self.h.byte_order + p.type) for p in e.properties])
        per = max(1, CHUNK_BYTES // dtype.itemsize)
        for first in range(0, e.count, per):
            n = min(per, e.count - first)
            data = self.f.read(n * dtype.itemsize)
            if len(data) < n * dtype.itemsize:
                self._truncated(e, first + len(data) // dtype.itemsize)
            records = np.frombuffer(data, dtype)
            yield first, {name: records[name] for name in names}

    def skip(self, e: Element) -> None:
        if self.h.ascii:
            for _ in self._ascii(e):
                pass
        elif not e.has_lists:
            size = e.count * e.min_record_bytes(False)
            if self.h.file_size - self.f.tell() < size:
                self._truncated(e, (self.h.file_size - self.f.tell()) // e.min_record_bytes(False))
            self.f.seek(size, 1)
        else:
            for _ in self.lists(e, None):
                pass

    # -- elements with lists ----------------------------------------------------------
    def lists(self, e: Element, name: str | None):
        """Chunks (first record, items, counts) of the list property `name` (None:
        just read past the element). Items come as float64 from ASCII files."""
        if self.h.ascii:
            for first, rows in self._ascii(e):
                chunk = self._ascii_list(e, name, first, rows)
                if name is not None:
                    yield chunk
            return
        layout = self._layout(e, name)
        buf, first = b"", 0
        while first < e.count:
            if len(buf) < CHUNK_BYTES:
                buf += self.f.read(CHUNK_BYTES)
            n, used, items, counts = self._parse(e, layout, buf, e.count - first, first)
            if n == 0:                                   # the next record is longer than buf
                more = self.f.read(max(CHUNK_BYTES, used - len(buf)))
                if not more:
                    self._truncated(e, first)
                buf += more
                continue
            if name is not None:
                yield first, items, counts
            buf, first = buf[used:], first + n
        self.f.seek(-len(buf), 1)                        # the rest belongs to the next element

    def _layout(self, e, name):
        """Steps of a record: a byte count for a run of scalars, or
        (count struct format, count size, item size, wanted) for a list."""
        steps, run = [], 0
        for p in e.properties:
            if not p.is_list:
                run += int(p.type[1])
                continue
            if run:
                steps.append(run)
                run = 0
            code = {"i1": "b", "u1": "B", "i2": "h", "u2": "H", "i4": "i", "u4": "I"}[p.count_type]
            steps.append((self.h.byte_order + code, int(p.count_type[1]), int(p.type[1]), p.name == name))
        if run:
            steps.append(run)
        return steps

    def _walk(self, e, layout, buf, pos, record):
        """(end, counts, item offsets) of the record at pos; end > len(buf) if it does not fit."""
        counts, starts = [], []
        for step in layout:
            if step.__class__ is int:
                pos += step
                continue
            fmt, csize, isize, wanted = step
            if pos + csize > len(buf):
                return pos + csize, None, None
            c = struct.unpack_from(fmt, buf, pos)[0]
            if c < 0:
                self.fail(e, record, f"a list count of {c}; expected a count >= 0")
            counts.append(c)
            starts.append(pos + csize)
            pos += csize + c * isize
        return pos, counts, starts

    def _parse(self, e, layout, buf, limit, first):
        """(records, bytes used, items of the wanted list, counts) of the complete
        records at the start of buf; (0, bytes needed, ...) when the first one is not."""
        end, counts0, _ = self._walk(e, layout, buf, 0, first)
        if end > len(buf):
            left = self.h.file_size - (self.f.tell() - len(buf))
            if end > left:
                self.fail(e, first, f"the record needs {end} bytes, but only {left} are left in the "
                                    f"file (a list count of {max(counts0 or [0])}: truncated or damaged?)")
            return 0, end, None, None
        wanted = [k for k, s in enumerate(s for s in layout if s.__class__ is not int) if s[3]]
        fields, j = [], 0
        for i, step in enumerate(layout):
            if step.__class__ is int:
                fields.append((f"pad{i}", f"V{step}"))
                continue
            fields += [(f"c{j}", step[0][0] + {"b": "i1", "B": "u1", "h": "i2", "H": "u2", "i": "i4",
                                               "I": "u4"}[step[0][1]]),
                       (f"v{j}", f"V{step[2]}", (counts0[j],))]
            j += 1
        dtype = np.dtype(fields)
        m = min(limit, len(buf) // dtype.itemsize)
        records = np.frombuffer(buf, dtype, count=m)
        alike = np.ones(m, dtype=bool)
        for k in range(j):
            alike &= records[f"c{k}"] == counts0[k]
        n = m if alike.all() else int(np.argmin(alike))
        if n >= _FAST_RUN or n == m:
            if not wanted:
                return n, n * dtype.itemsize, None, None
            w = wanted[0]
            item = self._item_dtype(e, layout, w)
            items = np.ascontiguousarray(records[f"v{w}"][:n]).view(item).reshape(-1)
            return n, n * dtype.itemsize, items, np.full(n, counts0[w], dtype=np.int64)
        return self._parse_slowly(e, layout, buf, limit, first, wanted)

    def _item_dtype(self, e, layout, w):
        lists = [p for p in e.properties if p.is_list]
        return np.dtype(self.h.byte_order + lists[w].type)

    def _parse_slowly(self, e, layout, buf, limit, first, wanted):
        pos, n, counts, starts = 0, 0, [], []
        w = wanted[0] if wanted else None
        for r in range(min(limit, _SLOW_BATCH)):
            end, c, s = self._walk(e, layout, buf, pos, first + r)
            if end > len(buf):
                break
            if w is not None:
                counts.append(c[w])
                starts.append(s[w])
            pos, n = end, n + 1
        if w is None:
            return n, pos, None, None
        item = self._item_dtype(e, layout, w)
        counts, starts = np.asarray(counts, np.int64), np.asarray(starts, np.int64)
        total, size = int(counts.sum()), item.itemsize
        offsets = np.repeat(starts - (np.cumsum(counts) - counts) * size, counts) + np.arange(total) * size
        raw = np.frombuffer(buf, np.uint8)[offsets[:, None] + np.arange(size)]
        return n, pos, raw.reshape(-1).view(item), counts

    # -- ASCII --------------------------------------------------------------------
    def _ascii(self, e):
        """Chunks (first record, up to ASCII_LINES lines) of element e; one record a line."""
        first = 0
        self.first_line[e.name] = self.line
        while first < e.count:
            if self._row >= len(self._rows):
                self._fill(e, first)
                continue
            rows = self._rows[self._row:self._row + min(e.count - first, ASCII_LINES)]
            self._row += len(rows)
            yield first, rows
            first += len(rows)
        self.line += e.count

    def _fill(self, e, record):
        data = self.f.read(ASCII_BYTES)
        if not data:
            if not self._text:
                self._truncated(e, record)
            self._rows, self._row, self._text = [self._text], 0, b""
            return
        rows = (self._text + data).split(self.h.newline)
        self._text = rows.pop()
        if len(self._text) > MAX_LINE:
            self.fail(e, record, f"a line of more than {MAX_LINE >> 20} MiB")
        self._rows, self._row = rows, 0

    def _numbers(self, e, first, rows, width=None):
        """The rows' numbers: a float64 (n, width) array, or (width None and
        widths that differ) a list of float lists."""
        try:
            values = np.loadtxt(rows, dtype=np.float64, ndmin=2, comments=None)
            if len(values) == len(rows) and (width is None or values.shape[1] == width):
                return values
        except ValueError:
            pass
        out = []
        for k, row in enumerate(rows):
            tokens = row.split()
            bad = next((t for t in tokens if not _is_number(t)), None)
            if bad is not None:
                self.fail(e, first + k, f"bad number {excerpt(bad)}")
            if width is not None and len(tokens) != width:
                names = " ".join(p.name for p in e.properties)
                self.fail(e, first + k, f"expected {width} numbers ({names}), got {len(tokens)}")
            out.append([float(t) for t in tokens])
        return np.array(out, dtype=np.float64).reshape(-1, width) if width is not None else out

    def _in_range(self, e, first, name, code, values, records=None):
        """Fail at the first value an integer type cannot hold (a binary file
        cannot hold one; in text, a 'uchar' of 300 or an 'int' of 2.5 is a
        broken writer's, which would read as a colour above 1 or a wrong index)."""
        info = _integer_range(code)
        if info is None:
            return
        bad = ~((values >= info.min) & (values <= info.max) & (values == np.floor(values)))
        if bad.any():
            k = int(np.argmax(bad))
            record = first + (k if records is None else int(records[k]))
            self.fail(e, record, f"{name} = {values[k]:g} does not fit its type {PLY_NAMES.get(code, code)} "
                                 f"(integers {info.min} to {info.max})")

    def _check_row(self, e, record, p, values):
        """_in_range for one record's values of p (a Python list), without numpy per row."""
        info = _integer_range(p.type)
        if info is not None:
            if not all(info.min <= v <= info.max and float(v).is_integer() for v in values):
                self._in_range(e, record, p.name, p.type, np.array(values, np.float64))

    def _ascii_list(self, e, name, first, rows):
        props = e.properties
        if len(props) == 1 and props[0].is_list:       # the common 'count i j k' line
            values = self._numbers(e, first, rows)
            if isinstance(values, np.ndarray) and np.all(values[:, 0] == values.shape[1] - 1):
                self._in_range(e, first, props[0].name, props[0].type, values[:, 1:].reshape(-1),
                               np.repeat(np.arange(len(rows)), values.shape[1] - 1))
                return first, values[:, 1:].reshape(-1), np.full(len(rows), values.shape[1] - 1, np.int64)
        else:
            values = self._numbers(e, first, rows)
        items, counts = [], []
        for k, row in enumerate(values.tolist() if isinstance(values, np.ndarray) else values):
            pos = 0
            for p in props:
                if not p.is_list:
                    self._check_row(e, first + k, p, row[pos:pos + 1])
                    pos += 1
                    continue
                c = row[pos] if pos < len(row) else None
                if c is None or not 0 <= c <= len(row) - pos - 1 or c != int(c):   # NaN fails too
                    got = "nothing" if c is None else f"{c:g} then {len(row) - pos - 1} numbers"
                    self.fail(e, first + k, f"list {p.name!r}: expected a count then that many "
                                                 f"numbers, got {got}")
                self._check_row(e, first + k, p, row[pos + 1:pos + 1 + int(c)])
                if p.name == name:
                    items += row[pos + 1:pos + 1 + int(c)]
                    counts.append(int(c))
                pos += 1 + int(c)
            if pos != len(row):
                self.fail(e, first + k, f"expected {pos} numbers (the properties "
                                             f"{' '.join(p.name for p in props)}), got {len(row)}")
        return first, np.asarray(items, np.float64), np.asarray(counts, np.int64)


def _integer_range(code: str):
    """numpy's iinfo of an integer type code ('u1', 'i4'), None for a float one."""
    return np.iinfo(np.dtype(code)) if code[0] in "iu" else None


def _is_number(token: bytes) -> bool:
    """A decimal number as C's strtod reads it (no '_' digit separators)."""
    try:
        float(token)
    except ValueError:
        return False
    return b"_" not in token
