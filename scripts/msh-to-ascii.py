#!/usr/bin/env python3
"""Convert a binary gmsh MSH 4.1 file to ASCII MSH 4.1 exactly.

gmsh's own ASCII writer prints coordinates with 16 significant digits, which does not always give
back the same f64 (17 are needed in general). This converter writes every floating-point value as
Python's `repr`, the shortest decimal string that reads back to the same bits, and every integer
as it is. Sections: $MeshFormat, $PhysicalNames (ASCII in both encodings), $Entities, $Nodes,
$Elements and $Periodic (layouts of the gmsh 4.1 reference manual, "MSH file format"). Any other
section, a partitioned mesh, a big-endian file or a size_t other than 8 bytes is refused.

Exactness is checked on every run, not assumed: the ASCII text is parsed back and encoded as
binary again, and those bytes must equal the input file byte for byte (so every tag, count and
f64, including the $Entities bounding boxes and $Periodic affine transforms, round-trips).

Usage: scripts/msh-to-ascii.py IN.msh [OUT.msh]   (no OUT: convert IN in place)
       scripts/msh-to-ascii.py --check-ascii FILE.msh   (exit 1 if FILE is not ASCII MSH 4.1)
An ASCII input is refused (nothing to convert); a failed check writes nothing.
"""

import os
import struct
import sys
import tempfile

SUPPORTED = ("MeshFormat", "PhysicalNames", "Entities", "Nodes", "Elements", "Periodic")


class MshError(Exception):
    """Malformed or unsupported input, with the file and the place."""


# --- one value stream, read from binary or from ASCII ------------------------------------------


class BinaryReader:
    """Little-endian values of a binary section: size_t (8 bytes), int (4), double (8)."""

    def __init__(self, data, name, section):
        self.data, self.pos, self.where = data, 0, f"{name}: ${section}"

    def _take(self, fmt):
        size = struct.calcsize(fmt)
        if self.pos + size > len(self.data):
            raise MshError(f"{self.where}: truncated at byte {self.pos}")
        (value,) = struct.unpack_from(fmt, self.data, self.pos)
        self.pos += size
        return value

    def size_t(self):
        return self._take("<Q")

    def int(self):
        return self._take("<i")

    def double(self):
        return self._take("<d")

    def finish(self):
        # gmsh ends the binary data with one newline before the $End line.
        rest = self.data[self.pos :]
        if rest.strip(b"\n") != b"":
            raise MshError(f"{self.where}: {len(rest)} unread bytes after the data")


class AsciiReader:
    """Whitespace-separated tokens of an ASCII section."""

    def __init__(self, data, name, section):
        self.tokens, self.pos, self.where = data.split(), 0, f"{name}: ${section}"

    def _token(self):
        if self.pos >= len(self.tokens):
            raise MshError(f"{self.where}: truncated after token {self.pos}")
        self.pos += 1
        return self.tokens[self.pos - 1]

    def size_t(self):
        return int(self._token())

    def int(self):
        return int(self._token())

    def double(self):
        return float(self._token())

    def finish(self):
        if self.pos != len(self.tokens):
            raise MshError(f"{self.where}: {len(self.tokens) - self.pos} unread tokens")


# --- one value sink, written as binary or as ASCII lines ---------------------------------------


class BinaryWriter:
    def __init__(self):
        self.parts = []

    def line(self, *items):
        for kind, value in items:
            fmt = {"s": "<Q", "i": "<i", "d": "<d"}[kind]
            self.parts.append(struct.pack(fmt, value))

    def bytes(self):
        return b"".join(self.parts) + b"\n"


class AsciiWriter:
    def __init__(self):
        self.lines = []

    def line(self, *items):
        self.lines.append(" ".join(repr(v) if k == "d" else str(v) for k, v in items))

    def bytes(self):
        return ("\n".join(self.lines) + "\n").encode("ascii")


# --- section layouts: read into plain lists, write from them -----------------------------------


