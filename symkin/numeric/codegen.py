"""C code generation for the evaluators: generate, compile, load, cache by model hash.

One entry point, :func:`compile_evaluators` (``ev.compile()``), and it is only a
speed-up: the generated functions give the numbers of the in-process CasADi Functions
(bit for bit with the default flags; the tests check it).

* C sources come from CasADi's ``CodeGenerator``; a header documents every function's
  arguments and results, their order, shapes and storage (:func:`header_notes`).  The
  bodies of ``indicators`` and of its loop ``indicators_batch`` are then replaced by the
  same instructions on vectors of configurations (:mod:`symkin.numeric.simd`: 2 per
  instruction with the default flags, 4 with AVX, 8 with AVX-512, e.g. :data:`NATIVE_FLAGS`),
  bit for bit the scalar results; the kernel is compiled once.
* The library is built with the system C compiler (``compiler`` argument, else the
  ``SYMKIN_CC`` or ``CC`` environment variable, else ``cc``) and loaded with
  ``casadi.external``.
* Artefacts are cached on disk under ``SYMKIN_CACHE`` (default ``~/.cache/symkin``), in a
  file named after the model's content hash, the CasADi version and a hash of the
  generating sources, compiler and flags (:func:`artefact_stem`), so a model is compiled
  once per machine; loaded libraries are also kept for the process.  Every generated
  artefact of symkin (these evaluators, the path corrector of
  :mod:`symkin.paths.generated`) goes through the one cache entry point
  :func:`cached_library`.
* Writes are atomic: sources, manifest and library are built in a temporary directory
  inside the cache and moved into place with ``os.replace``, the library last; builders of
  the same artefact are serialised by a lock file (``fcntl.flock`` where available), so
  concurrent processes (Dask workers) never load a half-written library.
* Every library is recorded when written: its size and SHA-256 go to a sidecar
  ``stem.so.sha256`` (JSON, written atomically before the library is moved into place),
  and a library is verified against it before it is loaded.  A truncated, zero-filled or
  foreign file (which the dynamic loader could map and then crash on with SIGBUS or
  SIGSEGV) is rebuilt with a one-line :class:`CodegenWarning` instead of loaded.
* Build folders (``.build-*``) left by a killed compile are removed on the next compile
  once they are older than an hour (:data:`STALE_BUILD_SECONDS`).  :func:`cache_size` and
  :func:`clear_cache` back the ``symkin cache`` command.
* With no working compiler, a :class:`CodegenWarning` says so and the in-process
  Functions stay in use.
"""
from __future__ import annotations

import hashlib
import json
import os
import shutil
import subprocess
import tempfile
import warnings
from contextlib import contextmanager
from pathlib import Path
from typing import Callable, Iterable

import casadi as ca

from symkin.errors import SymkinError
from symkin.numeric import simd

__all__ = ["CodegenWarning", "CompilerError", "DEFAULT_FLAGS", "cache_directory", "artefact_stem",
           "artefact_key", "cached_library", "write_atomic",
           "generate_sources", "build_library", "load_library", "compile_evaluators", "header_notes",
           "find_compiler", "GENERATED_FUNCTIONS", "manifest", "NATIVE_FLAGS", "record_artefact",
           "verify_artefact", "cache_size", "clear_cache", "clean_stale_builds", "STALE_BUILD_SECONDS"]

#: flags for the system compiler; ``-ffp-contract=off`` keeps the arithmetic of the
#: in-process CasADi virtual machine (no fused multiply-add), so results are identical;
#: ``-fno-math-errno`` lets ``sqrt`` compile to one instruction (same value)
DEFAULT_FLAGS = ("-O3", "-fno-math-errno", "-fPIC", "-shared", "-ffp-contract=off")
#: the default flags for this machine's processor (``-march=native``): wider vectors in the
#: batch loop (AVX: 4 configurations per instruction, AVX-512: 8), the same numbers.  The
#: library then runs only on processors like this one, so the cache key also holds the
#: processor's description (:func:`_target_fingerprint`)
NATIVE_FLAGS = DEFAULT_FLAGS + ("-march=native",)
#: modules whose source decides what is generated: their text is part of the cache key,
#: so a changed symkin never loads a stale library
_SOURCES = ("casadi_model", "evaluators", "sx_linalg", "codegen", "geometric_matrix", "linalg", "simd")
#: Functions written to the C file, in this order
GENERATED_FUNCTIONS = ("G", "J", "closure", "closure_jacobian", "parameters", "indicators",
                       "indicators_batch", "motion")
