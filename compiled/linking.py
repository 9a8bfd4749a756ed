"""Linking a compiled ``cfunc`` into a shared library with the system C compiler."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from compiled.entry import UNREACHABLE
from compiled.records import publish


class BuildError(RuntimeError):
    """A shared library could not be built (no C compiler, a link error ...)."""


def compiler() -> list[str]:
    """The C compiler: ``$CC``, else ``cc`` or ``gcc``; a ``BuildError`` when none."""
    # deferred, as in link: only a build needs them, not a render loading a library
    import shlex
    import shutil

    found = (
        shlex.split(os.environ.get("CC", ""))
        or [found for found in (shutil.which("cc"), shutil.which("gcc")) if found][:1]
    )
    if not found:
        raise BuildError("no C compiler (cc, gcc or $CC) found")
    return found


# numba's code library steps ``_final_module`` takes in numba's order (0.60 and later)
_LINKING_STEPS = (
    "_linking_libraries", "_get_module_for_linking", "_optimize_final_module", "_finalized",
)


class ForLinking:
    """``function`` compiled by numba as a C function over ``signature`` (as numba's ``cfunc``
    compiles it, with ``options``), for ``link`` alone: numba types, lowers and optimizes it,
    but never makes its machine code for its own JIT (``cfunc`` does, and ``link`` then made
    it a second time, position independent: 8-10 s of a big kernel's build)."""

    def __init__(self, function: Any, signature: Any, **options: Any) -> None:
        # deferred: only a build imports numba's compiler here
        from numba.core import sigutils
        from numba.core.ccallback import CFunc
        from numba.core.compiler_lock import global_compiler_lock

        compiled: Any = CFunc(function, sigutils.normalize_signature(signature), {}, options)
        if not hasattr(compiled, "_compile_uncached"):  # another numba: its JIT's code too
            compiled.compile()
            self._library, self.native_name = compiled._library, compiled.native_name
            return
        with global_compiler_lock:
            result = compiled._compile_uncached()  # not ``compile``: that finalizes for the JIT
            if not all(hasattr(result.library, name) for name in _LINKING_STEPS):
                result.library.finalize()  # another numba: ``_final_module`` as ``cfunc``'s
        self._library = result.library
        self.native_name = result.fndesc.llvm_cfunc_wrapper_name


def link(entry: Any, stub: str, path: Path, what: str) -> None:
    """Link a compiled ``cfunc`` ``entry`` (or a ``ForLinking``) with the C ``stub`` (which
    calls it as ``ENTRY_SYMBOL``) into the shared library ``path``; ``what`` names it in
    errors."""
    # deferred: 5-13 ms of every render's imports, and only a build runs the C compiler
    import subprocess
    import tempfile

    command_start = compiler()
    try:
        obj, helpers = _object_code(entry)
    except Exception as error:  # numba's internals moved: fall back to numba's own cache
        raise BuildError(f"cannot take the compiled {what} out of numba: {error!r}") from None
    runtime = [name for name in helpers if not name.startswith("numba_")]
    if runtime:
        raise BuildError(f"the compiled {what} calls numba's runtime ({', '.join(runtime)})")
    source = (
        stub.replace("ENTRY_SYMBOL", entry.native_name)
        + UNREACHABLE
        + "".join(f'void {name}(void) {{ unreachable("{name}"); }}\n' for name in helpers)
    )
    with tempfile.TemporaryDirectory(prefix="rtc-numba-link-", dir=path.parent) as folder:
        work = Path(folder)
        (work / "kernel.o").write_bytes(obj)
        (work / "entry.c").write_text(source, encoding="utf-8")
        built = work / path.name
        command = [  # names relative to the work folder: each build gives the same bytes
            *command_start, "-shared", "-fPIC", "-O2", "-o", built.name, "entry.c", "kernel.o",
            "-lm",
        ]  # fmt: skip
        try:
            done = subprocess.run(
                command, capture_output=True, text=True, timeout=300, cwd=work
            )
        except (OSError, subprocess.SubprocessError) as error:
            raise BuildError(f"{command_start[0]} failed to run: {error}") from None
        if done.returncode != 0 or not built.is_file():
            problem = done.stderr.strip()[:500] or f"exit status {done.returncode}"
            raise BuildError(f"{command_start[0]} could not link the {what}: {problem}")
        publish(built, path)


def _object_code(entry: Any) -> tuple[bytes, list[str]]:
    """The position-independent machine code of a compiled ``cfunc`` (numba's optimized,
    linked LLVM module, for this CPU), and the numba runtime functions it declares."""
    # deferred: saves ~80 ms (llvmlite) of every process that builds no library
    import llvmlite.binding as llvm

    module = _final_module(entry._library)
    target = llvm.Target.from_triple(llvm.get_process_triple())
    machine = target.create_target_machine(
        cpu=llvm.get_host_cpu_name(),
        features=llvm.get_host_cpu_features().flatten(),
        opt=3,
        reloc="pic",
        codemodel="default",
    )
    helpers = sorted(
        f.name
        for f in module.functions
        if f.is_declaration and f.name.startswith(("numba_", "NRT_"))
    )
    return machine.emit_object(module), helpers


def _final_module(library: Any) -> Any:
    """numba's final LLVM module of ``library``: its callees linked in and the whole
    optimized, as numba's ``finalize`` makes it, without handing it to numba's JIT (a
    ``ForLinking`` entry's library is not finalized; a ``cfunc``'s is)."""
    if library._finalized:
        return library._final_module
    from numba.core.compiler_lock import global_compiler_lock

    with global_compiler_lock:
        for linked in dict.fromkeys(library._linking_libraries):  # once each, in order
            library._final_module.link_in(linked._get_module_for_linking(), preserve=True)
        library._optimize_final_module()
        library._final_module.verify()
        library._finalized = True  # nothing may be added to it now
    return library._final_module
