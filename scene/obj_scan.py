"""Chapter 15's OBJ text, scanned by compiled code: the lines of ordinary form read straight
into arrays, every other line left to Python (``scene.obj_mesh``).

This file is self-contained (numba's ``cache=True`` checks only the file a function is in):
it imports no project module. ``scene.obj_mesh`` calls it through a small shared library
built from ``make_entry`` (``compiled.library``), so that reading a model needs no numba at
run time, or through numba itself when no C compiler is found.

One entry point, ``run(mode, ...)``, over raw bytes (``buf``, ``n`` long) and arrays:

- mode ``COUNT``: how many lines, vertices, normals, triangle slots, group lines, slow lines
  and ignored lines the text has (``counts``), so that the caller can allocate;
- mode ``SCAN``: the vertices and normals of ordinary ``v`` and ``vn`` lines into ``vs`` and
  ``ns``; the triangles of ordinary ``f`` lines, fanned from their first corner as the book
  does, into ``tri`` (corners' vertex numbers, from 0), ``tri_n`` (their normals' numbers,
  -1 for a flat triangle), ``tri_line`` (the face's line) and ``tri_group`` (how many ``g``
  lines came before it); one record per *slow* line into ``slow`` (``SLOW_WIDTH`` ints);
- mode ``DEGENERATE``: for every triangle, 1 in ``flags`` when it has no area, by the very
  arithmetic of ``raytracer.obj_file.is_degenerate`` (``limit`` = DEGENERATE_SINE²).

A line is *ordinary* when Python's own reading could not say anything else about it: a
``v`` line of 3 or 4 plain decimal numbers (at most 15 significant digits and a power of ten
within ±22, which one multiplication or division by an exact power of ten rounds correctly,
as Python's ``float`` does); a ``vn`` line of 3; an ``f`` line of 3 or more corners ``v``,
``v/t``, ``v//n`` or ``v/t/n`` (plain integers), every corner with a normal or none, every
number naming a vertex or normal already read; a comment, a blank line, or a line whose first
word is another plain keyword (``vt``, ``s``, ``usemtl`` ...: ignored). Every other line (a
``g`` line, whose name Python reads; anything not plain ASCII; any form or number outside the
above, mistakes included) is slow: its vertex, normal or triangle slots are reserved and
Python fills them in, or says what is wrong, in file order.

Bytes the caller must have ruled out (it reads such text with Python alone): NUL, and the
characters other than ``\\n`` (and ``\\r\\n``) that Python's ``splitlines`` breaks lines at.
"""

import math
from typing import Any

import numpy as np
from numba import cfunc, njit, types

COUNT = 0
SCAN = 1
DEGENERATE = 2

# counts[...]
C_LINES = 0
C_VERTICES = 1
C_NORMALS = 2
C_TRIANGLES = 3  # triangle slots: the faces' corners - 2, ordinary or slow
C_GROUPS = 4  # g lines
C_SLOW = 5
C_IGNORED = 6
N_COUNTS = 7

# slow[k * SLOW_WIDTH + ...]: one line for Python
S_LINE = 0  # its number, from 1
S_START = 1  # its bytes: [start, end)
S_END = 2
S_KIND = 3  # K_ below
S_SLOT = 4  # v: its vertex; vn: its normal; f: its first triangle slot; g: its number, from 1
S_VERTICES = 5  # vertices read before it
S_NORMALS = 6  # normals read before it
S_TRIANGLES = 7  # f: its triangle slots (its words - 3)
S_GROUP = 8  # g lines before it
SLOW_WIDTH = 9

K_V = 1
K_VN = 2
K_F = 3
K_G = 4
K_OTHER = 5  # a first word that is not plain ASCII

POWERS = np.array([10.0**k for k in range(23)])  # exact: every one is a float
# the C library's strtod (correctly rounded, as Python's float is) for a plain number outside
# the fast path; its pointer arguments are passed as integers (the same registers)
strtod: Any = types.ExternalFunction("strtod", types.float64(types.intp, types.intp))


@njit(cache=True, error_model="numpy")
def _space(c):
    """ASCII whitespace as Python's ``str.split`` sees it (the caller rules out the ones
    that also break lines, but ``\\r`` of ``\\r\\n``)."""
    return c == 32 or c == 9 or c == 13 or c == 31


@njit(cache=True, error_model="numpy")
def _word_end(buf, i, end):
    while i < end and not _space(buf[i]):
        i += 1
    return i


@njit(cache=True, error_model="numpy")
def _skip_space(buf, i, end):
    while i < end and _space(buf[i]):
        i += 1
    return i


