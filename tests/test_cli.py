"""The command line's dispatch: every command module is named after its command."""

from __future__ import annotations

import importlib
import subprocess
import sys

import pytest

from rtc.cli import COMMANDS, build_parser, main


@pytest.mark.parametrize("module_name", COMMANDS)
def test_each_command_module_is_named_after_its_command(module_name: str) -> None:
    module = importlib.import_module(module_name)
    assert module_name == f"rtc.cmd_{module.NAME}"


def test_the_full_parser_lists_every_command() -> None:
    help_text = build_parser([]).format_help()
    for module_name in COMMANDS:
        assert module_name.removeprefix("rtc.cmd_") in help_text


def test_a_command_imports_only_its_own_module() -> None:
    code = (
        "import sys; from rtc.cli import main; main(['variants']); "
        "print(sorted(m for m in sys.modules if m.startswith('rtc.cmd_')))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout
    assert out.strip().splitlines()[-1] == "['rtc.cmd_variants']"


def test_an_unknown_command_is_a_usage_error(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exit_info:
        main(["frobnicate"])
    assert exit_info.value.code == 2
    assert "invalid choice: 'frobnicate'" in capsys.readouterr().err


def test_rtc_variants_lists_the_tracer_steps_each_overrides(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert main(["variants"]) == 0
    out = capsys.readouterr().out
    assert "tracer steps: none, the reference Tracer" in out  # naive, cached
    assert (
        "tracer steps: lighting, prepare_computations, is_shadowed, refracted_color, schlick" in out
    )