_LOADED: dict[str, dict[str, ca.Function]] = {}
#: a ``.build-*`` folder older than this (seconds) belongs to a killed compile and is removed
STALE_BUILD_SECONDS = 3600.0

_DESCRIPTIONS = {
    "q": "free nodal coordinates (free nodes in node order, x, y[, z] each)",
    "p": "closure parameters (lengths, slider offsets, affine coordinates; model values by default)",
    "G": "reduced geometric matrix over the free coordinates (eq. 8)",
    "G_full": "geometric matrix over all coordinates (eq. 3, A5)",
    "J": "constraint rows over all coordinates (G = J^T J)",
    "J_free": "constraint rows over the free coordinates",
    "phi": "closure residual, one entry per row of J",
    "dphi_dq": "Jacobian of phi with respect to q (= J_free where phi = 0)",
    "inputs": "input parameter rows over all coordinates (physical units)",
    "outputs": "output parameter rows over all coordinates (physical units)",
    "platform": "platform twist rows over all coordinates (physical units)",
    "im": "IM indicator lambda_{F+1} of the reduced G",
    "im_certified": "1 when Sturm counts certify im to 1e-12 relative, else 0",
    "trace": "trace of J_e J_e^T (squared Frobenius norm of J_free)",
    "dkp_input": "det([J_S; unit input rows]) / sqrt(det(J_S J_S^T)) when k = F (signed), "
                 "else the product of the singular values of the restricted input rows",
    "dkp_input_bound": "lower bound on the smallest squared singular value of the restricted input rows",
    "dkp_output": "det([J_S; unit output rows]) / sqrt(det(J_S J_S^T)) when k = F (signed), "
                  "else the product of the singular values of the restricted output rows",
    "dkp_output_bound": "lower bound on the smallest squared singular value of the restricted output rows",
    "V": "orthonormal basis of the motion space (columns), valid when L = F",
}


class CodegenWarning(UserWarning):
    """Code generation could not compile; the in-process CasADi Functions are used."""


class CompilerError(SymkinError):
    """The C compiler is missing or failed; ``stderr`` holds its message."""

    def __init__(self, message: str, stderr: str = ""):
        self.stderr = stderr
        super().__init__(message)


# ---------------------------------------------------------------------- names and paths
def cache_directory(cache_dir=None) -> Path:
    """The artefact cache: ``cache_dir``, else ``$SYMKIN_CACHE``, else ``~/.cache/symkin``."""
    if cache_dir is not None:
        return Path(cache_dir)
    env = os.environ.get("SYMKIN_CACHE")
    return Path(env) if env else Path.home() / ".cache" / "symkin"


def find_compiler(compiler: str | None = None) -> str:
    """The compiler command: ``compiler``, else ``$SYMKIN_CC``, ``$CC``, ``cc``."""
    return compiler or os.environ.get("SYMKIN_CC") or os.environ.get("CC") or "cc"


def _generator_fingerprint(sources: Iterable = ()) -> str:
    """Hash of the text of the modules that decide what is generated (and of ``sources``)."""
    here = Path(__file__).resolve().parent
    digest = hashlib.sha256()
    for name in _SOURCES:
        digest.update((here / f"{name}.py").read_bytes())
    for path in sources:
        digest.update(Path(path).read_bytes())
    return digest.hexdigest()


def _target_fingerprint(flags) -> str:
    """The processor's description when ``flags`` target it (``-march=native``), else ``""``.

    On Linux the model name and feature flags of ``/proc/cpuinfo``, elsewhere
    ``platform.processor()``: a library built for one processor is not loaded on another
    that shares the cache directory.
    """
    if not any(f.endswith("=native") for f in flags):
        return ""
    import platform
    try:
        info = Path("/proc/cpuinfo").read_text().splitlines()
        keep = sorted({ln for ln in info if ln.split(":")[0].strip() in ("model name", "flags", "Features")})
        text = "\n".join(keep)
    except OSError:
        text = ""
    return hashlib.sha256(f"{platform.machine()}|{platform.processor()}|{text}".encode()).hexdigest()[:16]


