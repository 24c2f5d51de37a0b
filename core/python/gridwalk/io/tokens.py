"""The whitespace-separated tokens of a text scene file, read in bounded chunks.

    for tokens, first in TokenStream(open(path, "rb")).segments():
        ...                         # tokens: [b"s", b"0", ...]; first: index of tokens[0]

Used by the NFF reader, which treats a file as SPD's own readers do: a stream
of words and numbers in which line breaks are just whitespace. The stream
never holds more than about two chunks of the file, whatever its size or
content:

* Lines end at LF, CRLF or a lone CR, and nowhere else: form feed, vertical
  tab, U+2028, U+0085 or the ASCII separators 0x1c-0x1e do not end a line
  (only space, tab, VT and FF separate tokens, as in C's scanf).
* A ^Z (0x1a, DOS's end-of-file mark) followed by nothing but blanks ends
  the file; anywhere else it is binary data.
* `#` starts a comment that runs to the end of its line, wherever it stands;
  a comment may be of any length and hold any bytes.
* A token longer than MAX_TOKEN bytes, or one holding a control byte or a
  non-ASCII byte, is refused (TokenError) as soon as it is met: no scene
  file has such tokens, and binary junk is refused after one chunk.

Positions are token indices counted from the start of the file.
Only the line of an error is needed, so lines are not tracked while reading:
`line_of(path, index)` reads the file again up to that token.
"""
from __future__ import annotations

import re

CHUNK_BYTES = 1 << 18          # bytes read at a time
MAX_TOKEN = 256                # longest token accepted (numbers need about 25)

_SPACE = b" \t\x0b\x0c"        # separators within a line
_COMMENT = re.compile(rb"#[^\n]*")
_TEXT = bytes(range(0x20, 0x7f)) + b" \t\n\x0b\x0c"   # printable ASCII and whitespace
_BOM = b"\xef\xbb\xbf"


class TokenError(ValueError):
    """A token no text scene file has: too long, or binary / non-ASCII data.
    `line` is the line it starts on, `token` the start of it, `size` its
    length (at least)."""

    def __init__(self, line: int, token: bytes, size: int, reason: str):
        super().__init__(reason)
        self.line, self.token, self.size, self.reason = line, token[:64], size, reason


class TokenStream:
    """Tokens of a binary file object, chunk by chunk (see the module docstring)."""

    def __init__(self, f, chunk_bytes: int = CHUNK_BYTES, max_token: int = MAX_TOKEN):
        self._f, self._chunk, self._max = f, chunk_bytes, max_token
        self.tokens: list[bytes] = []     # the current segment's tokens
        self.base = 0                     # index of self.tokens[0] in the file
        self.text = b""                   # the current segment (comments removed)
        self.first_line = 1               # line on which self.text starts
        self._next_line = 1
        self._carry = b""                 # an unfinished line or token
        self._in_comment = False          # a comment continues into the next chunk
        self._eof = False
        self._started = False

    def segments(self):
        """(tokens, index of the first one in the file) of each part of the file
        that has tokens, in order; the last part of the file comes last."""
        while self._load():
            yield self.tokens, self.base

    def line_in_segment(self, index: int) -> int:
        """Line of the token with this file index, which must lie in the current segment."""
        j, line = index - self.base, self.first_line
        for row in self.text.split(b"\n"):
            n = len(row.split())
            if j < n:
                return line
            j, line = j - n, line + 1
        return line

    # -- chunks ------------------------------------------------------------------
    def _read(self) -> bytes:
        data = self._f.read(self._chunk)
        if not self._started:
            self._started = True
            if data.startswith(_BOM):
                data = data[len(_BOM):]
        if data.endswith(b"\r"):              # keep a CRLF pair together
            data += self._f.read(1)
        while True:                            # a DOS end-of-file mark, if only blanks follow it
            eof_mark = data.rfind(b"\x1a")    # (the last: an earlier one, in a comment say, is data)
            if eof_mark < 0 or data[eof_mark + 1:].strip():
                break
            more = self._f.read(4096)
            if not more:
                data = data[:eof_mark]
                break
            data += more
        if not data:
            self._eof = True
        return data.replace(b"\r\n", b"\n").replace(b"\r", b"\n")

    def _load(self) -> bool:
        """Make the next segment with tokens current; False at the end of the file."""
        while not (self._eof and not self._carry):
            buf = self._carry + (b"" if self._eof else self._read())
            self._carry = b""
            if self._in_comment:              # skip the rest of a long comment line
                end = buf.find(b"\n")
                if end < 0:
                    continue
                buf, self._in_comment = buf[end:], False
            text = buf
            if not self._eof:
                cut = buf.rfind(b"\n")
                if cut >= 0:
                    text, self._carry = buf[:cut + 1], buf[cut + 1:]
                else:
                    text = self._split_long_line(buf)
            if b"#" in text:
                text = _COMMENT.sub(b"", text)
            self.base += len(self.tokens)
            self.tokens, self.text = text.split(), text
            self.first_line = self._next_line
            self._next_line += text.count(b"\n")
            self._check(text)
            if self.tokens:
                return True
        self.base += len(self.tokens)
        self.tokens, self.text = [], b""
        return False

    def _split_long_line(self, buf: bytes) -> bytes:
        """A chunk without a line break: keep its complete tokens, carry the last
        (unfinished) one, or skip from a `#` to the end of the line."""
        hash_at = buf.find(b"#")
        if hash_at >= 0:
            self._in_comment = True
            return buf[:hash_at]
        space = max(buf.rfind(c) for c in (b" ", b"\t", b"\x0b", b"\x0c"))
        self._carry = buf[space + 1:]
        if len(self._carry) > self._max:
            if self._carry.translate(None, _TEXT):
                raise TokenError(self._next_line, self._carry, len(self._carry), "binary or non-ASCII data")
            raise TokenError(self._next_line, self._carry, len(self._carry),
                             f"a token of more than {self._max} characters")
        return buf[:space + 1]

    def _check(self, text: bytes) -> None:
        """Refuse binary or non-ASCII data and over-long tokens in a segment."""
        if text.translate(None, _TEXT):
            bad = next(j for j, t in enumerate(self.tokens) if t.translate(None, _TEXT))
            raise TokenError(self.line_in_segment(self.base + bad), self.tokens[bad],
                             len(self.tokens[bad]), "binary or non-ASCII data")
        if self.tokens and max(map(len, self.tokens)) > self._max:
            bad = next(j for j, t in enumerate(self.tokens) if len(t) > self._max)
            raise TokenError(self.line_in_segment(self.base + bad), self.tokens[bad],
                             len(self.tokens[bad]), f"a token of {len(self.tokens[bad])} characters (at most {self._max})")


def line_of(path, index: int) -> int | None:
    """Line of the token with this index in the file, read again from the
    start (None when the file cannot be read again as it was)."""
    try:
        with open(path, "rb") as f:
            stream = TokenStream(f)
            while stream._load():
                if index < stream.base + len(stream.tokens):
                    return stream.line_in_segment(index)
    except (OSError, TokenError):
        return None
    return stream.first_line
