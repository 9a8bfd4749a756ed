"""A command starts at Python's floor: ``rtc --help`` imports no command module and no numpy,
and ``rtc render`` imports what the scene and the variant need and nothing of the report,
the plots, the bench, Pillow, psutil or importlib.metadata's scan (issue 36, item 4).

Each case runs the command in a fresh interpreter and looks at ``sys.modules`` after it:
what was imported, never how long it took (no verdict here depends on the machine)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
from yaml.nodes import ScalarNode, SequenceNode

from rtc.cli import COMMANDS

ROOT = Path(__file__).resolve().parent.parent

RUN_AND_LIST = (
    "import json, sys\n"
    "from rtc.cli import main\n"
    "try:\n"
    "    status = main(sys.argv[1:])\n"
    "except SystemExit as done:\n"
    "    status = done.code\n"
    "records = sorted(\n"
    "    f'{name}.{value.__name__}' for name, module in list(sys.modules.items())\n"
    "    for value in list(vars(module).values()) if isinstance(value, type)\n"
    "    and value.__module__ == name and '__dataclass_fields__' in vars(value))\n"
    "print('\\n' + json.dumps({'status': status, 'modules': sorted(sys.modules),\n"
    "                          'dataclasses': records}))\n"
)

# What no render imports: the bench and everything of it (its report and templates, plots,
# rooms, instruments, the meshes it generates: a scene naming one imports their maker then),
# Pillow (PNGs are written by groundwork.images), the YAML writers' users, psutil (read from
# /proc where there is one), importlib.metadata's scan of every installed package (the
# project's own variants are a table), numpy.ma (np.unique's)
NEVER_ON_THE_RENDER_PATH = (
    "jinja2", "markupsafe", "matplotlib", "importlib.metadata", "numpy.ma", "harness", "PIL",
    "logging", "rtc.demos", "rtc.scaffold", "pyperf", "distributed", "dask", "tqdm",
    *(("psutil",) if Path("/proc/meminfo").exists() else ()),
    # temporary files are made by groundwork.files (tempfile brings random, shutil's
    # archivers); the fir branch's drawing (random) only for a scene that adds one
    "tempfile", "random", "scene.fir_branch",
    # an OBJ model's reader and the image textures' decoder: only for a scene that names one
    "scene.obj_mesh", "scene.images",
    # the kernel cache's digests are the interpreter's own SHA-256 (hashlib loads OpenSSL's)
    "hashlib", "_hashlib",
    # shutil brings its archivers (bz2, lzma): argparse's formatter would import it for the
    # terminal's width (rtc.cli gives it one), the kernels' module writer to remove a folder
    "shutil", "bz2", "lzma",
)  # fmt: skip
# The dataclasses a render defines, at most: each compiles its methods from source at every
# start (about half a millisecond of a render's command each, a quarter of its imports' CPU
# when this was written); tables and records that nothing mutates or replaces are
# NamedTuples (scene.kinds, scene.pattern_kinds, scene.limits, scene.reader's Entry, the
# registry's entries and specs, the numba variant's options and feature sets, a compiled
# library's loaded function). A new one
# on the render path needs a reason, and this figure raised with it.
RENDER_DATACLASSES = {"naive": 45, "numba": 57}
# What only building a compiled library needs (running the C compiler): a render that loads
# one already built imports none of it
ONLY_TO_BUILD_A_LIBRARY = ("subprocess", "shlex")

SCENE = """\
- add: camera
  width: 16
  height: 12
  field-of-view: 1.0
  from: [0, 1.5, -5]
  to: [0, 1, 0]
  up: [0, 1, 0]
- add: light
  at: [-10, 10, -10]
  intensity: [1, 1, 1]
- add: plane
  material:
    pattern:
      type: checkers
      colors: [[1, 1, 1], [0, 0, 0]]
- add: sphere
  transform: [[translate, 0, 1, 0]]
  material:
    color: [1, 0.2, 0.2]
    reflective: 0.3
