"""The learner's own tracer, scaffolded by ``rtc new NAME``: a small package of its own.

Layout (``FOLDER`` is ``--dir``, by default ``./NAME``)::

    FOLDER/pyproject.toml      registers NAME in the ``rtc.variants`` entry-point group
    FOLDER/README.md           how to install it and work through the book
    FOLDER/NAME/__init__.py
    FOLDER/NAME/variant.py     the factory rtc calls: the book's names read from tracer.py
    FOLDER/NAME/tracer.py      every book function as a stub, in chapter order: the learner's

``scaffold`` writes the files that are missing and never replaces one that exists.
"""

from __future__ import annotations

import ast
import inspect
import re
import tomllib
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import groundwork.files
from raytracer.api import BOOK_API, CHAPTER_TITLES, naive_api
from variants.learner import CONSTANTS, python_names

# What the scenarios read from each chapter's values: the attributes and operators a
# learner's own types need (docs/architecture.md lists them all).
CHAPTER_NOTES: dict[int, str] = {
    1: "Tuples: the scenarios read a.x a.y a.z a.w, use + - * / and unary -, and compare "
    "with = (within EPSILON). 'a is a point' reads w (1.0 for a point, 0.0 for a vector).",
    2: "Colors: c.red c.green c.blue; + - and *, where color * color multiplies channel by "
    "channel. Canvases: c.width c.height; write_pixel changes the canvas (or returns a new "
    "one). canvas_to_ppm returns the PPM text.",
    3: "Matrices: M[row, col], M.size (the number of rows), M * M, M * tuple; = compares every "
    "cell within EPSILON.",
    4: "Every transformation is a 4x4 matrix (chapter 3).",
    5: "Rays: r.origin r.direction. Intersections: i.t i.object; intersections(...) is a list "
    "sorted by t (xs.count is its length). Shapes: s.transform (the identity at first).",
    6: "Lights: light.position light.intensity. Materials: m.color m.ambient m.diffuse "
    "m.specular m.shininess. Shapes: s.material.",
    7: "Worlds: w.objects (a list) and w.light. Computations: comps.t .object .point .eyev "
    ".normalv .inside. Cameras: c.hsize c.vsize c.field_of_view c.transform c.pixel_size; "
    "render returns a canvas.",
    8: "Computations gain comps.over_point.",
    9: "Every shape shares transform, material, intersect and normal_at, and adds its own "
    "local_intersect and local_normal_at; the test shape keeps its last ray as s.saved_ray.",
    10: "Patterns: p.a p.b p.transform; materials gain m.pattern.",
    11: "Materials gain m.reflective m.transparency m.refractive_index; computations gain "
    "comps.reflectv comps.n1 comps.n2 comps.under_point.",
    12: "Cubes are shapes (chapter 9).",
    13: "Cylinders and cones: .minimum .maximum .closed, which the scenarios set.",
    14: "Groups: g.children; shapes gain s.parent.",
    15: "Triangles: t.p1 t.p2 t.p3 t.e1 t.e2 t.normal (smooth ones also .n1 .n2 .n3); "
    "intersections gain i.u i.v. The OBJ parser: parser.vertices and parser.normals "
    "(1-based: item 0 unused), parser.default_group, parser.groups (name -> group), "
    "parser.ignored_lines.",
    16: "CSG shapes: c.operation c.left c.right.",
    17: "The bonus chapter 'Bounding boxes and hierarchies'. Boxes: box.min box.max (points; "
    "coordinates may be infinity or -infinity). bounding_box(empty) is called with no "
    "arguments, bounding_box(min=p max=q) with the keywords min and max. add_point and "
    "add_box may change the box or return a new one. '(left, right) ← f(...)' unpacks a "
    "tuple or list; [s1, s2] is a list.",
    18: "The bonus chapter 'Rendering soft shadows'. An area light: light.corner light.uvec "
    "light.vvec (one cell's edges) light.usteps light.vsteps light.samples light.position "
    "(its centre) light.intensity light.jitter_by (a sequence); a point light is read as "
    "light.position and light.intensity. sequence(...) cycles through its values; next(gen) "
    "is written next_ here (Python's own next stays usable). lighting's last argument is "
    "in_shadow (true or false) or the fraction of light that arrives (a number).",
    19: "The bonus chapter 'Texture mapping'. Mappings return a pair (u, v); "
    "face_from_point returns the face's name as a string ('left', 'right', 'front', "
    "'back', 'up', 'down'). canvas_from_ppm takes the file's text and raises ValueError "
    "for a malformed file ('should fail').",
}


class ScaffoldError(ValueError):
    """The folder cannot take the scaffold (it belongs to something else); names the file."""


@dataclass
class ScaffoldResult:
    """What ``scaffold`` did: files created and files left alone (paths relative to the
    folder), and the book names a kept ``tracer.py`` does not define."""

    folder: Path
    created: list[str] = field(default_factory=list)
    kept: list[str] = field(default_factory=list)
    undefined: list[str] = field(default_factory=list)


