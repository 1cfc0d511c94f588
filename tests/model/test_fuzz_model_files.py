"""Fuzz test of model files (issue 7 §7): random edits end in an analysis or a ModelError.

Every catalogue model, every ``papers_examples/*.toml`` (among them models written by their
``[[joints]]``) and the joint forms of the 3-RPR and the 6-UPS is edited at random by a
seeded :class:`random.Random` (the cases are the same on every run): keys deleted or
renamed, values replaced by wrong types, NaN, ±inf, ±1e308, huge integers, empty
containers, unicode and very long names, node names swapped or duplicated inside links,
coordinates scaled to overflow or underflow, and the serialised TOML/JSON text truncated
or corrupted at a random byte.  Each case is written to a file and

* read with :func:`symkin.read_model` and analysed with :func:`symkin.analyze`: the
  result must be an :class:`~symkin.Analysis` or a :class:`~symkin.ModelError` (any
  other exception fails with the case's id and file text);
* for a sample, run through the CLI in-process (``symkin analyze FILE --json``): the exit
  code must be 0 (and the JSON parse) or 2, and no traceback may be printed.

The number of cases tried is asserted and printed (run with ``-s`` to see it).
"""
from __future__ import annotations

import contextlib
import io
import json
import math
import random
import tomllib
from pathlib import Path

import pytest

import symkin
from symkin.cli import main
from symkin.model import catalogue
from tests.model import joint_forms

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((ROOT / "papers_examples").glob("*.toml"))

SEED = 20041206
CASES_PER_BASE = 260          # mutated cases per base model (x 2 file formats by alternation)
CLI_EVERY = 8                 # one case in CLI_EVERY also goes through the command line

UNICODE = ["ß", "节点", "🦾", "\u202e", "A\u0301", "Ω", "é", " ", "a b", "a.b", "[x]", "\"q\"", "#c", "="]
LONG = "L" * 5000


def _bad_values(rng: random.Random) -> list:
    """Values of the wrong kind, out of range or pathological."""
    return [
        "x", "", rng.choice(UNICODE), LONG, None, True, False, 0, 1, -1, 2, 3, 4, 7, 10**400, 2.0, 3.0,
        1.5, -0.0, float("nan"), float("inf"), float("-inf"), 1e308, -1e308, 5e-324, 1e-308,
        [], {}, [[]], [{}], [None], ["A", "A"], [1e308, -1e308], [1e308, 1e308, 1e308],
        [float("nan"), 0.0], [0.0, 0.0, 0.0], [1, 2, 3, 4], [10**400, 0], {"A": [0, 0]},
        {"rotation": "crank"}, ["crank"], [True, False],
    ]


# ---------------------------------------------------------------------- walking the data
def _paths(data, prefix=()):
    """Every (path) to a value inside nested dicts and lists."""
    out = []
    if isinstance(data, dict):
        for k, v in data.items():
            out.append(prefix + (k,))
            out += _paths(v, prefix + (k,))
    elif isinstance(data, list):
        for i, v in enumerate(data):
            out.append(prefix + (i,))
            out += _paths(v, prefix + (i,))
    return out


def _parent(data, path):
    for p in path[:-1]:
        data = data[p]
    return data


def _node_names(data) -> list[str]:
    nodes = data.get("nodes") if isinstance(data, dict) else None
    return list(nodes) if isinstance(nodes, dict) else []


# ---------------------------------------------------------------------- edits
def _delete(data, rng):
    paths = _paths(data)
    if not paths:
        return "nothing to delete"
    path = rng.choice(paths)
    parent = _parent(data, path)
    del parent[path[-1]]
    return f"delete {path}"


def _rename_key(data, rng):
    paths = [p for p in _paths(data) if isinstance(_parent(data, p), dict)]
    if not paths:
        return "nothing to rename"
    path = rng.choice(paths)
    parent = _parent(data, path)
    new = rng.choice(UNICODE + [LONG, path[-1] + "_", str(path[-1]).upper(), ""])
    parent[new] = parent.pop(path[-1])
    return f"rename {path} -> {new[:20]!r}"


def _replace(data, rng):
    paths = _paths(data)
    if not paths:
        return "nothing to replace"
    path = rng.choice(paths)
    value = rng.choice(_bad_values(rng))
    _parent(data, path)[path[-1]] = value
    return f"set {path} = {str(value)[:30]!r}"