"""


def run_listing(*argv: str, cwd: Path = ROOT) -> tuple[int, set[str], str]:
    """``rtc ARGV`` in a fresh interpreter: its exit status, the modules it had imported
    when it ended, and its stderr."""
    status, modules, _, err = run_listing_records(*argv, cwd=cwd)
    return status, modules, err


def run_listing_records(*argv: str, cwd: Path = ROOT) -> tuple[int, set[str], list[str], str]:
    """``run_listing``'s answers and the dataclasses the command's modules define."""
    done = subprocess.run(
        [sys.executable, "-c", RUN_AND_LIST, *argv], cwd=cwd, capture_output=True, text=True,
        env={**os.environ, "PYTHONPATH": str(ROOT)},
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout.rstrip().rpartition("\n")[2])
    return report["status"], set(report["modules"]), report["dataclasses"], done.stderr


def imported(modules: set[str], package: str) -> list[str]:
    return sorted(m for m in modules if m == package or m.startswith(f"{package}."))


def test_rtc_help_imports_no_command_module_and_no_numpy() -> None:
    status, modules, _ = run_listing("--help")
    assert status == 0
    assert imported(modules, "rtc") == ["rtc", "rtc.cli"]
    for package in ("numpy", "yaml", "PIL", "scene", "variants", "harness", "raytracer"):
        assert not imported(modules, package), package


def test_rtc_help_lists_every_command_from_the_table(
    capsys: pytest.CaptureFixture[str],
) -> None:
    from rtc.cli import main

    with pytest.raises(SystemExit):
        main(["--help"])
    out = capsys.readouterr().out
    for module, help_line in COMMANDS.items():
        assert module.removeprefix("rtc.cmd_") in out
        assert help_line.split()[0] in out


@pytest.mark.parametrize("variant", ["naive", "numba"])
def test_rtc_render_imports_only_what_the_scene_needs(tmp_path: Path, variant: str) -> None:
    scene = tmp_path / "small.yml"
    scene.write_text(SCENE, encoding="utf-8")
    out = tmp_path / "small.png"
    argv = ("render", str(scene), "--variant", variant, "--progress", "none")
    status, modules, records, err = run_listing_records(*argv, "-o", str(out))
    assert status == 0, err
    assert out.stat().st_size > 0
    if "compiling" in err:  # this kernel's first render built its library: render again
        status, modules, records, err = run_listing_records(
            *argv, "-o", str(tmp_path / "again.png")
        )
        assert status == 0, err
        assert "compiling" not in err
    assert len(records) <= RENDER_DATACLASSES[variant], (
        f"rtc render --variant {variant} defines {len(records)} dataclasses, more than "
        f"{RENDER_DATACLASSES[variant]} (see RENDER_DATACLASSES): {records}"
    )
    # (numba imported: no C compiler here, the kernel came from numba's cache, which may)
    built = [name for name in ONLY_TO_BUILD_A_LIBRARY if name in modules and "numba" not in modules]
    assert not built, f"imported by rtc render --variant {variant} loading its kernel: {built}"
    assert imported(modules, "rtc") == ["rtc", "rtc.cli", "rtc.cmd_render"]
    crept_in = [name for name in NEVER_ON_THE_RENDER_PATH if imported(modules, name)]
    assert not crept_in, f"imported by rtc render --variant {variant}: {crept_in}"
    others = [m for m in modules if m.startswith("variants.")]  # only the one named
    assert not [m for m in others if m.split(".")[1] in ("wavefront", "pooled", "dask_cluster")]


def test_rtc_render_still_writes_a_generated_mesh_a_scene_names(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The meshes' maker is imported only when a scene names one (``cmd_render._provide``),
    and then it writes the mesh as before."""
    from harness.scenery import make_meshes
    from rtc import cmd_render

    monkeypatch.setattr(make_meshes, "GENERATED", tmp_path / "meshes")  # the project's, here
    assert cmd_render._provide(tmp_path / "meshes" / "ring-1k.obj")
    assert (tmp_path / "meshes" / "ring-1k.obj").stat().st_size > 0
    assert not cmd_render._provide(tmp_path / "elsewhere" / "ring-1k.obj")
    assert not cmd_render._provide(tmp_path / "meshes" / "not-generated.obj")