# ----------------------------------------------------------------------------- the stubs


def _signature(name: str, reference: Callable[..., object]) -> str:
    """The book's arguments of a function, from the reference: positional ones with their
    simple defaults and ``*args``; annotations, keyword-only hooks and ``**kwargs`` left out."""
    parts = []
    for parameter in inspect.signature(reference).parameters.values():
        if parameter.kind in (parameter.POSITIONAL_ONLY, parameter.POSITIONAL_OR_KEYWORD):
            default = parameter.default
            simple = default is None or isinstance(default, bool | int | float | str)
            if default is parameter.empty or not simple:
                parts.append(parameter.name)
            else:
                parts.append(f"{parameter.name}={default!r}")
        elif parameter.kind is parameter.VAR_POSITIONAL:
            parts.append(f"*{parameter.name}")
    return ", ".join(parts)


def _summary(reference: object) -> str:
    """The first paragraph of the reference's docstring, on one line."""
    doc = inspect.getdoc(reference) or ""
    return " ".join(doc.split("\n\n")[0].split())


def python_name(name: str) -> str:
    """The Python spelling of a book name in the scaffold: a name that would hide a Python
    builtin gets a trailing underscore (``tuple`` -> ``tuple_``, ``next`` -> ``next_``)."""
    return f"{name}_" if name in ("tuple", "next") else name


def stub_source(name: str) -> str:
    """One book name's stub: a function that raises ``NotImplementedYet``, or a constant
    placeholder."""
    if name in CONSTANTS:
        return f'{name} = not_written_yet("{name}")\n'
    reference = naive_api()[name]
    doc = _summary(reference).replace('"""', "'''").replace("\\", "\\\\")
    lines = [f"def {python_name(name)}({_signature(name, reference)}):"]
    if doc:
        lines.append(f'    """{doc}"""')
    lines.append(f'    raise NotImplementedYet("{name}")')
    return "\n".join(lines) + "\n"


def _wrapped_comment(text: str, width: int = 92) -> list[str]:
    lines: list[str] = []
    for word in text.split():
        if lines and len(lines[-1]) + 1 + len(word) <= width:
            lines[-1] += " " + word
        else:
            lines.append("# " + word if not lines else "#   " + word)
    return lines


def tracer_source(variant: str) -> str:
    """``tracer.py``: the module docstring, then every book name in chapter order."""
    header = f'''"""{variant}: my ray tracer, written test-first with "The Ray Tracer Challenge".

Every function the book's scenarios call is below, in chapter order, with the book's
argument names. Each starts as a stub that raises NotImplementedYet (naming the function
and its chapter), and `rtc kata` shows the scenarios that reach a stub as "to do". Replace
a stub's body with your code, then

    rtc kata --variant {variant} --next     the next scenario to make pass
    rtc kata --variant {variant} --watch    re-run whenever you save

Constants: EPSILON and identity_matrix start as not_written_yet(...), a placeholder that
raises NotImplementedYet on any use (arithmetic, comparison, indexing, attributes), so a
scenario that touches one is "to do" as well. Replace the placeholder with the value:
EPSILON = 0.0001, identity_matrix = matrix([...]) (it comes after matrix() below).

Names: the book's `tuple` and `next` are spelled `tuple_` and `next_` here, so that
Python's own stay usable; view_transform's `from` is `from_`. You may split this file into
modules of your own: rtc reads the book's names from this module, so import them here. A
name you delete shows as "undefined" in the kata.

Values: return types of your own. The scenarios read the attributes and use the operators
that each chapter's note below lists, and compare with `=` within EPSILON.
"""

from variants.learner import NotImplementedYet, not_written_yet
'''
    blocks = [header.rstrip("\n")]
    chapter = 0
    for name, introduced in BOOK_API.items():
        if introduced != chapter:
            chapter = introduced
            rule = f"# {'-' * 8} Chapter {chapter}: {CHAPTER_TITLES.get(chapter, '')} "
            blocks.append(
                "\n".join([rule.ljust(94, "-"), *_wrapped_comment(CHAPTER_NOTES.get(chapter, ""))])
            )
        blocks.append(stub_source(name).rstrip("\n"))
    return blocks[0] + "\n\n" + "\n\n\n".join(blocks[1:]) + "\n"


def variant_source(variant: str) -> str:
    """``variant.py``: the factory the ``rtc.variants`` entry point names."""
    return f'''"""The factory rtc calls to load {variant} (entry-point group rtc.variants):
the book's names, read from tracer.py each time an rtc command starts."""

from __future__ import annotations

import importlib
from typing import Any

from variants.learner import learner_variant

NAME = "{variant}"


def variant(inner: Any = None, **options: str) -> Any:
    """{variant} as a variant; it takes no options and wraps no other variant."""
    tracer = importlib.import_module(f"{{__package__}}.tracer")
    return learner_variant(NAME, tracer, inner, options)
'''


