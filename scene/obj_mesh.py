"""OBJ models (chapter 15) read straight into arrays: a ``Mesh``, as pbrt's ``TriangleMesh``
holds one: shared vertex and normal arrays and three vertex numbers per triangle, never an
object per triangle. A tracer that uses the book's shapes builds them from it
(``scene.build``); the compiled and vectorized tracers pack its arrays.

``read_mesh`` gives what the book's ``parse_obj_file`` and ``obj_to_group`` give, number for
number and in the same order (the default group's triangles, then each named group's, in the
order their ``g`` lines first appear), with the same errors, naming the same lines: the
lines of ordinary form are read by compiled code (``scene.obj_scan``), every other line by
Python with the book parser's own line readers, in file order, so that the first mistake in
the file is the one reported. Text the scanner does not handle at all (a NUL byte, lines
broken by characters other than ``\\n``, a word that only Python can split) is read by the
book's parser itself and converted.

Beyond the book: a UTF-8 byte-order mark at the start is not part of the first line (the
book's parser would read ``\\ufeffv`` as an unknown keyword and shift every vertex).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Any

import numpy as np

from raytracer.obj_file import (
    DEGENERATE_SINE,
    ObjNoFacesError,
    ObjParseError,
    _coordinates,
    _corners,
    _no_faces,
    obj_to_group,
    parse_obj_file,
)
from raytracer.shapes.group import Group

BOM = b"\xef\xbb\xbf"
# bytes the scanner leaves to the book's parser: NUL (a binary file: the parser names its
# line) and every line break of Python's splitlines but \n and \r\n
EXOTIC = (b"\x00", b"\x0b", b"\x0c", b"\x1c", b"\x1d", b"\x1e", b"\xc2\x85", b"\xe2\x80\xa8",
          b"\xe2\x80\xa9")  # fmt: skip
EXTRA_SLOW = 4096  # slow lines of ordinary kind (v, vn, f) the scan makes room for


def _scanner() -> Any:
    """The compiled OBJ scanner's function, built or loaded the first time an OBJ is read
    (``compiled.library``: a scene without one never loads it)."""
    # deferred: saves ~100 ms (ctypes, the library loader) of every scene load without an OBJ model
    from compiled.library import Recipe, load

    return load(
        Recipe(
            name="obj_scan",
            module="scene.obj_scan",
            function="run_arrays",
            parameters=(
                ("int64_t", "mode"),
                ("uint8_t *", "buf"),
                ("int64_t", "base"),
                ("int64_t", "n"),
                ("int64_t *", "counts"),
                ("double *", "vs"),
                ("double *", "ns"),
                ("int32_t *", "tri"),
                ("int32_t *", "tri_n"),
                ("int32_t *", "tri_line"),
                ("int32_t *", "tri_group"),
                ("int64_t *", "slow"),
                ("int64_t", "capacity"),
                ("int8_t *", "flags"),
                ("double", "limit"),
            ),
            what="the OBJ scanner",
        )
    ).function


@dataclass(frozen=True, eq=False)
class Mesh:
    """Chapter 15's model as arrays.

    source: the file it came from (for messages); positions: the vertices (n x 3 floats),
    numbered from 0; normals: the vertex normals (m x 3); triangles: each triangle's corners
    (t x 3 vertex numbers, int32); corner_normals: each corner's normal number (t x 3,
    int32), -1 for a flat triangle's corners, None when every triangle is flat; groups:
    (name, triangles) in order, "" for the faces before any named group (present only when
    it has some; a named group may have none); lines: lines read; ignored_lines: lines not
    understood; degenerate: triangles left out for having no area, the first at line
    ``first_degenerate_line`` (0: none).
    """

    source: str
    positions: np.ndarray
    normals: np.ndarray
    triangles: np.ndarray
    corner_normals: np.ndarray | None
    groups: tuple[tuple[str, int], ...]
    lines: int = 0
    ignored_lines: int = 0
    degenerate: int = 0
    first_degenerate_line: int = 0

    @property
    def count(self) -> int:
        """How many triangles."""
        return len(self.triangles)

    def smooth(self) -> np.ndarray:
        """Per triangle: True for a smooth triangle (a normal at every corner)."""
        if self.corner_normals is None:
            return np.zeros(self.count, dtype=bool)
        return self.corner_normals[:, 0] >= 0

    def corners(self, rows: slice | np.ndarray = slice(None)) -> np.ndarray:
        """The corners of triangles ``rows`` as points: (t, 3 corners, 3 axes) floats."""
        return self.positions[self.triangles[rows]]


def read_mesh(data: bytes, source: str, *, require_faces: bool = True) -> Mesh:
    """Chapter 15: OBJ text (bytes, UTF-8) as a ``Mesh``; an ``ObjParseError`` naming the line
    of the first mistake, or an ``ObjNoFacesError`` (``require_faces``) for text that makes no
    triangle."""
    if data.startswith(BOM):
        data = data[len(BOM) :]
    if any(marker in data for marker in EXOTIC) or data.count(b"\r") != data.count(b"\r\n"):
        return _normals_checked(book_mesh(data, source, require_faces=require_faces), data)
    scanned = _Scan(data, source).run()
    if scanned is None:  # text only Python can split, or too many slow lines
        return _normals_checked(book_mesh(data, source, require_faces=require_faces), data)
    if require_faces and scanned.count == 0:
        found = SimpleNamespace(
            lines=scanned.lines, vertices=range(len(scanned.positions) + 1),
            ignored_lines=scanned.ignored_lines, degenerate_triangles=scanned.degenerate,
            first_degenerate_line=scanned.first_degenerate_line,
        )  # fmt: skip
        raise ObjNoFacesError(source, _no_faces(source, found))  # type: ignore[arg-type]
    return _normals_checked(scanned, data)


def _normals_checked(mesh: Mesh, data: bytes) -> Mesh:
    """``mesh``, unless a triangle's corner uses a normal of length 0 (``vn 0 0 0``): that
    corner would shade as if lit from nowhere (ambient light only). An ``ObjParseError``
    naming the ``vn`` line then."""
    if mesh.corner_normals is None or not len(mesh.normals):
        return mesh
    used = np.unique(mesh.corner_normals[mesh.corner_normals >= 0])
    flat = used[~np.any(mesh.normals[used] != 0.0, axis=1)]
    if not len(flat):
        return mesh
    wanted, seen = int(flat[0]), -1
    for number, line in enumerate(_decode(data).split("\n"), start=1):
        if line.split(maxsplit=1)[:1] == ["vn"]:
            seen += 1
            if seen == wanted:
                raise ObjParseError(
                    mesh.source, number, line, "a vertex normal of length 0 has no direction "
                    "(a smooth triangle's corner uses it); give its direction, or leave the "
                    "face's normals out (f 1 2 3) for a flat triangle",
                )  # fmt: skip
    raise ObjParseError(mesh.source, 0, "", f"vertex normal {wanted + 1} has length 0")


def _decode(data: bytes) -> str:
    """Bytes as the scene loader reads a file: UTF-8, errors replaced, \\r\\n as \\n."""
    return data.decode("utf-8", errors="replace").replace("\r\n", "\n").replace("\r", "\n")


def book_mesh(data: bytes, source: str, *, require_faces: bool = True) -> Mesh:
    """The same ``Mesh``, read by the book's parser itself (``parse_obj_file``,
    ``obj_to_group``) and converted: for text the scanner leaves alone."""
    if data.startswith(BOM):
        data = data[len(BOM) :]
    parser = parse_obj_file(_decode(data), source=source, require_faces=require_faces)
    vertex = {id(v): k - 1 for k, v in enumerate(parser.vertices) if v is not None}
    normal = {id(n): k - 1 for k, n in enumerate(parser.normals) if n is not None}
    triangles: list[list[int]] = []
    corner_normals: list[list[int]] = []
    groups: list[tuple[str, int]] = []
    names = {id(g): name for name, g in parser.groups.items()}
    for g in obj_to_group(parser).children:
        assert isinstance(g, Group)
        groups.append((names.get(id(g), ""), len(g.children)))
        for t in g.children:
            corners: Any = t
            triangles.append([vertex[id(p)] for p in (t.p1, t.p2, t.p3)])  # type: ignore[attr-defined]
            smooth = hasattr(corners, "n1")
            corner_normals.append(
                [normal[id(n)] for n in (corners.n1, corners.n2, corners.n3)]
                if smooth
                else [-1, -1, -1]
            )
    positions = [[v.x, v.y, v.z] for v in parser.vertices[1:] if v is not None]
    normals = [[n.x, n.y, n.z] for n in parser.normals[1:] if n is not None]
    cn = np.array(corner_normals, dtype=np.int32).reshape(-1, 3)
    return Mesh(
        source,
        np.array(positions, dtype=np.float64).reshape(-1, 3),
        np.array(normals, dtype=np.float64).reshape(-1, 3),
        np.array(triangles, dtype=np.int32).reshape(-1, 3),
        cn if (cn >= 0).any() else None,
        tuple(groups),
        parser.lines,
        parser.ignored_lines,
        parser.degenerate_triangles,
        parser.first_degenerate_line,
    )


class _Layout:
    """The scanner's modes, counts and slow-line records (``scene.obj_scan``, which imports
    numba and so is imported only to build it; the tests check that the two agree)."""

    COUNT, SCAN, DEGENERATE = 0, 1, 2
    C_LINES, C_VERTICES, C_NORMALS, C_TRIANGLES, C_GROUPS, C_SLOW, C_IGNORED = range(7)
    N_COUNTS = 7
    S_LINE, S_START, S_END, S_KIND, S_SLOT, S_VERTICES, S_NORMALS, S_TRIANGLES = range(8)
    S_GROUP = 8
    SLOW_WIDTH = 9
    K_V, K_VN, K_F, K_G, K_OTHER = 1, 2, 3, 4, 5


class _Scan:
    """One read of OBJ bytes by the compiled scanner and Python (``read_mesh``)."""

    def __init__(self, data: bytes, source: str) -> None:
        self.S = _Layout
        self.data = data
        self.source = source
        self.buf = np.frombuffer(data, dtype=np.uint8) if data else np.zeros(1, np.uint8)
        self.scanner = _scanner()

    def _call(self, mode: int, counts: np.ndarray, arrays: dict[str, Any], capacity: int) -> int:
        a = arrays
        done = self.scanner(
            mode, self.buf, self.buf.ctypes.data, len(self.data), counts, a["vs"], a["ns"],
            a["tri"], a["tri_n"], a["tri_line"], a["tri_group"], a["slow"], capacity,
            a["flags"], DEGENERATE_SINE * DEGENERATE_SINE,
        )  # fmt: skip
        return int(done)

    def run(self) -> Mesh | None:
        S = self.S
        counts = np.zeros(S.N_COUNTS, dtype=np.int64)
        one: dict[str, np.ndarray] = {
            "vs": np.zeros(3), "ns": np.zeros(3), "tri": np.zeros(3, np.int32),
            "tri_n": np.zeros(3, np.int32), "tri_line": np.zeros(1, np.int32),
            "tri_group": np.zeros(1, np.int32), "slow": np.zeros(S.SLOW_WIDTH, np.int64),
            "flags": np.zeros(1, np.int8),
        }  # fmt: skip
        self._call(S.COUNT, counts, one, 0)
        nv, nn, nt = (int(counts[k]) for k in (S.C_VERTICES, S.C_NORMALS, S.C_TRIANGLES))
        capacity = int(counts[S.C_SLOW]) + EXTRA_SLOW
        arrays: dict[str, np.ndarray] = {
            "vs": np.zeros(3 * max(nv, 1)), "ns": np.zeros(3 * max(nn, 1)),
            "tri": np.zeros(3 * max(nt, 1), np.int32),
            "tri_n": np.full(3 * max(nt, 1), -1, np.int32),
            "tri_line": np.zeros(max(nt, 1), np.int32),
            "tri_group": np.zeros(max(nt, 1), np.int32),
            "slow": np.zeros(S.SLOW_WIDTH * capacity, np.int64), "flags": one["flags"],
        }  # fmt: skip
        if self._call(S.SCAN, counts, arrays, capacity) != 0:
            return None
        slow = arrays["slow"][: S.SLOW_WIDTH * int(counts[S.C_SLOW])].reshape(-1, S.SLOW_WIDTH)
        names = self._slow_lines(slow, arrays, counts)
        if names is None:
            return None
        arrays["flags"] = np.zeros(max(nt, 1), np.int8)
        self._call(S.DEGENERATE, counts, arrays, capacity)
        return self._mesh(arrays, counts, names, nv, nn, nt)

    def _slow_lines(
        self, slow: np.ndarray, arrays: dict[str, Any], counts: np.ndarray
    ) -> list[str] | None:
        """Read every slow line, in file order, with the book parser's line readers (so a
        mistake is reported as the book's parser reports it); the names of the ``g`` lines
        (by number, from 1). None when a line turns out to be one the scanner misread."""
        S = self.S
        source = self.source
        names = [""]
        for record in slow.tolist():
            number, start, end, kind, slot, vertices, normals, triangles, _ = record
            line = self.data[start:end].decode("utf-8", errors="replace")
            if line.endswith("\r"):
                line = line[:-1]
            words = line.split()
            keyword = words[0] if words else ""
            if kind == S.K_OTHER:
                if keyword in ("v", "vn", "f", "g"):  # split at a space only Python sees
                    return None
                if not keyword.startswith("#") and words:
                    counts[S.C_IGNORED] += 1
                continue
            expected = {S.K_V: "v", S.K_VN: "vn", S.K_F: "f", S.K_G: "g"}[kind]
            if keyword != expected:
                return None
            if kind == S.K_G:
                names.append(" ".join(words[1:]))
            elif kind in (S.K_V, S.K_VN):
                form, allowed = ("v x y z", (3, 4)) if kind == S.K_V else ("vn x y z", (3,))
                x, y, z, *_ = _coordinates(source, number, line, words, allowed, form)
                out = arrays["vs"] if kind == S.K_V else arrays["ns"]
                out[3 * slot : 3 * slot + 3] = (x, y, z)
            else:
                known = SimpleNamespace(vertices=range(vertices + 1), normals=range(normals + 1))
                corners = _corners(source, number, line, words, known)  # type: ignore[arg-type]
                if len(corners) - 2 != triangles:
                    return None
                self._fan(arrays, slot, corners, number, record[S.S_GROUP])
        return names

    @staticmethod
    def _fan(
        arrays: dict[str, Any], slot: int, corners: Sequence[tuple[Any, Any]], number: int,
        group: int,
    ) -> None:  # fmt: skip
        """Chapter 15: a slow face's triangles (its corners: 1-based vertex and normal
        numbers) into their slots."""
        (v0, n0) = corners[0]
        for k in range(1, len(corners) - 1):
            s = slot + k - 1
            (v1, n1), (v2, n2) = corners[k], corners[k + 1]
            arrays["tri"][3 * s : 3 * s + 3] = (v0 - 1, v1 - 1, v2 - 1)
            if n0 is not None:
                arrays["tri_n"][3 * s : 3 * s + 3] = (n0 - 1, n1 - 1, n2 - 1)
            arrays["tri_line"][s] = number
            arrays["tri_group"][s] = group

    def _mesh(
        self, arrays: dict[str, Any], counts: np.ndarray, names: list[str], nv: int, nn: int,
        nt: int,
    ) -> Mesh:  # fmt: skip
        S = self.S
        flags = arrays["flags"][:nt].view(bool)
        tri = arrays["tri"][: 3 * nt].reshape(nt, 3)
        tri_n = arrays["tri_n"][: 3 * nt].reshape(nt, 3)
        lines = arrays["tri_line"][:nt]
        degenerate = int(flags.sum())
        first = int(lines[flags].min()) if degenerate else 0
        # each triangle's group: the default one ("") first, then named ones as they appear
        order = {"": 0}
        for name in names[1:]:
            order.setdefault(name, len(order))
        rank = np.array([order[name] for name in names], dtype=np.int32)
        which = rank[arrays["tri_group"][:nt]]
        keep = ~flags
        if degenerate:
            tri, tri_n, which = tri[keep], tri_n[keep], which[keep]
        if len(which) and (np.diff(which) < 0).any():  # groups out of order: sort, stably
            by_group = np.argsort(which, kind="stable")
            tri, tri_n, which = tri[by_group], tri_n[by_group], which[by_group]
        sizes = np.bincount(which, minlength=len(order)) if len(order) else np.zeros(0)
        groups = [("", int(sizes[0]))] if sizes[0] else []
        groups += [(name, int(sizes[k])) for name, k in order.items() if k > 0]
        smooth = bool((tri_n[:, 0] >= 0).any()) if len(tri_n) else False
        return Mesh(
            self.source,
            arrays["vs"][: 3 * nv].reshape(nv, 3),
            arrays["ns"][: 3 * nn].reshape(nn, 3),
            np.ascontiguousarray(tri),
            np.ascontiguousarray(tri_n) if smooth else None,
            tuple(groups),
            int(counts[S.C_LINES]),
            int(counts[S.C_IGNORED]),
            degenerate,
            first,
        )
