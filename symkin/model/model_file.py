"""Read and write model files (TOML or JSON, one schema; see the README)."""
from __future__ import annotations

import json
import re
import sys
import tomllib
from pathlib import Path

from symkin.errors import ModelError, ModelFileError, Problem
from symkin.model.mechanism import Mechanism
from symkin.model.validation import parse_mechanism

__all__ = ["read_model", "write_model", "load_model_data", "CATALOGUE_PREFIX"]


def _reject_duplicates(pairs):
    seen = {}
    for key, value in pairs:
        if key in seen:
            raise ValueError(f"duplicate key {key!r}")
        seen[key] = value
    return seen


def _unreadable(exc: Exception) -> str:
    """What a parser's ValueError or RecursionError means for the user."""
    if isinstance(exc, RecursionError):
        return "lists or tables nested too deeply"
    if "integer string conversion" in str(exc):
        return f"an integer with more than {sys.get_int_max_str_digits()} digits"
    return str(exc)


def load_model_data(path: str | Path) -> dict:
    """The raw dictionary of a model file; malformed files raise :class:`ModelFileError`."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ModelFileError(path, [Problem("", "no such file")]) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ModelFileError(path, [Problem("", f"cannot read the file ({exc})")]) from None
    suffix = path.suffix.lower()
    if suffix == ".json":
        try:
            return json.loads(text, object_pairs_hook=_reject_duplicates)
        except json.JSONDecodeError as exc:
            raise ModelFileError(path, [Problem(f"line {exc.lineno}", f"malformed JSON: {exc.msg}")],
                                 line=exc.lineno) from None
        except (ValueError, RecursionError) as exc:
            raise ModelFileError(path, [Problem("", f"malformed JSON: {_unreadable(exc)}")]) from None
    if suffix == ".toml":
        try:
            return tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            match = re.search(r"line (\d+)", str(exc))
            line = int(match.group(1)) if match else None
            raise ModelFileError(path, [Problem(f"line {line}" if line else "", f"malformed TOML: {exc}")],
                                 line=line) from None
        except (ValueError, RecursionError) as exc:  # tomllib lets these through (a huge integer, deep nesting)
            raise ModelFileError(path, [Problem("", f"malformed TOML: {_unreadable(exc)}")]) from None
    raise ModelFileError(path, [Problem("", f"unknown model file type {path.suffix!r}: use .toml or .json")])


CATALOGUE_PREFIX = "catalogue:"


def read_model(path: str | Path) -> Mechanism:
    """Read and validate a model file, or build a catalogue mechanism.

    Parameters
    ----------
    path : str or Path
        A ``.toml`` or ``.json`` model file, or ``catalogue:NAME`` for the mechanism
        ``NAME`` of :mod:`symkin.catalogue` (every command that takes a model takes this).

    Returns
    -------
    Mechanism
        The validated mechanism.

    Raises
    ------
    ModelFileError
        For a missing or malformed file, or one that describes an invalid mechanism;
        ``.problems`` lists every problem with the key, node or link at fault.  An
        unknown catalogue name is one problem that lists the known names.

    Examples
    --------
    >>> import symkin, pathlib
    >>> m = symkin.read_model(pathlib.Path(symkin.__file__).parents[1] / "papers_examples" / "fourbar_appendix.toml")
    >>> m.link_names
    ('crank', 'coupler', 'rocker')
    >>> symkin.read_model("catalogue:five_bar").name
    'five-bar (2RR)'
    """
    if isinstance(path, str) and path.startswith(CATALOGUE_PREFIX):
        return _catalogue_model(path[len(CATALOGUE_PREFIX):])
    path = Path(path)
    data = load_model_data(path)
    if isinstance(data, dict) and "name" not in data:
        data = {"name": path.stem, **data}
    try:
        return parse_mechanism(data, source=str(path))
    except ModelError as exc:
        raise ModelFileError(path, exc.problems) from None


def _catalogue_model(name: str) -> Mechanism:
    """The catalogue's mechanism ``name``; an unknown name is a :class:`ModelFileError` listing the names."""
    from symkin.model import catalogue

    if name not in catalogue.names():
        raise ModelFileError(CATALOGUE_PREFIX + name, [Problem(
            "", f"no mechanism {name!r} in the catalogue; known: {', '.join(catalogue.names())}")])
    return catalogue.get(name)


def _toml_value(value) -> str:
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {_toml_value(v)}" for k, v in value.items()) + "}"
    raise TypeError(f"cannot write {value!r} to TOML")


def write_model(mechanism: Mechanism, path: str | Path) -> Path:
    """Write ``mechanism`` as TOML or JSON (by the file's suffix); returns the path.

    The file is written to a temporary name first and renamed, so a failure leaves
    nothing half-written.
    """
    path = Path(path)
    data = mechanism.to_dict()
    if path.suffix.lower() == ".json":
        text = json.dumps(data, indent=2) + "\n"
    elif path.suffix.lower() == ".toml":
        lines = [f"{k} = {_toml_value(v)}" for k, v in data.items() if k not in ("nodes", "links")]
        lines += ["", "[nodes]"] + [f"{k} = {_toml_value(v)}" for k, v in data["nodes"].items()]
        lines += ["", "[links]"] + [f"{k} = {_toml_value(v)}" for k, v in data["links"].items()]
        text = "\n".join(lines) + "\n"
    else:
        raise ModelFileError(path, [Problem("", f"unknown model file type {path.suffix!r}: use .toml or .json")])
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(text, encoding="utf-8")
    tmp.replace(path)
    return path