@njit(cache=True, error_model="numpy")
def _keyword(buf, i, end):
    """The line's first word as a code: 1 v, 2 vn, 3 f, 4 g, 5 a comment, 6 another plain
    word, 7 a word with a byte outside ASCII, 0 none (a blank line)."""
    j = _word_end(buf, i, end)
    if j == i:
        return 0
    for k in range(i, j):
        if buf[k] >= 128:
            return 7
    if buf[i] == 35:  # '#'
        return 5
    if j - i == 1:
        c = buf[i]
        if c == 118:  # v
            return 1
        if c == 102:  # f
            return 3
        if c == 103:  # g
            return 4
    if j - i == 2 and buf[i] == 118 and buf[i + 1] == 110:  # vn
        return 2
    return 6


@njit(cache=True, error_model="numpy")
def _words(buf, i, end):
    """How many words from i to end."""
    count = 0
    i = _skip_space(buf, i, end)
    while i < end:
        count += 1
        i = _skip_space(buf, _word_end(buf, i, end), end)
    return count


@njit(cache=True, error_model="numpy")
def _number(buf, base, i, end):
    """A plain decimal number filling buf[i:end]: (ok, value); ok False for any other form,
    or one that needs more than the correctly rounded fast path."""
    first = i
    negative = False
    if i < end and (buf[i] == 43 or buf[i] == 45):
        negative = buf[i] == 45
        i += 1
    mantissa = 0
    significant = 0
    exponent = 0
    digits = 0
    while i < end and 48 <= buf[i] <= 57:
        d = buf[i] - 48
        if mantissa > 0 or d > 0:
            significant += 1
        if significant <= 15:
            mantissa = mantissa * 10 + d
        else:
            exponent += 1  # a digit past the 15th: the fast path cannot take it
        digits += 1
        i += 1
    if i < end and buf[i] == 46:  # '.'
        i += 1
        while i < end and 48 <= buf[i] <= 57:
            d = buf[i] - 48
            if mantissa > 0 or d > 0:
                significant += 1
            if significant <= 15:
                mantissa = mantissa * 10 + d
                exponent -= 1
            digits += 1
            i += 1
    if digits == 0:
        return False, 0.0
    if i < end and (buf[i] == 101 or buf[i] == 69):  # e, E
        i += 1
        minus = False
        if i < end and (buf[i] == 43 or buf[i] == 45):
            minus = buf[i] == 45
            i += 1
        power = 0
        count = 0
        while i < end and 48 <= buf[i] <= 57:
            if power < 100000:
                power = power * 10 + (buf[i] - 48)
            count += 1
            i += 1
        if count == 0:
            return False, 0.0
        exponent += -power if minus else power
    if i != end:
        return False, 0.0
    if mantissa == 0 and significant == 0:
        value = 0.0
    elif significant <= 15 and 0 <= exponent <= 22:
        value = float(mantissa) * POWERS[exponent]
    elif significant <= 15 and -22 <= exponent < 0:
        value = float(mantissa) / POWERS[-exponent]
    else:  # the token is a plain number and is followed by a space or the line's end
        value = strtod(base + first, 0)
        return math.isfinite(value), value
    return True, -value if negative else value


@njit(cache=True, error_model="numpy")
def _integer(buf, i, end):
    """A plain integer filling buf[i:end] (a sign allowed): (ok, value)."""
    negative = False
    if i < end and (buf[i] == 43 or buf[i] == 45):
        negative = buf[i] == 45
        i += 1
    if i >= end:
        return False, 0
    value = 0
    while i < end:
        c = buf[i]
        if c < 48 or c > 57 or value > 100000000000:
            return False, 0
        value = value * 10 + (c - 48)
        i += 1
    return True, -value if negative else value


@njit(cache=True, error_model="numpy")
def _position(index, defined):
    """The 1-based position a face's index names (negative: from the last defined), or 0
    when it names nothing defined so far."""
    position = index if index > 0 else defined + 1 + index
    if index == 0 or position < 1 or position > defined:
        return 0
    return position