def artefact_key(parts: Iterable[str], compiler: str, flags, sources: Iterable = ()) -> str:
    """Cache key of a generated artefact: what it is (``parts``), CasADi version, sources, compiler, flags.

    ``sources`` are extra files whose text decides what is generated (e.g. the module that
    builds a Function outside :mod:`symkin.numeric`); the numeric modules are always in.
    """
    text = "|".join([*parts, ca.__version__, _generator_fingerprint(sources), compiler, " ".join(flags),
                     _target_fingerprint(flags)])
    return hashlib.sha256(text.encode()).hexdigest()[:24]


def artefact_stem(mech, compiler: str, flags) -> str:
    """File stem of a model's artefacts: content hash, CasADi version, build options.

    The last part also hashes the source of the modules that decide what is generated.
    """
    options = hashlib.sha256(f"{_generator_fingerprint()}|{compiler}|{' '.join(flags)}|"
                             f"{_target_fingerprint(flags)}".encode())
    return (f"symkin_{mech.content_hash()[:20]}_casadi{ca.__version__.replace('.', '_')}_"
            f"{options.hexdigest()[:8]}")


# ---------------------------------------------------------------------- documentation
def _shape(f: ca.Function, i: int, out: bool) -> str:
    r, c = f.size_out(i) if out else f.size_in(i)
    return f"{r}x{c}"


def manifest(ev) -> dict:
    """What the generated code computes: argument names, order, shapes and labels (JSON-ready)."""
    funcs = {}
    for name in GENERATED_FUNCTIONS:
        if name not in ev._symbolic:
            continue
        f = ev._symbolic[name]
        each = " (one column per configuration)" if name.endswith("_batch") else ""
        funcs[name] = {
            "inputs": [{"name": f.name_in(i), "shape": list(f.size_in(i)),
                        "meaning": _DESCRIPTIONS.get(f.name_in(i), "") + each} for i in range(f.n_in())],
            "outputs": [{"name": f.name_out(i), "shape": list(f.size_out(i)),
                         "meaning": _DESCRIPTIONS.get(f.name_out(i), "") + each} for i in range(f.n_out())],
        }
    return {
        "mechanism": ev.mech.name, "content_hash": ev.mech.content_hash(), "casadi": ca.__version__,
        "dim": ev.mech.dim, "mobility": ev.mobility, "storage": "dense, column-major",
        "q": list(ev.q_labels), "p": list(ev.p_labels), "rows": list(ev.row_owners),
        "basis_rows": list(ev.basis_rows),
        "input_labels": list(ev.input_labels), "output_labels": list(ev.output_labels),
        "platform_labels": list(ev.platform_labels), "functions": funcs,
    }