def test_the_command_collects_again_once_its_modules_are_loaded(tmp_path: Path) -> None:
    """``rtc`` as the process (``main()`` reading ``sys.argv``) loads its modules with the
    cyclic collector off, then freezes them out of its reach and turns it back on for the
    work; a caller passing its own arguments (a test) keeps the collector as it was."""
    scene = tmp_path / "small.yml"
    scene.write_text(SCENE, encoding="utf-8")
    probe = (
        "import atexit, gc, sys\n"
        "from rtc.cli import main\n"
        "collector, caller, *argv = sys.argv[1:]\n"
        "if collector == 'off':\n"
        "    gc.disable()\n"
        "if caller == 'process':\n"
        "    sys.argv = ['rtc', *argv]\n"
        "atexit.register(lambda: print(gc.isenabled(), gc.get_freeze_count() > 0))\n"
        "sys.exit(main() if caller == 'process' else main(argv))\n"
    )
    argv = ["render", str(scene), "-o", str(tmp_path / "x.ppm"), "--progress", "none"]
    answers = {}
    for collector, caller in (("on", "process"), ("off", "argv"), ("on", "argv")):
        done = subprocess.run(
            [sys.executable, "-c", probe, collector, caller, *argv],
            cwd=ROOT, capture_output=True, text=True, env={**os.environ, "PYTHONPATH": str(ROOT)},
        )  # fmt: skip
        assert done.returncode == 0, done.stderr
        answers[collector, caller] = done.stdout.splitlines()[-1]
    assert answers["on", "process"] == "True True"
    assert answers["off", "argv"] == "False False"
    assert answers["on", "argv"] == "True False"


@pytest.mark.parametrize("caller", ["process", "argv"])
def test_rtc_render_as_the_process_ends_without_the_teardown(tmp_path: Path, caller: str) -> None:
    """``rtc render`` as the process ends once its output is flushed and its exit functions
    have run, without the interpreter's teardown (``cli._exit_at_once``): every line it
    printed and every exit function's is there, and its status is the command's, but
    ``main`` never returned. A caller passing its own arguments (a test) gets ``main``'s
    status back; a command that fails returns its status too."""
    scene = tmp_path / "small.yml"
    scene.write_text(SCENE, encoding="utf-8")
    probe = (
        "import atexit, sys\n"
        "from rtc.cli import main\n"
        "caller, *argv = sys.argv[1:]\n"
        "atexit.register(print, 'exit functions ran')\n"
        "if caller == 'process':\n"
        "    sys.argv = ['rtc', *argv]\n"
        "status = main() if caller == 'process' else main(argv)\n"
        "print('main returned', status)\n"
    )
    outputs = {}
    for name in ("x.png", "missing/x.png"):  # a render, and one that fails (exit status 2)
        argv = ["render", str(scene), "-o", str(tmp_path / name), "--progress", "none"]
        outputs[name] = subprocess.run(
            [sys.executable, "-c", probe, caller, *argv],
            cwd=ROOT, capture_output=True, text=True, env={**os.environ, "PYTHONPATH": str(ROOT)},
        )  # fmt: skip
    done, failed = outputs["x.png"], outputs["missing/x.png"]
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "x.png").stat().st_size > 0
    lines = done.stdout.splitlines()
    assert lines[0].startswith("rendering ") and lines[1].startswith("rendered in ")
    if caller == "process":
        assert lines[2:] == ["exit functions ran"]
    else:
        assert lines[2:] == ["main returned 0", "exit functions ran"]
    # a command that fails ends as usual, its one line said
    assert "rtc render: cannot write" in failed.stderr and "Traceback" not in failed.stderr
    assert failed.returncode == 0, failed.stderr  # the probe's own exit, main having returned
    assert failed.stdout.splitlines()[-2:] == ["main returned 2", "exit functions ran"]


def test_the_command_starts_numpys_blas_on_one_thread(tmp_path: Path) -> None:
    """``rtc`` as the process sets ``OPENBLAS_NUM_THREADS=1`` before numpy is imported
    (``cli.BLAS_THREADS``): at its exit it runs no thread it did not start itself (where
    ``/proc`` lists them); a value the user set is kept."""
    scene = tmp_path / "small.yml"
    scene.write_text(SCENE, encoding="utf-8")
    probe = (
        "import atexit, os, sys\n"
        "from rtc.cli import main\n"
        "tasks = '/proc/self/task'\n"
        "atexit.register(lambda: print(os.environ.get('OPENBLAS_NUM_THREADS'),\n"
        "    len(os.listdir(tasks)) if os.path.isdir(tasks) else 1))\n"
        "sys.argv = ['rtc', *sys.argv[1:]]\n"
        "sys.exit(main())\n"
    )
    argv = ["render", str(scene), "-o", str(tmp_path / "x.png"), "--progress", "none"]
    answers = []
    for given in (None, "2"):
        env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
        if given is not None:
            env["OPENBLAS_NUM_THREADS"] = given
        done = subprocess.run(
            [sys.executable, "-c", probe, *argv], cwd=ROOT, capture_output=True, text=True,
            env={**env, "PYTHONPATH": str(ROOT)},
        )  # fmt: skip
        assert done.returncode == 0, done.stderr
        answers.append(done.stdout.splitlines()[-1])
    assert answers[0] == "1 1"
    assert answers[1].split()[0] == "2"