@njit(cache=True, error_model="numpy")
def _corner(buf, i, end, vertices, normals):
    """One corner ``v``, ``v/t``, ``v//n`` or ``v/t/n`` in buf[i:end]: (ok, vertex from 0,
    normal from 0 or -1)."""
    slash1 = -1
    slash2 = -1
    for k in range(i, end):
        if buf[k] == 47:  # '/'
            if slash1 < 0:
                slash1 = k
            elif slash2 < 0:
                slash2 = k
            else:
                return False, 0, 0
    v_end = end if slash1 < 0 else slash1
    ok, v = _integer(buf, i, v_end)
    if not ok:
        return False, 0, 0
    position = _position(v, vertices)
    if position == 0:
        return False, 0, 0
    if slash1 >= 0:
        t_end = end if slash2 < 0 else slash2
        if t_end > slash1 + 1:  # a texture number: checked, not used
            ok, _ = _integer(buf, slash1 + 1, t_end)
            if not ok:
                return False, 0, 0
        elif slash2 < 0:
            return False, 0, 0  # 'v/': Python reads it; rare enough to leave to it
    normal = -1
    if slash2 >= 0:
        if slash2 + 1 >= end:
            return False, 0, 0  # 'v//' or 'v/t/': as above
        ok, n = _integer(buf, slash2 + 1, end)
        if not ok:
            return False, 0, 0
        found = _position(n, normals)
        if found == 0:
            return False, 0, 0
        normal = found - 1
    return True, position - 1, normal


@njit(cache=True, error_model="numpy")
def _face(buf, i, end, vertices, normals, corners, tri, tri_n, tri_line, tri_group, slot, line,
          group):  # fmt: skip
    """An ordinary face's triangles into the slots from ``slot`` (its ``corners`` - 2, read
    from i to end); False (nothing written) when the line is not ordinary."""
    first_v = 0
    first_n = 0
    prev_v = 0
    prev_n = 0
    k = 0
    smooth = False
    i = _skip_space(buf, i, end)
    while i < end:
        j = _word_end(buf, i, end)
        ok, v, n = _corner(buf, i, j, vertices, normals)
        if not ok:
            return False
        if k == 0:
            smooth = n >= 0
        elif (n >= 0) != smooth:
            return False
        if k == 0:
            first_v = v
            first_n = n
        elif k >= 2:
            s = slot + k - 2
            tri[3 * s] = first_v
            tri[3 * s + 1] = prev_v
            tri[3 * s + 2] = v
            tri_n[3 * s] = first_n
            tri_n[3 * s + 1] = prev_n
            tri_n[3 * s + 2] = n
            tri_line[s] = line
            tri_group[s] = group
        prev_v = v
        prev_n = n
        k += 1
        i = _skip_space(buf, j, end)
    return k == corners


@njit(cache=True, error_model="numpy")
def _vector(buf, base, i, end, out, at, most):
    """3 (or ``most``, 4) plain numbers from i to end into out[at:at + 3] (the 4th, a
    ``v`` line's w, is read and dropped); False when the line is not ordinary."""
    k = 0
    i = _skip_space(buf, i, end)
    while i < end:
        j = _word_end(buf, i, end)
        if k >= most:
            return False
        ok, value = _number(buf, base, i, j)
        if not ok:
            return False
        if k < 3:
            out[at + k] = value
        k += 1
        i = _skip_space(buf, j, end)
    return k >= 3


@njit(cache=True, error_model="numpy")
def _slow(slow, counts, capacity, line, start, end, kind, slot, vertices, normals, triangles,
          group):  # fmt: skip
    """Record a slow line; False when ``slow`` is full (then nothing more is read)."""
    k = counts[C_SLOW]
    if k >= capacity:
        return False
    s = k * SLOW_WIDTH
    slow[s + S_LINE] = line
    slow[s + S_START] = start
    slow[s + S_END] = end
    slow[s + S_KIND] = kind
    slow[s + S_SLOT] = slot
    slow[s + S_VERTICES] = vertices
    slow[s + S_NORMALS] = normals
    slow[s + S_TRIANGLES] = triangles
    slow[s + S_GROUP] = group
    counts[C_SLOW] = k + 1
    return True


@njit(cache=True, error_model="numpy")
def _degenerate(counts, vs, tri, flags, limit):
    """``raytracer.obj_file.is_degenerate`` for every triangle, term by term."""
    for t in range(counts[C_TRIANGLES]):
        a = 3 * tri[3 * t]
        b = 3 * tri[3 * t + 1]
        c = 3 * tri[3 * t + 2]
        ax = vs[b] - vs[a]
        ay = vs[b + 1] - vs[a + 1]
        az = vs[b + 2] - vs[a + 2]
        bx = vs[c] - vs[a]
        by = vs[c + 1] - vs[a + 1]
        bz = vs[c + 2] - vs[a + 2]
        cx = ay * bz - az * by
        cy = az * bx - ax * bz
        cz = ax * by - ay * bx
        area = cx * cx + cy * cy + cz * cz
        scale = (ax * ax + ay * ay + az * az) * (bx * bx + by * by + bz * bz)
        flags[t] = 1 if area <= scale * limit else 0


