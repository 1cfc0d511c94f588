"""``symkin cache [--clear]``: where the compiled-artefact cache is, its size; empty it.

The cache (``$SYMKIN_CACHE``, default ``~/.cache/symkin``) holds the generated C and the
libraries compiled from it (:mod:`symkin.numeric.codegen`).  Every library is verified
against its recorded size and hash before it is loaded, and rebuilt when damaged, so
clearing is never needed for correctness; it frees the space.
"""
from __future__ import annotations

from symkin.commands import Output

NAME = "cache"
HELP = "print where the compiled-artefact cache is and its size; --clear empties it"


def add_arguments(p) -> None:
    p.add_argument("--clear", action="store_true", help="remove every cached artefact")


def _size(n: int) -> str:
    for unit in ("bytes", "KiB", "MiB", "GiB"):
        if n < 1024 or unit == "GiB":
            return f"{n} {unit}" if unit == "bytes" else f"{n:.1f} {unit}"
        n /= 1024
    return f"{n} bytes"  # pragma: no cover


def run(args) -> Output:
    from symkin.numeric.codegen import cache_directory, cache_size, clear_cache

    root = cache_directory()
    if args.clear:
        files, size = clear_cache(root)
        return Output(f"{root}: removed {files} file(s), {_size(size)}")
    files, size = cache_size(root)
    where = "" if root.is_dir() else " (does not exist yet)"
    return Output(f"{root}{where}: {files} file(s), {_size(size)}")
