"""The README and docs/ cannot drift from what they describe: the README's figures are those
``rtc report`` writes from the committed runs, its variant table is the registry's, every
link leads to a file of the clone, and the reference pages name every kind, key, section
and case group the code has. No page names anything a clone does not have."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

from harness.report import readme_figures
from harness.report.build import load_history
from harness.sections import SECTIONS
from harness.stability.suite import CASES
from rtc.cmd_stability import GROUPS
from rtc.cmd_variants import markdown_table
from scene import loader
from scene.kinds import ADDABLE
from scene.materials import MATERIAL_KEYS, NUMBER_PROPERTIES, PATTERNS
from scene.path_items import RENDER_KEYS, SKY_KEYS
from scene.shapes import KEYS, SCENE_ITEMS, STRUCTURES
from scene.textures import MAPPINGS, UV_KEYS
from scene.transforms import TRANSFORMS

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
DOCS = sorted((ROOT / "docs").glob("*.md"))
MAX_README_LINES = 200


def _text(path: Path) -> str:
    return path.read_text(encoding="utf-8")


def test_the_readme_is_a_page_not_a_diary() -> None:
    lines = _text(README).splitlines()
    assert len(lines) <= MAX_README_LINES, f"README.md has {len(lines)} lines"
    first_screen = "\n".join(lines[:60])
    assert "rtc render" in first_screen, "the first screen shows how to render"


def test_the_readmes_figures_are_the_committed_runs() -> None:
    runs, _ = load_history(ROOT / "results")
    quoted = readme_figures.quoted(_text(README))
    assert quoted is not None, "README.md lost its figures' markers"
    assert quoted == readme_figures.block(runs), "run `rtc report` to rewrite them"


def test_rewriting_the_figures_keeps_the_rest_and_is_idempotent(tmp_path: Path) -> None:
    page = tmp_path / "README.md"
    page.write_text(
        f"intro\n{readme_figures.START}\nold figures\n{readme_figures.END}\nrest\n",
        encoding="utf-8",
    )
    runs, _ = load_history(ROOT / "results")
    assert readme_figures.rewrite(page, runs)
    text = _text(page)
    assert text.startswith("intro\n") and text.endswith(f"{readme_figures.END}\nrest\n")
    assert readme_figures.quoted(text) == readme_figures.block(runs)
    assert not readme_figures.rewrite(page, runs)  # unchanged: not written again
    (tmp_path / "plain.md").write_text("no markers\n", encoding="utf-8")
    assert not readme_figures.rewrite(tmp_path / "plain.md", runs)


def test_the_readmes_variant_table_is_the_registrys() -> None:
    text = _text(README)
    found = re.search(r"<!-- variants: [^>]*-->\n(.*?)\n<!-- end of variants -->", text, re.S)
    assert found is not None, "README.md lost its variant table's markers"
    assert found.group(1) == markdown_table(), "paste `rtc variants --markdown` into README.md"


@pytest.mark.parametrize("page", [README, *DOCS], ids=lambda p: p.name)
def test_every_relative_link_leads_to_a_file_of_the_clone(page: Path) -> None:
    for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", _text(page)):
        if "://" in target:
            continue
        assert (page.parent / target).exists(), f"{page.name} links to missing {target}"


def test_no_tracked_file_names_what_a_clone_lacks() -> None:
    """No machine path, no tool of the workplace the project was written in, no file from
    outside the repository."""
    listed = subprocess.run(
        ["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=False
    )
    if listed.returncode != 0:
        pytest.fail(f"git ls-files failed: {listed.stderr.strip()}")
    # each word with one letter in brackets, so that this file does not name them itself
    forbidden = re.compile(
        r"/wor[k]/|/roo[t]/|/hom[e]/\w|far[m]-bench|far[m]-studio|DESIG[N]\.md|\.\./share[d]"
    )
    for name in listed.stdout.splitlines():
        path = ROOT / name
        if path.suffix not in {".py", ".md", ".yml", ".toml", ".cfg", ".txt", ".sh", ""}:
            continue
        if not path.is_file() or name.startswith("results/runs/"):
            continue
        text = path.read_text(encoding="utf-8", errors="replace")
        found = forbidden.search(text)
        assert found is None, f"{name} names {found.group(0)!r}" if found else ""


def test_the_scene_format_page_names_every_item_shape_and_key() -> None:
    text = re.sub(r"```.*?```", "", _text(ROOT / "docs" / "scene-format.md"), flags=re.S)
    words = set(re.findall(r"`([^`]+)`", text)) | {"add"}  # `- add: ...`
    mentioned = " ".join(words)
    for item in SCENE_ITEMS:
        assert item in words, item
    for keys in (
        loader.CAMERA_KEYS,
        loader.LIGHT_KEYS,
        loader.AREA_LIGHT_KEYS,
        SKY_KEYS,
        RENDER_KEYS,
    ):
        for key in keys:
            assert key in words, key
    for kind in [*(k.name for k in ADDABLE), *STRUCTURES]:
        assert kind in mentioned, kind
        for key in KEYS[kind]:
            assert key in words, f"{kind}: {key}"
    for name in [*TRANSFORMS, *NUMBER_PROPERTIES, *MATERIAL_KEYS, *PATTERNS, *MAPPINGS, *UV_KEYS]:
        assert name in mentioned, name


def test_the_measuring_page_names_every_section() -> None:
    text = _text(ROOT / "docs" / "measuring.md")
    listed = text[text.index("The bench is made of sections") : text.index("`rtc bench --help`")]
    named = set(re.findall(r"\*\*([a-z-]+)\*\*", listed))
    assert named == {s.name for s in SECTIONS}


def test_the_stability_groups_are_the_suites() -> None:
    groups = tuple(dict.fromkeys(case.group for case in CASES))
    assert groups == GROUPS  # rtc stability --help
    table = re.findall(r"^\| `([a-z]+)` \|", _text(ROOT / "docs" / "stability.md"), re.M)
    assert tuple(table) == groups
