"""Fuzz: the mutation kinds of issue 20 on every base model of the model-file fuzz test.

Repeated ``fixed`` entries, a link listing thousands of nodes, every node fixed,
repeated inputs, outputs and sliders, and an outlier coordinate (2**63): each case is
read within a time bound (linear validation) and ends in a mechanism or a
:class:`~symkin.ModelError`; small ones are analysed; a sample goes through the CLI
(exit 0 or 2, no traceback).
"""
from __future__ import annotations

import json
import random
import signal

import pytest

import symkin
from tests.model.test_fuzz_model_files import _bases, _node_names, _write, run_cli

SEED = 20
BOUND_SECONDS = 60.0  # per case; quadratic validation of these sizes takes far longer


def _node_bases():
    """The fuzz bases written with nodes (the mutations below grow nodes, links and lists of them;
    a model written by its joints alone has no node to start from)."""
    return [(name, base) for name, base in _bases() if base.get("nodes")]


def _repeat_fixed(data, rng):
    fixed = data.get("fixed") or _node_names(data)[:1]
    data["fixed"] = list(fixed) * rng.choice((2, 500, 20000))
    return "fixed repeated"


def _huge_link(data, rng):
    n = rng.choice((300, 5000, 30000))
    first = _node_names(data)[0]
    x0, y0, *rest = list(data["nodes"][first]) + [0.0]
    for k in range(n):
        data["nodes"][f"Z{k}"] = [x0 + 1 + k % 97, y0 + 1 + k // 97, *rest[:1]][: len(data["nodes"][first])]
    data.setdefault("links", {})["zbody"] = [first] + [f"Z{k}" for k in range(n)]
    return f"link of {n + 1} nodes"


def _all_fixed(data, rng):
    data["fixed"] = _node_names(data)
    return "every node fixed"


def _repeat_parameters(data, rng):
    key = rng.choice(("inputs", "outputs"))
    items = data.get(key) or [{"rotation": next(iter(data.get("links", {"x": 0})))}]
    data[key] = list(items) * rng.choice((2, 1000, 10000))
    return f"{key} repeated"


def _repeat_sliders(data, rng):
    if not data.get("sliders"):
        return "no sliders"
    data["sliders"] = list(data["sliders"]) * rng.choice((2, 1000))
    return "sliders repeated"


def _outlier(data, rng):
    name = rng.choice(_node_names(data))
    coords = list(data["nodes"][name])
    coords[rng.randrange(len(coords))] = rng.choice((2.0 ** 63, -(2.0 ** 63), 1e300))
    data["nodes"][name] = coords
    return f"outlier coordinate at {name}"


KINDS = (_repeat_fixed, _huge_link, _all_fixed, _repeat_parameters, _repeat_sliders, _outlier)


def _bounded(fn, *args):
    def stop(*_):
        raise TimeoutError(f"still running after {BOUND_SECONDS:.0f} s")

    old = signal.signal(signal.SIGALRM, stop)
    signal.setitimer(signal.ITIMER_REAL, BOUND_SECONDS)
    try:
        return fn(*args)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def _read_and_maybe_analyse(path):
    try:
        mech = symkin.read_model(path)
    except symkin.ModelError as exc:
        assert str(exc) and len(exc.problems) <= 50, "duplicates are reported once, with their count"
        return "ModelError"
    if len(mech.nodes) <= 100:
        assert isinstance(symkin.analyze(mech), symkin.Analysis)
        return "analysis"
    return "mechanism"


@pytest.mark.slow
def test_issue_20_mutations_end_in_a_mechanism_or_a_model_error(tmp_path):
    rng = random.Random(SEED)
    outcomes, failures, cli = {}, [], 0
    for b, (base_name, base) in enumerate(_node_bases()):
        for kind in KINDS:
            data = json.loads(json.dumps(base))
            how = kind(data, rng)
            path = _write(tmp_path, len(outcomes) + len(failures), ".json", json.dumps(data))
            try:
                result = _bounded(_read_and_maybe_analyse, path)
            except Exception as exc:  # noqa: BLE001 - the point of the test: report the case
                failures.append(f"{base_name} [{how}]: {type(exc).__name__}: {exc}"[:400])
                continue
            outcomes[result] = outcomes.get(result, 0) + 1
            if result == "ModelError" and (b + KINDS.index(kind)) % 4 == 0:
                cli += 1
                code, out, err = run_cli(path)
                if code != 2 or "Traceback" in out + err or not err.strip():
                    failures.append(f"{base_name} [{how}]: CLI exit {code}: {err[-300:]}")
    print(f"\nfuzz (issue 20 kinds): {outcomes}, {cli} through the CLI, {len(failures)} failures")
    assert not failures, "\n".join(failures[:20])
    assert outcomes.get("ModelError", 0) >= len(_node_bases()) * 3 and cli >= 10