def _set_top(data, rng):
    key = rng.choice(["dim", "fixed", "mobility", "inputs", "outputs", "platform", "platform_dof", "nodes",
                      "links", "sliders", "name", "description"])
    value = rng.choice(_bad_values(rng))
    data[key] = value
    return f"top {key} = {str(value)[:30]!r}"


def _rename_node(data, rng):
    """Rename a node in [nodes] and (maybe) everywhere it is used, to a unicode name or an existing one."""
    names = _node_names(data)
    if not names:
        return "no nodes"
    old = rng.choice(names)
    new = rng.choice(UNICODE + [LONG] + names)
    everywhere = rng.random() < 0.7
    text = json.dumps(data, ensure_ascii=False)
    if everywhere:
        text = text.replace(json.dumps(old, ensure_ascii=False), json.dumps(new, ensure_ascii=False))
        data.clear()
        data.update(json.loads(text, object_pairs_hook=_last_wins))
    else:
        data["nodes"][new] = data["nodes"].pop(old)
    return f"rename node {old!r} -> {new[:20]!r} ({'everywhere' if everywhere else 'in nodes only'})"


def _last_wins(pairs):
    return dict(pairs)


def _swap_in_link(data, rng):
    links = data.get("links")
    if not isinstance(links, dict) or not links:
        return "no links"
    name = rng.choice(list(links))
    ns = links[name]
    if not isinstance(ns, list) or not ns:
        return "link not a list"
    choice = rng.random()
    names = _node_names(data) or ["A"]
    if choice < 0.3:
        ns[0] = ns[-1]                                   # a node twice in a link
    elif choice < 0.6:
        ns[rng.randrange(len(ns))] = rng.choice(names)   # another node
    elif choice < 0.8:
        other = rng.choice(list(links))                 # two links with the same nodes
        links[other] = list(ns)
    else:
        rng.shuffle(ns)
    return f"swap nodes in link {name!r}"


def _scale_coordinates(data, rng):
    nodes = data.get("nodes")
    if not isinstance(nodes, dict):
        return "no nodes"
    factor = rng.choice([1e300, 1e-300, 1e155, 1e-170, -1e308, 1e308, 0.0])
    for k, v in nodes.items():
        if isinstance(v, list):
            nodes[k] = [c * factor if isinstance(c, float) else c for c in v]
    return f"scale coordinates by {factor:g}"


def _one_coordinate(data, rng):
    nodes = data.get("nodes")
    if not isinstance(nodes, dict) or not nodes:
        return "no nodes"
    name = rng.choice(list(nodes))
    v = nodes[name]
    if not isinstance(v, list) or not v:
        return "node not a list"
    value = rng.choice([float("nan"), float("inf"), 1e308, -1e308, 1e200, 1e-320, 10**400, "1.0", None, True])
    v[rng.randrange(len(v))] = value
    return f"node {name!r} coordinate = {value!r}"


def _slider_edit(data, rng):
    sliders = data.get("sliders")
    if not isinstance(sliders, list) or not sliders or not isinstance(sliders[0], dict):
        data["sliders"] = [{"node": rng.choice(_node_names(data) or ["A"]),
                            "point": [0.0] * 2, "direction": rng.choice([[1e308, 1e308], [0.0, 0.0], [1.0, 0.0],
                                                                         [5e-324, 0.0]])}]
        return "add a slider"
    s = sliders[rng.randrange(len(sliders))]
    if not isinstance(s, dict):
        return "slider not a table"
    key = rng.choice(["id", "node", "point", "direction", "normal", "line", "link"])
    s[key] = rng.choice(_bad_values(rng) + [[1e308, 1e308], [5e-324, 5e-324], [1e-200, 0.0]])
    if rng.random() < 0.3:
        sliders.append(dict(s))                          # duplicate slider
    return f"slider {key} edited"


