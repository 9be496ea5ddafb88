"""Decoders for the two EXT_meshopt_compression bitstreams a Tessera meshopt GLB uses (docs/GLB.md):
mode 0, attributes (header 0xa0), and mode 1, triangles (header 0xe1), written from the
extension's specification (KhronosGroup/glTF, extensions/2.0/Vendor/EXT_meshopt_compression,
Appendix A). Pure Python and NumPy, since Blender's Python has no pip for meshoptimizer's C
decoder. Filters (Appendix B) are refused: Tessera writes none. A stream that does not follow
the specification raises ValueError, never returns wrong bytes silently."""
import numpy as np

ATTRIBUTES_HEADER = 0xA0
TRIANGLES_HEADER = 0xE1
_TAIL_MIN = 32          # the attribute stream's tail: the baseline element, zero-padded in front to 32 bytes
_AUX_BYTES = 16         # the triangle stream's tail: the codeaux table
_FIFO = 16              # entries in the edge and vertex FIFOs

# A group's deltas in sentinel coding, first delta in the highest bits of each byte.
_TWO_BIT = [tuple((byte >> shift) & 3 for shift in (6, 4, 2, 0)) for byte in range(256)]
_FOUR_BIT = [(byte >> 4, byte & 15) for byte in range(256)]
# Zigzag decoding of a byte delta: 0, 1, 2, 3, ... -> 0, -1, 1, -2, ... (mod 256).
_UNZIGZAG = bytes(((~(v >> 1)) & 0xFF) if v & 1 else v >> 1 for v in range(256))


class _Reader:
    """A cursor over the stream's body that refuses to read past its end."""

    def __init__(self, data: bytes, start: int, end: int):
        self.data, self.at, self.end = data, start, end

    def take(self, size: int) -> bytes:
        if self.at + size > self.end:
            raise ValueError("meshopt stream ends early")
        chunk = self.data[self.at:self.at + size]
        self.at += size
        return chunk

    def byte(self) -> int:
        return self.take(1)[0]

    def varint(self) -> int:
        """Unsigned LEB128: seven bits a byte, low first, a clear top bit ends it."""
        value, shift = 0, 0
        while True:
            byte = self.byte()
            value |= (byte & 0x7F) << shift
            if byte < 0x80:
                return value & 0xFFFFFFFF
            shift += 7
            if shift > 28:
                raise ValueError("meshopt index varint longer than 5 bytes")


def _group_deltas(reader: _Reader, mode: int) -> bytes:
    """16 zigzag-coded byte deltas of one group: mode 0 all zero, 1 two-bit and 2 four-bit sentinel
    coding (an all-ones value means the delta follows as a whole byte), 3 sixteen raw bytes."""
    if mode == 0:
        return bytes(16)
    if mode == 3:
        return reader.take(16)
    if mode == 1:
        packed, sentinel, table = reader.take(4), 3, _TWO_BIT
    else:
        packed, sentinel, table = reader.take(8), 15, _FOUR_BIT
    values = [v for byte in packed for v in table[byte]]
    for i, v in enumerate(values):
        if v == sentinel:
            values[i] = reader.byte()
    return bytes(values)