def _tree(node: Any) -> Any:
    """A YAML node as plain values: kind, tag, where it starts and ends, style, children."""
    base = (type(node).__name__, node.tag, node.start_mark.line, node.start_mark.column,
            node.end_mark.line, node.end_mark.column)  # fmt: skip
    if isinstance(node, ScalarNode):
        return (*base, node.value, node.style)
    if isinstance(node, SequenceNode):
        return (*base, node.flow_style, [_tree(child) for child in node.value])
    return (*base, node.flow_style, [(_tree(k), _tree(v)) for k, v in node.value])


@pytest.mark.parametrize("path", sorted((ROOT / "scenes").glob("*.yml")), ids=lambda p: p.name)
def test_a_scene_read_by_libyaml_composes_as_pyyaml_reads_it(path: Path) -> None:
    """A scene's YAML events come from libyaml (five times faster than PyYAML's scanner in
    Python): the same nodes, lines, styles and shape count as PyYAML's own reading."""
    from scene.composer import CParser, LibyamlLimitedLoader, LimitedLoader
    from scene.limits import Limits

    assert CParser is not None  # PyYAML's wheels carry libyaml
    text = path.read_text(encoding="utf-8")
    read = []
    for loader_class in (LimitedLoader, LibyamlLimitedLoader):
        loader = loader_class(text, path, Limits())
        try:
            read.append((_tree(loader.get_single_node()), loader.shapes))
        finally:
            loader.dispose()
    assert read[0] == read[1]
    assert read[0][1] > 0


def test_rtc_render_builds_the_parser_of_render_alone() -> None:
    """A chosen command's parser is the only one made (the others' would be shown only by
    ``rtc --help``, which makes them all from their help lines)."""
    from rtc.cli import build_parser

    commands = [a for a in build_parser(["render"])._actions if a.dest == "command"]
    assert list(commands[0].choices) == ["render"]
    everything = [a for a in build_parser([])._actions if a.dest == "command"]
    assert list(everything[0].choices) == [m.removeprefix("rtc.cmd_") for m in COMMANDS]


def test_a_new_file_is_made_by_its_call_alone(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``groundwork.files.new_file`` (the render path's temporary files, without tempfile):
    a private file under a fresh name; a name already there is never opened again."""
    from groundwork import files

    fd, name = files.new_file(tmp_path, ".out.png.", ".tmp")
    os.close(fd)
    path = Path(name)
    assert path.parent == tmp_path and path.name.startswith(".out.png.")
    assert path.name.endswith(".tmp") and (path.stat().st_mode & 0o777) == 0o600
    monkeypatch.setattr(files.os, "urandom", lambda size: bytes(size))  # every name the same
    fd, taken = files.new_file(tmp_path, "x-")
    os.close(fd)
    with pytest.raises(FileExistsError):
        files.new_file(tmp_path, "x-")
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([path.name, Path(taken).name])
    files.check_can_write(tmp_path, ".check-")
    assert len(list(tmp_path.iterdir())) == 2  # the check leaves nothing behind


@pytest.mark.parametrize("own_inverse", [False, True])
def test_a_load_inverts_each_shapes_transform_once(own_inverse: bool) -> None:
    """The loader's check of a shape's transform keeps the inverse it computed
    (``Scene.inverses``) and the packer's flattening takes that very matrix instead of
    inverting again; only when the API's ``inverse`` is the reference's, the one the
    packer uses (a variant's own ``inverse`` is never taken for it)."""
    from raytracer.api import naive_api
    from raytracer.matrices import inverse
    from scene import load_scene
    from variants.arrays import flatten

    api = dict(naive_api())
    if own_inverse:
        api["inverse"] = lambda m: inverse(m)  # the same numbers, another function
    scene = load_scene(ROOT / "scenes" / "reference.yml", api)
    kept = {id(inverted) for _, inverted in scene.inverses.values()}
    leaves = [node for node in flatten.from_description(scene) if isinstance(node, flatten.Leaf)]
    transformed = [leaf for leaf in leaves if not flatten.is_identity(leaf.inv)]
    reused = [leaf for leaf in transformed if id(leaf.inv) in kept]
    assert len(scene.inverses) >= len(transformed) > 3
    assert len(reused) == (0 if own_inverse else len(transformed))