def _parameter_edit(data, rng):
    where = rng.choice(["inputs", "outputs"])
    items = data.get(where)
    if not isinstance(items, list):
        return f"{where} not a list"
    links = (list(data["links"]) if isinstance(data.get("links"), dict) else []) or ["x"]
    nodes = _node_names(data) or ["A"]
    item = rng.choice([
        {"rotation": rng.choice(links)}, {"twist": rng.choice(links)}, {"velocity": rng.choice(nodes)},
        {"velocity": rng.choice(nodes), "component": rng.choice(["x", "y", "z", "w", 0])},
        {"joint": [rng.choice(links), rng.choice(links)]}, {"slide": rng.choice(nodes)},
        {"rotation": rng.choice(links), "axis": rng.choice([[0.0, 0.0, 1.0], [1e308, 1e308, 0.0],
                                                           [5e-324, 0.0, 0.0], nodes[:2], [0.0, 0.0, 0.0]])},
        {"rotation": rng.choice(links), "label": rng.choice(UNICODE + [LONG, 3])},
        {}, {"rotation": "crank", "twist": "crank"},
    ])
    if rng.random() < 0.5 and items:
        items[rng.randrange(len(items))] = item
    else:
        items.append(item)
    return f"{where} <- {str(item)[:40]}"


#: texts that no Python value serialises to: written in place of a placeholder string
RAW = {"@@deep@@": "[" * 3000 + "]" * 3000, "@@digits@@": "1" * 5000, "@@shallow@@": "[" * 60 + "]" * 60,
       "@@exp@@": "1e999", "@@hex@@": "0x7fffffffffffffff"}


def _raw_text(data, rng):
    """A value that only exists as text: deep nesting, a 5000-digit integer, 1e999, ..."""
    paths = _paths(data)
    if not paths:
        return "nothing to replace"
    path = rng.choice(paths)
    marker = rng.choice(list(RAW))
    _parent(data, path)[path[-1]] = marker
    return f"set {path} = {marker}"


def _unraw(text: str) -> str:
    for marker, raw in RAW.items():
        text = text.replace(json.dumps(marker), raw)
    return text


EDITS = [_raw_text, _delete, _rename_key, _replace, _set_top, _rename_node, _swap_in_link, _scale_coordinates,
         _one_coordinate, _slider_edit, _parameter_edit]


# ---------------------------------------------------------------------- serialising
def _toml_key(key) -> str:
    return json.dumps(str(key), ensure_ascii=False)