def header_notes(ev) -> str:
    """A C comment documenting every generated function's arguments, results and their order."""
    man = manifest(ev)
    lines = [
        f"symkin generated evaluators for: {man['mechanism']}",
        f"model content hash {man['content_hash']}, CasADi {man['casadi']}",
        "Geometric-matrix method of Altuzarra et al., IEEE T-RO 2004 (eqs. 3-4, 8-10, 12, 16).",
        "",
        "Calling convention (CasADi): int NAME(const casadi_real** arg, casadi_real** res,",
        "casadi_int* iw, casadi_real* w, int mem); arg[i] / res[i] point to dense column-major",
        "arrays of the shapes below; work sizes from NAME_work() or NAME_SZ_* macros.",
        "indicators and indicators_batch run one vector kernel (symkin.numeric.simd: 2, 4 or 8",
        "configurations per instruction by the target, the scalar results bit for bit);",
        "compile with -DSYMKIN_NO_VECTOR for CasADi's scalar code.",
        "",
        f"q ({len(man['q'])} entries, in this order):",
    ]
    lines += [f"  q[{i}] = {lab}" for i, lab in enumerate(man["q"])]
    lines.append(f"p ({len(man['p'])} entries, in this order):")
    lines += [f"  p[{i}] = {lab}" for i, lab in enumerate(man["p"])]
    lines.append(f"rows of J and phi ({len(man['rows'])}):")
    lines += [f"  row {i}: {lab}" for i, lab in enumerate(man["rows"])]
    if man["basis_rows"]:
        lines.append("independent rows J_S (motion space V, DKP values): "
                     + ", ".join(str(i) for i in man["basis_rows"]))
    for key in ("input_labels", "output_labels", "platform_labels"):
        if man[key]:
            lines.append(f"rows of '{key.split('_')[0]}s': {', '.join(man[key])}".replace("platforms", "platform"))
    lines.append("")
    for name, spec in man["functions"].items():
        ins = ", ".join(f"{a['name']} [{a['shape'][0]}x{a['shape'][1]}]" for a in spec["inputs"])
        outs = ", ".join(f"{a['name']} [{a['shape'][0]}x{a['shape'][1]}]" for a in spec["outputs"])
        lines.append(f"{name}({ins}) -> ({outs})")
        for kind in ("inputs", "outputs"):
            for k, a in enumerate(spec[kind]):
                where = "arg" if kind == "inputs" else "res"
                lines.append(f"    {where}[{k}] {a['name']}: {a['meaning']}")
    body = "\n".join(" * " + ln if ln else " *" for ln in lines)
    return "/*\n" + body.replace("*/", "* /") + "\n */\n"


# ---------------------------------------------------------------------- generate, build, load
def generate_sources(ev, directory, stem: str) -> tuple[Path, Path]:
    """Write ``stem.c`` and ``stem.h`` (documented) for every Function of ``ev``."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    cg = ca.CodeGenerator(f"{stem}.c", {"with_header": True})
    for name in GENERATED_FUNCTIONS:
        if name in ev._symbolic:
            cg.add(ev._symbolic[name])
    cg.generate(str(directory) + os.sep)
    c_path, h_path = directory / f"{stem}.c", directory / f"{stem}.h"
    text = c_path.read_text()
    for name in GENERATED_FUNCTIONS:
        base = name[: -len("_batch")]
        if name.endswith("_batch") and name in ev._symbolic and base in ev._symbolic:
            text = simd.patch(text, ev._symbolic[base], {base: 1, name: ev._symbolic[name].size_in(0)[1]})
    notes = header_notes(ev)
    write_atomic(h_path, notes + h_path.read_text())
    write_atomic(c_path, notes + text)
    return c_path, h_path


def build_library(c_path, so_path, compiler: str | None = None, flags=DEFAULT_FLAGS,
                  timeout: float = 300.0) -> Path:
    """Compile ``c_path`` into the shared library ``so_path`` (atomically replaced).

    Raises
    ------
    CompilerError
        When the compiler is not found or fails.
    """
    cc = find_compiler(compiler)
    exe = shutil.which(cc)
    if exe is None:
        raise CompilerError(f"C compiler {cc!r} not found (set SYMKIN_CC or CC, or pass compiler=)")
    so_path = Path(so_path)
    so_path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(suffix=".so", dir=so_path.parent)
    os.close(fd)
    cmd = [exe, *flags, str(c_path), "-o", tmp, "-lm"]
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except (OSError, subprocess.TimeoutExpired) as exc:
        os.unlink(tmp)
        raise CompilerError(f"C compiler {cc!r} could not run: {exc}") from None
    if proc.returncode != 0:
        os.unlink(tmp)
        raise CompilerError(f"C compiler {cc!r} failed (exit {proc.returncode}): "
                            f"{proc.stderr.strip()[:2000]}", proc.stderr)
    mask = os.umask(0)
    os.umask(mask)
    os.chmod(tmp, 0o777 & ~mask)  # the mode a linker gives a library, not mkstemp's 0600 (+x)
    os.replace(tmp, so_path)
    return so_path


def load_library(so_path, names) -> dict[str, ca.Function]:
    """``casadi.external`` Functions ``names`` from the library (kept for the process)."""
    key = str(Path(so_path).resolve())
    loaded = _LOADED.get(key)
    if loaded is None or any(n not in loaded for n in names):
        loaded = {n: ca.external(n, key) for n in names}
        _LOADED[key] = loaded
    return loaded


def write_atomic(path, text: str) -> Path:
    """Write ``text`` to ``path`` through a temporary file in the same directory and ``os.replace``."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    mask = os.umask(0)
    os.umask(mask)
    os.chmod(tmp, 0o666 & ~mask)  # the mode of a new file, not mkstemp's 0600
    try:
        with os.fdopen(fd, "w") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except OSError:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