def init_source(variant: str) -> str:
    return f'"""{variant}: my own tracer for "The Ray Tracer Challenge" (the code: tracer.py)."""\n'


def pyproject_source(variant: str) -> str:
    """``pyproject.toml``: the package, and its entry point in the ``rtc.variants`` group."""
    return f"""# {variant}: my own tracer for "The Ray Tracer Challenge", an rtc variant.
[build-system]
requires = ["setuptools>=64"]
build-backend = "setuptools.build_meta"

[project]
name = "rtc-variant-{re.sub("_+", "-", variant).strip("-")}"
version = "0.1.0"
description = "A ray tracer written test-first with The Ray Tracer Challenge"
requires-python = ">=3.11"
dependencies = ["rtc-workbook"]

# This entry point lets every rtc command find the tracer as `--variant {variant}`.
[project.entry-points."rtc.variants"]
{variant} = "{variant}.variant:variant"

[tool.setuptools]
packages = ["{variant}"]
"""


def readme_source(variant: str, install: str, start: str) -> str:
    return f"""# {variant}

My own tracer for "The Ray Tracer Challenge", written chapter by chapter. The book's
scenarios (in the rtc workbook) are the tests; `{variant}/tracer.py` is the code.

    {install}    # once: install it, editable
    {start}      # the progress table of chapter 1
    rtc kata --variant {variant} --next           # the next scenario to make pass
    rtc kata --variant {variant} --watch          # re-run on every save
    rtc render SCENE.yml -o {variant}.png --variant {variant}   # once its chapters pass
"""


# ----------------------------------------------------------------------------- writing


MAX_LEARNER_FILE_BYTES = 4 << 20  # a pyproject.toml or tracer.py; never a pipe or a device


def entry_point_line(variant: str) -> str:
    return f'{variant} = "{variant}.variant:variant"'


def registers(pyproject: Path, variant: str) -> bool:
    """True if ``pyproject`` registers ``variant`` in the ``rtc.variants`` group."""
    try:
        data = tomllib.loads(groundwork.files.read_text(pyproject, MAX_LEARNER_FILE_BYTES))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
        return False
    group = data.get("project", {}).get("entry-points", {}).get("rtc.variants", {})
    return isinstance(group, dict) and variant in group


def defined_names(tracer: Path) -> set[str] | None:
    """The top-level names ``tracer`` defines, or None when that cannot be known from its
    text (a syntax error, or ``from x import *``)."""
    try:
        tree = ast.parse(groundwork.files.read_text(tracer, MAX_LEARNER_FILE_BYTES))
    except (OSError, SyntaxError, UnicodeDecodeError, ValueError):
        return None
    names: set[str] = set()
    for node in tree.body:
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            names.add(node.name)
        elif isinstance(node, ast.Assign | ast.AnnAssign | ast.AugAssign):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            for target in targets:
                names |= {n.id for n in ast.walk(target) if isinstance(n, ast.Name)}
        elif isinstance(node, ast.Import | ast.ImportFrom):
            for alias in node.names:
                if alias.name == "*":
                    return None
                names.add((alias.asname or alias.name).split(".")[0])
    return names


def write_new(path: Path, text: str) -> bool:
    """Write ``text`` to ``path`` atomically unless the file exists; True if written."""
    if path.exists():
        return False
    path.parent.mkdir(parents=True, exist_ok=True)
    return groundwork.files.write_new(path, text)


def files(variant: str, install: str, start: str) -> dict[str, str]:
    """The scaffold's files: path relative to the folder -> text."""
    return {
        "pyproject.toml": pyproject_source(variant),
        "README.md": readme_source(variant, install, start),
        f"{variant}/__init__.py": init_source(variant),
        f"{variant}/variant.py": variant_source(variant),
        f"{variant}/tracer.py": tracer_source(variant),
    }


def scaffold(variant: str, folder: Path, install: str, start: str) -> ScaffoldResult:
    """Write the scaffold for ``variant`` into ``folder``: every missing file, nothing else.

    An existing ``pyproject.toml`` that does not register ``variant`` is a ``ScaffoldError``
    (the folder is some other project), and nothing is written.
    """
    if folder.exists() and not folder.is_dir():
        raise ScaffoldError(f"{folder} is a file, not a folder")
    pyproject = folder / "pyproject.toml"
    if pyproject.exists() and not registers(pyproject, variant):
        raise ScaffoldError(
            f"{pyproject} exists and does not register the variant {variant!r} "
            f'(no {entry_point_line(variant)!r} under [project.entry-points."rtc.variants"]);'
            " choose another folder with --dir"
        )
    result = ScaffoldResult(folder)
    for relative, text in files(variant, install, start).items():
        written = write_new(folder / relative, text)
        (result.created if written else result.kept).append(relative)
    tracer = folder / variant / "tracer.py"
    if f"{variant}/tracer.py" in result.kept:
        names = defined_names(tracer)
        if names is not None:
            result.undefined = [
                name
                for name in BOOK_API
                if not any(spelling in names for spelling in python_names(name))
            ]
    return result