def read_entities(r):
    counts = [r.size_t() for _ in range(4)]
    entities = []
    for dim, count in enumerate(counts):
        for _ in range(count):
            tag = r.int()
            box = [r.double() for _ in range(3 if dim == 0 else 6)]
            physicals = [r.int() for _ in range(r.size_t())]
            bounding = [] if dim == 0 else [r.int() for _ in range(r.size_t())]
            entities.append((dim, tag, box, physicals, bounding))
    return counts, entities


def write_entities(w, content):
    counts, entities = content
    w.line(*[("s", c) for c in counts])
    for dim, tag, box, physicals, bounding in entities:
        items = [("i", tag)] + [("d", x) for x in box]
        items += [("s", len(physicals))] + [("i", p) for p in physicals]
        if dim > 0:
            items += [("s", len(bounding))] + [("i", b) for b in bounding]
        w.line(*items)


def read_nodes(r):
    header = [r.size_t() for _ in range(4)]
    blocks = []
    for _ in range(header[0]):
        dim, tag, parametric, count = r.int(), r.int(), r.int(), r.size_t()
        tags = [r.size_t() for _ in range(count)]
        width = 3 + (dim if parametric else 0)
        coords = [[r.double() for _ in range(width)] for _ in range(count)]
        blocks.append((dim, tag, parametric, tags, coords))
    return header, blocks


def write_nodes(w, content):
    header, blocks = content
    w.line(*[("s", h) for h in header])
    for dim, tag, parametric, tags, coords in blocks:
        w.line(("i", dim), ("i", tag), ("i", parametric), ("s", len(tags)))
        for t in tags:
            w.line(("s", t))
        for xyz in coords:
            w.line(*[("d", x) for x in xyz])


# Nodes per element of the gmsh element types (gmsh's MElement table; the ones a mesh of this
# project can hold, and the other low-order and quadratic types).
NODES_PER_TYPE = {
    1: 2, 2: 3, 3: 4, 4: 4, 5: 8, 6: 6, 7: 5, 8: 3, 9: 6, 10: 9, 11: 10, 12: 27, 13: 18,
    14: 14, 15: 1, 16: 8, 17: 20, 18: 15, 19: 13, 21: 10, 26: 4, 29: 20,
}


def read_elements(r, where):
    header = [r.size_t() for _ in range(4)]
    blocks = []
    for _ in range(header[0]):
        dim, tag, kind, count = r.int(), r.int(), r.int(), r.size_t()
        if kind not in NODES_PER_TYPE:
            raise MshError(f"{where}: $Elements: element type {kind} not in the converter's table")
        width = 1 + NODES_PER_TYPE[kind]
        rows = [[r.size_t() for _ in range(width)] for _ in range(count)]
        blocks.append((dim, tag, kind, rows))
    return header, blocks


def write_elements(w, content):
    header, blocks = content
    w.line(*[("s", h) for h in header])
    for dim, tag, kind, rows in blocks:
        w.line(("i", dim), ("i", tag), ("i", kind), ("s", len(rows)))
        for row in rows:
            w.line(*[("s", v) for v in row])


def read_periodic(r):
    links = []
    for _ in range(r.size_t()):
        entity = (r.int(), r.int(), r.int())
        affine = [r.double() for _ in range(r.size_t())]
        pairs = [(r.size_t(), r.size_t()) for _ in range(r.size_t())]
        links.append((entity, affine, pairs))
    return links


def write_periodic(w, links):
    w.line(("s", len(links)))
    for entity, affine, pairs in links:
        w.line(*[("i", e) for e in entity])
        w.line(("s", len(affine)), *[("d", a) for a in affine])
        w.line(("s", len(pairs)))
        for slave, master in pairs:
            w.line(("s", slave), ("s", master))


LAYOUTS = {
    "Entities": (lambda r, where: read_entities(r), write_entities),
    "Nodes": (lambda r, where: read_nodes(r), write_nodes),
    "Elements": (read_elements, write_elements),
    "Periodic": (lambda r, where: read_periodic(r), write_periodic),
}


# --- file level --------------------------------------------------------------------------------