@contextmanager
def _build_lock(path: Path):
    """Exclusive lock on ``path`` (``fcntl.flock``; no lock where ``fcntl`` does not exist)."""
    try:
        import fcntl
    except ImportError:  # not POSIX: atomic replacement alone keeps readers safe
        yield
        return
    with open(path, "a") as fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


def _sidecar(so_path: Path) -> Path:
    return so_path.with_name(so_path.name + ".sha256")


def _digest(path: Path) -> tuple[int, str]:
    digest = hashlib.sha256()
    size = 0
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            size += len(block)
            digest.update(block)
    return size, digest.hexdigest()


def record_artefact(so_path, final_path=None) -> Path:
    """Write the size and SHA-256 of ``so_path`` to the sidecar of ``final_path`` (default ``so_path``).

    The sidecar ``NAME.sha256`` is a small JSON object written atomically; a library is
    loaded only when its size and hash match it (:func:`verify_artefact`).
    """
    so_path = Path(so_path)
    size, sha = _digest(so_path)
    target = Path(final_path) if final_path is not None else so_path
    return write_atomic(_sidecar(target), json.dumps({"size": size, "sha256": sha}))


def verify_artefact(so_path) -> str | None:
    """``None`` when ``so_path`` matches its recorded size and hash, else why not (one phrase)."""
    so_path = Path(so_path)
    try:
        record = json.loads(_sidecar(so_path).read_text())
        size, sha = int(record["size"]), str(record["sha256"])
    except FileNotFoundError:
        return "no recorded hash"
    except (OSError, ValueError, KeyError, TypeError):
        return "its recorded hash is unreadable"
    try:
        actual = so_path.stat().st_size
    except OSError:
        return "missing"
    if actual != size:
        return f"size {actual} bytes, recorded {size}"
    if _digest(so_path)[1] != sha:
        return "content differs from its recorded hash"
    return None


def clean_stale_builds(directory, age: float = STALE_BUILD_SECONDS) -> list[Path]:
    """Remove the ``.build-*`` folders of ``directory`` older than ``age`` seconds; return them."""
    import time

    removed = []
    now = time.time()
    for path in Path(directory).glob(".build-*"):
        try:
            if now - path.stat().st_mtime > age:
                shutil.rmtree(path, ignore_errors=True)
                removed.append(path)
        except OSError:
            continue
    return removed


def cache_size(cache_dir=None) -> tuple[int, int]:
    """``(number of files, bytes)`` under the artefact cache (0, 0 when it does not exist)."""
    root = cache_directory(cache_dir)
    count = total = 0
    if root.is_dir():
        for path in root.rglob("*"):
            try:
                if path.is_file():
                    count += 1
                    total += path.stat().st_size
            except OSError:
                continue
    return count, total


def clear_cache(cache_dir=None) -> tuple[int, int]:
    """Empty the artefact cache (the folder itself stays); return what was removed as :func:`cache_size`."""
    root = cache_directory(cache_dir)
    removed = cache_size(root)
    if root.is_dir():
        for path in root.iterdir():
            if path.is_dir() and not path.is_symlink():
                shutil.rmtree(path, ignore_errors=True)
            else:
                try:
                    path.unlink()
                except FileNotFoundError:
                    pass
    _LOADED.clear()
    return removed