def _block_deltas(reader: _Reader, elements: int) -> bytes:
    """One data block (one byte of every element of an attribute block): 2 header bits a group,
    four groups a byte from the low bits up, then each group's deltas."""
    groups = (elements + 15) // 16
    header = reader.take((groups + 3) // 4)
    deltas = bytearray()
    for group in range(groups):
        deltas += _group_deltas(reader, (header[group // 4] >> (2 * (group % 4))) & 3)
    return bytes(deltas[:elements])


def decode_attributes(data: bytes, count: int, stride: int) -> bytes:
    """Mode 0: `count` elements of `stride` bytes. Blocks of at most min(8192 / stride rounded
    down to 16, 256) elements; each stores, byte by byte, deltas from the element before (the
    first from the baseline in the tail), in 8-bit wrapping arithmetic."""
    if stride <= 0 or stride > 256 or stride % 4:
        raise ValueError(f"meshopt attributes: byteStride {stride} is not a multiple of 4 up to 256")
    tail = max(stride, _TAIL_MIN)
    if len(data) < 1 + tail or data[0] != ATTRIBUTES_HEADER:
        raise ValueError("meshopt attributes: not a version 0 attribute stream (header 0xa0)")
    baseline = np.frombuffer(data[len(data) - stride:], dtype=np.uint8)
    reader = _Reader(data, 1, len(data) - tail)
    per_block = min((8192 // stride) & ~15, 256)
    channels = [bytearray() for _ in range(stride)]
    done = 0
    while done < count:
        elements = min(count - done, per_block)
        for channel in channels:
            channel += _block_deltas(reader, elements)
        done += elements
    if reader.at != reader.end:
        raise ValueError("meshopt attributes: bytes left over before the tail")
    deltas = np.frombuffer(b"".join(bytes(c).translate(_UNZIGZAG) for c in channels), dtype=np.uint8)
    deltas = deltas.reshape(stride, count).T
    values = (np.cumsum(deltas, axis=0, dtype=np.uint8) + baseline).astype(np.uint8)
    return values.tobytes()


class _TriangleState:
    """The decoder's variables: next (the high-water mark), last (the last explicit index) and the
    two 16-entry FIFOs, read by age (0 is the newest)."""

    def __init__(self, reader: _Reader):
        self.reader = reader
        self.next = 0
        self.last = 0
        self.edges = [(0, 0)] * _FIFO
        self.edge_at = 0
        self.vertices = [0] * _FIFO
        self.vertex_at = 0

    def edge(self, age: int):
        return self.edges[(self.edge_at - 1 - age) & 15]

    def vertex(self, age: int) -> int:
        return self.vertices[(self.vertex_at - 1 - age) & 15]

    def push_edge(self, a: int, b: int) -> None:
        self.edges[self.edge_at] = (a, b)
        self.edge_at = (self.edge_at + 1) & 15

    def push_vertex(self, v: int) -> None:
        self.vertices[self.vertex_at] = v
        self.vertex_at = (self.vertex_at + 1) & 15

    def take_next(self) -> int:
        self.next += 1
        return self.next - 1

    def explicit(self) -> int:
        """An index stored as a zigzag delta from `last`, which it becomes."""
        v = self.reader.varint()
        delta = ~(v >> 1) if v & 1 else v >> 1
        self.last = (self.last + delta) & 0xFFFFFFFF
        return self.last


def _edge_triangle(state: _TriangleState, code: int):
    """Codes 0xXY with X < 0xf: the edge X entries old, and a third vertex by Y."""
    a, b = state.edge(code >> 4)
    low = code & 15
    if low == 0:
        c = state.take_next()
    elif low < 13:
        c = state.vertex(low)
    elif low < 15:
        c = state.last = (state.last + (1 if low == 14 else -1)) & 0xFFFFFFFF
    else:
        c = state.explicit()
    if low == 0 or low >= 13:
        state.push_vertex(c)
    state.push_edge(c, b)
    state.push_edge(a, c)
    return a, b, c


def _free_vertex(state: _TriangleState, selector: int, explicit_allowed: bool):
    """b or c of a 0xfY/0xfe/0xff triangle: 0 is `next`, 1-14 the vertex FIFO at selector - 1,
    15 (0xfe/0xff only) an explicit index; returns it and whether it enters the vertex FIFO."""
    if selector == 0:
        return state.take_next(), True
    if selector == 15 and explicit_allowed:
        return state.explicit(), True
    return state.vertex(selector - 1), False


def _free_triangle(state: _TriangleState, code: int, codeaux: bytes):
    """Codes 0xfY: a is `next`, b and c from the codeaux entry Y; 0xfe, 0xff: from a data byte,
    a being `next` (0xfe) or explicit (0xff); a data byte 0 restarts `next` at 0."""
    low = code & 15
    if low < 14:
        selectors, explicit_allowed = codeaux[low], False
    else:
        selectors, explicit_allowed = state.reader.byte(), True
        if selectors == 0:
            state.next = 0
    a = state.take_next() if low < 15 else state.explicit()
    b, push_b = _free_vertex(state, selectors >> 4, explicit_allowed)
    c, push_c = _free_vertex(state, selectors & 15, explicit_allowed)
    state.push_edge(b, a)
    state.push_edge(c, b)
    state.push_edge(a, c)
    state.push_vertex(a)
    if push_b:
        state.push_vertex(b)
    if push_c:
        state.push_vertex(c)
    return a, b, c


def decode_triangles(data: bytes, count: int, stride: int) -> bytes:
    """Mode 1: `count` indices (a triangle list) of `stride` bytes (2 or 4): one code byte per
    triangle, then the extra data they read, then the 16-byte codeaux table."""
    if count % 3 or stride not in (2, 4):
        raise ValueError(f"meshopt triangles: count {count} or byteStride {stride} invalid")
    triangles = count // 3
    if len(data) < 1 + triangles + _AUX_BYTES or data[0] != TRIANGLES_HEADER:
        raise ValueError("meshopt triangles: not a version 1 triangle stream (header 0xe1)")
    codes = data[1:1 + triangles]
    codeaux = data[len(data) - _AUX_BYTES:]
    state = _TriangleState(_Reader(data, 1 + triangles, len(data) - _AUX_BYTES))
    indices = []
    for code in codes:
        indices.extend(_edge_triangle(state, code) if code < 0xF0 else _free_triangle(state, code, codeaux))
    if state.reader.at != state.reader.end:
        raise ValueError("meshopt triangles: extra data left over")
    return np.array(indices, dtype=np.uint32 if stride == 4 else np.uint16).tobytes()


def decode_view(data: bytes, count: int, stride: int, mode: str, filter_name: str = "NONE") -> bytes:
    """The bytes of a bufferView compressed with EXT_meshopt_compression."""
    if filter_name != "NONE":
        raise ValueError(f"meshopt filter {filter_name} is not supported (Tessera writes none)")
    if mode == "ATTRIBUTES":
        return decode_attributes(data, count, stride)
    if mode == "TRIANGLES":
        return decode_triangles(data, count, stride)
    raise ValueError(f"meshopt mode {mode} is not supported (Tessera writes ATTRIBUTES and TRIANGLES)")