@njit(cache=True, error_model="numpy")
def run(mode, buf, base, n, counts, vs, ns, tri, tri_n, tri_line, tri_group, slow, capacity,
        flags, limit):  # fmt: skip
    """See the module's docstring. ``base``: the address of ``buf`` (for ``strtod``);
    ``capacity``: how many slow lines ``slow`` holds. Returns 0, or 1 when there were more
    slow lines than that (the scan stopped)."""
    if mode == DEGENERATE:
        _degenerate(counts, vs, tri, flags, limit)
        return 0
    scan = mode == SCAN
    for k in range(N_COUNTS):
        counts[k] = 0
    line = 0
    start = 0
    group = 0
    full = False
    while start < n and not full:
        end = start
        while end < n and buf[end] != 10:
            end += 1
        line += 1
        i = _skip_space(buf, start, end)
        key = _keyword(buf, i, end)
        body = _word_end(buf, i, end)
        vertices = counts[C_VERTICES]
        normals = counts[C_NORMALS]
        if key == 1 or key == 2:  # v, vn
            which = C_VERTICES if key == 1 else C_NORMALS
            slot = counts[which]
            counts[which] += 1
            if scan:
                out = vs if key == 1 else ns
                if not _vector(buf, base, body, end, out, 3 * slot, 4 if key == 1 else 3):
                    full = not _slow(slow, counts, capacity, line, start, end,
                                     K_V if key == 1 else K_VN, slot, vertices, normals, 0,
                                     group)  # fmt: skip
        elif key == 3:  # f
            words = _words(buf, body, end)
            triangles = words - 2 if words >= 3 else 0
            slot = counts[C_TRIANGLES]
            counts[C_TRIANGLES] += triangles
            if scan:
                ordinary = words >= 3 and _face(
                    buf, body, end, vertices, normals, words, tri, tri_n, tri_line, tri_group,
                    slot, line, group,
                )  # fmt: skip
                if not ordinary:
                    full = not _slow(slow, counts, capacity, line, start, end, K_F, slot,
                                     vertices, normals, triangles, group)  # fmt: skip
        elif key == 4:  # g: always slow (Python reads the name)
            counts[C_GROUPS] += 1
            if scan:
                full = not _slow(slow, counts, capacity, line, start, end, K_G,
                                 counts[C_GROUPS], vertices, normals, 0, group)  # fmt: skip
            else:
                counts[C_SLOW] += 1
            group = counts[C_GROUPS]
        elif key == 6:
            counts[C_IGNORED] += 1
        elif key == 7:  # always slow (Python reads it)
            if scan:
                full = not _slow(slow, counts, capacity, line, start, end, K_OTHER, 0,
                                 vertices, normals, 0, group)  # fmt: skip
            else:
                counts[C_SLOW] += 1
        start = end + 1
    counts[C_LINES] = line
    return 1 if full else 0


def make_entry(cache: bool) -> Any:
    """``run`` as a C function over raw pointers (numba's ``cfunc``): ``int64 f(int64 mode,
    uint8 *buf, int64 base, int64 n, int64 *counts, double *vs, double *ns, int32 *tri,
    int32 *tri_n, int32 *tri_line, int32 *tri_group, int64 *slow, int64 capacity, int8
    *flags, double limit)``; ``cache``: numba's disk cache."""
    i64, f64 = types.int64, types.float64
    p32 = types.CPointer(types.int32)
    signature = i64(
        i64, types.CPointer(types.uint8), i64, i64, types.CPointer(i64), types.CPointer(f64),
        types.CPointer(f64), p32, p32, p32, p32, types.CPointer(i64), i64,
        types.CPointer(types.int8), f64,
    )  # fmt: skip
    flags: dict[str, Any] = {"_nrt": False, "error_model": "numpy"}
    return cfunc(signature, cache=cache, **flags)(run.py_func)


def run_arrays(mode, buf, base, n, counts, vs, ns, tri, tri_n, tri_line, tri_group, slow,
               capacity, flags, limit):  # fmt: skip
    """The shared library's entry point, called with numpy arrays, through numba (where
    no library could be built)."""
    return run(mode, buf, base, n, counts, vs, ns, tri, tri_n, tri_line, tri_group, slow,
               capacity, flags, limit)  # fmt: skip