def cached_library(directory, stem: str, write_sources: Callable[[Path], Path], names,
                   compiler: str | None = None, flags=DEFAULT_FLAGS, force: bool = False) -> dict[str, ca.Function]:
    """Build (once per cache) and load the library ``stem.so``: the one entry point of the artefact cache.

    ``write_sources(tmp)`` writes ``stem.c`` (and any companion files: header, manifest)
    into the temporary directory ``tmp`` and returns the path of the C file.  Under a
    lock on ``stem.lock``, when the library is missing (or ``force``), the sources are
    written and compiled inside a temporary directory of the cache and moved into place,
    the library last, with ``os.replace``: a reader sees either no library or a complete
    one.  A file under the library's name that does not load is rebuilt once.

    Raises
    ------
    CompilerError
        When the compiler is missing or fails.
    """
    directory = _ensure(Path(directory))
    so_path = directory / f"{stem}.so"
    key = str(so_path.resolve())

    def build(rebuild: bool) -> None:
        with _build_lock(directory / f"{stem}.lock"):
            if not rebuild and so_path.exists() and verify_artefact(so_path) is None:
                return  # another process built it while we waited
            clean_stale_builds(directory)
            with tempfile.TemporaryDirectory(dir=directory, prefix=".build-") as tmp:
                c_path = write_sources(Path(tmp))
                built = build_library(c_path, Path(tmp) / so_path.name, compiler, flags)
                for src in sorted(Path(tmp).iterdir()):
                    if src != built:
                        os.replace(src, directory / src.name)
                record_artefact(built, so_path)  # the record first: a reader then sees a mismatch, not a crash
                os.replace(built, so_path)
        _LOADED.pop(key, None)

    if force or not so_path.exists():
        build(rebuild=force)
    elif key not in _LOADED:
        problem = verify_artefact(so_path)
        if problem is not None:
            warnings.warn(f"symkin: cached library {so_path} is damaged ({problem}); compiled again",
                          CodegenWarning, stacklevel=3)
            build(rebuild=False)  # under the lock: rebuilt unless another process just did
    try:
        return load_library(so_path, names)
    except RuntimeError:  # a file the loader refuses under our name: build it again, once
        build(rebuild=True)
        return load_library(so_path, names)


def compile_evaluators(ev, cache_dir=None, compiler: str | None = None, flags=None, force: bool = False):
    """Generate, compile (once, cached on disk) and load C for the Functions of ``ev``.

    Parameters
    ----------
    ev : Evaluators
    cache_dir : path, optional
        Artefact directory (default :func:`cache_directory`).
    compiler : str, optional
        C compiler command (default :func:`find_compiler`).
    flags : sequence of str, optional
        Compiler flags (default :data:`DEFAULT_FLAGS`).
    force : bool
        Regenerate and recompile even when the artefact exists.  (A process that has
        already loaded that library keeps its loaded code: the dynamic loader does not
        load a path twice.)

    Returns
    -------
    Evaluators
        ``ev`` itself, its ``functions`` replaced by the compiled ones (``ev.compiled``
        True, ``ev.library`` the shared library), or unchanged with a
        :class:`CodegenWarning` when no compiler works.
    """
    flags = tuple(DEFAULT_FLAGS if flags is None else flags)
    cc = find_compiler(compiler)
    directory = cache_directory(cache_dir)
    stem = artefact_stem(ev.mech, cc, flags)
    names = [n for n in GENERATED_FUNCTIONS if n in ev._symbolic]

    def write_sources(tmp: Path) -> Path:
        c_path, _ = generate_sources(ev, tmp, stem)
        write_atomic(tmp / f"{stem}.json", json.dumps(manifest(ev), indent=1))
        return c_path

    try:
        functions = cached_library(directory, stem, write_sources, names, cc, flags, force=force)
    except (CompilerError, OSError, RuntimeError) as exc:
        warnings.warn(f"symkin: could not compile the evaluators of {ev.mech.name!r} ({exc}); "
                      "using the in-process CasADi functions, which give the same numbers more slowly",
                      CodegenWarning, stacklevel=3)
        return ev
    ev.functions = dict(functions)
    ev.compiled = True
    ev.library = str(directory / f"{stem}.so")
    ev._cache.clear()
    return ev


def _ensure(directory: Path) -> Path:
    directory.mkdir(parents=True, exist_ok=True)
    return directory