def split_sections(data, name):
    """[(section name, content bytes)], content between the '$Name\\n' and '\\n$EndName' lines."""
    sections, pos = [], 0
    while pos < len(data):
        if data[pos : pos + 1] != b"$":
            raise MshError(f"{name}: expected a section at byte {pos}")
        eol = data.index(b"\n", pos)
        section = data[pos + 1 : eol].decode("ascii").strip()
        end = data.find(f"$End{section}".encode("ascii"), eol + 1)
        if end < 0:
            raise MshError(f"{name}: ${section} has no $End{section}")
        sections.append((section, data[eol + 1 : end]))
        pos = data.index(b"\n", end) + 1 if b"\n" in data[end:] else len(data)
    return sections


def parse_format(content, name):
    first = content.split(b"\n", 1)[0].split()
    if len(first) != 3 or first[0] != b"4.1":
        raise MshError(f"{name}: $MeshFormat {first!r} is not MSH 4.1")
    binary, size_t = int(first[1]), int(first[2])
    if size_t != 8:
        raise MshError(f"{name}: size_t of {size_t} bytes (only 8 is read)")
    if binary and struct.unpack_from("<i", content, len(content.split(b"\n", 1)[0]) + 1)[0] != 1:
        raise MshError(f"{name}: big-endian binary MSH is not read")
    return bool(binary)


def decode(data, name):
    """[(section name, content)], content = bytes for $MeshFormat/$PhysicalNames, else lists."""
    sections = split_sections(data, name)
    if not sections or sections[0][0] != "MeshFormat":
        raise MshError(f"{name}: does not start with $MeshFormat")
    binary = parse_format(sections[0][1], name)
    decoded = []
    for section, content in sections:
        if section not in SUPPORTED:
            raise MshError(f"{name}: ${section} is not converted (sections read: {SUPPORTED})")
        if section in ("MeshFormat", "PhysicalNames"):
            decoded.append((section, content))
            continue
        reader = (BinaryReader if binary else AsciiReader)(content, name, section)
        read, _ = LAYOUTS[section]
        decoded.append((section, read(reader, name)))
        reader.finish()
    return binary, decoded


def encode(decoded, binary):
    out = []
    for section, content in decoded:
        if section == "MeshFormat":
            body = b"4.1 1 8\n" + struct.pack("<i", 1) + b"\n" if binary else b"4.1 0 8\n"
        elif section == "PhysicalNames":
            body = content
        else:
            writer = BinaryWriter() if binary else AsciiWriter()
            LAYOUTS[section][1](writer, content)
            body = writer.bytes()
        out.append(f"${section}\n".encode() + body + f"$End{section}\n".encode())
    return b"".join(out)


def convert(data, name):
    """ASCII bytes of the binary MSH `data`, after checking they re-encode to `data` exactly."""
    binary, decoded = decode(data, name)
    if not binary:
        raise MshError(f"{name}: already ASCII")
    text = encode(decoded, binary=False)
    again_binary, again = decode(text, name + " (ASCII)")
    if again_binary or encode(again, binary=True) != data:
        raise MshError(f"{name}: the ASCII text does not re-encode to the input bytes")
    return text


def main(argv):
    if len(argv) == 3 and argv[1] == "--check-ascii":
        binary, _ = decode(open(argv[2], "rb").read(), argv[2])
        print(f"{argv[2]}: {'binary' if binary else 'ASCII'} MSH 4.1")
        return 1 if binary else 0
    if len(argv) not in (2, 3) or argv[1].startswith("-"):
        print(__doc__.split("\n\n")[-2], file=sys.stderr)
        return 2
    source = argv[1]
    target = argv[2] if len(argv) == 3 else source
    data = open(source, "rb").read()
    text = convert(data, source)
    folder = os.path.dirname(os.path.abspath(target))
    with tempfile.NamedTemporaryFile(dir=folder, delete=False) as tmp:
        tmp.write(text)
    os.chmod(tmp.name, 0o644)
    os.replace(tmp.name, target)
    print(f"{source} -> {target}: binary {len(data)} B -> ASCII {len(text)} B, re-encodes exactly")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv))
    except (MshError, OSError, ValueError, struct.error) as error:
        print(f"msh-to-ascii: {error}", file=sys.stderr)
        sys.exit(1)