def _toml_value(value) -> str | None:
    """TOML inline text of ``value``; None when TOML cannot hold it (None, a huge int)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value) if -2**63 <= value < 2**63 else None
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list):
        parts = [_toml_value(v) for v in value]
        return None if None in parts else "[" + ", ".join(parts) + "]"
    if isinstance(value, dict):
        parts = [(_toml_key(k), _toml_value(v)) for k, v in value.items()]
        if any(p is None for _, p in parts):
            return None
        return "{" + ", ".join(f"{k} = {v}" for k, v in parts) + "}"
    return None


def to_toml(data) -> str | None:
    """The model as TOML text (tables for nodes and links), or None when TOML cannot hold it."""
    if not isinstance(data, dict):
        return None
    head, tables = [], []
    for key, value in data.items():
        if key in ("nodes", "links") and isinstance(value, dict):
            rows = [(_toml_key(k), _toml_value(v)) for k, v in value.items()]
            if any(v is None for _, v in rows):
                return None
            tables += ["", f"[{_toml_key(key)}]"] + [f"{k} = {v}" for k, v in rows]
        else:
            text = _toml_value(value)
            if text is None:
                return None
            head.append(f"{_toml_key(key)} = {text}")
    return "\n".join(head + tables) + "\n"


def _corrupt(text: str, rng: random.Random) -> tuple[str | bytes, str]:
    """Truncate, damage or duplicate part of the serialised text at a random position."""
    raw = text.encode("utf-8")
    cut = rng.randrange(len(raw) + 1)
    kind = rng.random()
    if kind < 0.6:
        return raw[:cut], f"truncated at byte {cut}"
    if kind < 0.75:
        return raw[:cut] + bytes([rng.randrange(256)]) + raw[cut + 1:], f"byte {cut} replaced"
    if kind < 0.9:                       # a key given twice (duplicate node, link or option)
        lines = text.splitlines(keepends=True)
        k = rng.randrange(len(lines))
        return "".join(lines[:k + 1] + [lines[k]] + lines[k + 1:]), f"line {k + 1} duplicated"
    return raw[:cut] + b"\xff\xfe" + raw[cut:], f"invalid UTF-8 at byte {cut}"


# ---------------------------------------------------------------------- cases
def _bases() -> list[tuple[str, dict]]:
    bases = [(f"catalogue:{n}", catalogue.data(n)) for n in catalogue.names()]
    for path in EXAMPLES:
        bases.append((f"papers_examples/{path.name}", tomllib.loads(path.read_text(encoding="utf-8"))))
    # models written by their joints (besides the papers_examples/*_joints.toml files)
    rpr, gough = (tomllib.loads((joint_forms.MODELS / f"{n}.toml").read_text()) for n in ("rpr_3", "gough_stewart"))
    bases.append(("joints:3-RPR", joint_forms.rpr_3(rpr["nodes"])))
    bases.append(("joints:6-UPS", joint_forms.ups_6(gough["nodes"])))
    return bases


def generate_cases(seed: int = SEED, per_base: int = CASES_PER_BASE):
    """Yield ``(case_id, suffix, content, edits)``: the file text (str or bytes) of each case."""
    rng = random.Random(seed)
    for base_name, base in _bases():
        for k in range(per_base):
            data = json.loads(json.dumps(base))
            edits = [rng.choice(EDITS)(data, rng) for _ in range(rng.choice((1, 1, 2, 3)))]
            suffix = ".json" if k % 2 else ".toml"
            text = to_toml(data) if suffix == ".toml" else None
            if text is None:
                suffix = ".json"
                text = json.dumps(data, ensure_ascii=rng.random() < 0.5, indent=rng.choice((None, 1)))
            text = _unraw(text)
            content: str | bytes = text
            if rng.random() < 0.12:
                content, how = _corrupt(text, rng)
                edits.append(how)
            yield f"{base_name}#{k}", suffix, content, edits


def _write(tmp: Path, index: int, suffix: str, content) -> Path:
    path = tmp / f"case{index}{suffix}"
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content, encoding="utf-8")
    return path


def run_case(path: Path) -> str:
    """``"analysis"`` or ``"ModelError"``; anything else raises."""
    try:
        mech = symkin.read_model(path)
    except symkin.ModelError as exc:
        assert str(exc), "a ModelError needs a message"
        assert all(p.message for p in exc.problems)
        return "ModelError"
    result = symkin.analyze(mech)
    assert isinstance(result, symkin.Analysis)
    return "analysis"


def run_cli(path: Path) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(["analyze", str(path), "--json"])
        except SystemExit as exc:             # argparse: a file name it does not like
            code = exc.code
    return code, out.getvalue(), err.getvalue()


N_CASES = len(_bases()) * CASES_PER_BASE


@pytest.mark.slow
@pytest.mark.parametrize("n_cases", [N_CASES], ids=[f"{N_CASES}_cases"])      # the count shows in -v
def test_random_edits_end_in_analysis_or_model_error(tmp_path, n_cases):
    outcomes = {"analysis": 0, "ModelError": 0}
    failures, cli_runs = [], 0
    for index, (case_id, suffix, content, edits) in enumerate(generate_cases()):
        path = _write(tmp_path, index, suffix, content)
        try:
            outcomes[run_case(path)] += 1
        except Exception as exc:  # noqa: BLE001 - the point of the test: report the case
            failures.append(f"{case_id} {edits}: {type(exc).__name__}: {exc}")
            continue
        if index % CLI_EVERY == 0:
            cli_runs += 1
            code, out, err = run_cli(path)
            if code not in (0, 2) or "Traceback" in out + err:
                failures.append(f"{case_id} {edits}: CLI exit {code}: {err[-400:]}")
            elif code == 0:
                json.loads(out)
            elif not err.strip():
                failures.append(f"{case_id} {edits}: CLI exit 2 without a message")
    tried = sum(outcomes.values()) + len(failures)
    print(f"\nfuzz: {tried} cases tried ({outcomes['analysis']} analysed, {outcomes['ModelError']} ModelError), "
          f"{cli_runs} through the CLI, {len(failures)} failures")
    assert not failures, f"{len(failures)} of {tried} cases failed:\n" + "\n".join(failures[:30])
    assert tried == n_cases >= 3000
    assert cli_runs >= 300
    # the edits must exercise both outcomes, not only rejections
    assert outcomes["analysis"] >= 100 and outcomes["ModelError"] >= 1000
