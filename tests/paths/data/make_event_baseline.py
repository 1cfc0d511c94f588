"""Write ``event_baseline.json``: the events of ``symkin.trace`` over a full turn of every catalogue
mechanism and every ``papers_examples/*.toml`` model that has an input.

Run on the code before a change to the paths stage; ``tests/paths/test_event_baseline.py``
compares the events after it (input values to 1e-10, kinds and types exactly).

    PYTHONPATH=. python tests/paths/data/make_event_baseline.py
"""
from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path

from symkin.errors import SymkinError
from symkin.model import catalogue
from symkin.model.mechanism import Mechanism
from symkin.model.model_file import read_model
from symkin.numeric.coordinates import input_coordinates

ROOT = Path(__file__).resolve().parents[3]
OUT = Path(__file__).with_name("event_baseline.json")
MAX_ARCLENGTH = 60.0


def cases() -> list[tuple[str, str, Mechanism]]:
    """(name, source, mechanism) of every catalogue entry and papers example with an input."""
    out = [(name, f"catalogue:{name}", catalogue.get(name)) for name in catalogue.names()]
    for toml in sorted((ROOT / "papers_examples").glob("*.toml")):
        out.append((toml.stem, f"papers_examples/{toml.name}", read_model(toml)))
    return [c for c in out if input_coordinates(c[2])]


def events_of(mech: Mechanism) -> dict:
    """The drive, the range and the events (kind, kinds, types, input) of a full turn (or a unit length)."""
    from symkin.paths.trace import trace

    drive = input_coordinates(mech)[0]
    stop = 2 * math.pi if drive.kind == "angle" else mech.length_scale
    try:
        path = trace(mech, start=0.0, stop=stop, max_arclength=MAX_ARCLENGTH)
    except SymkinError as exc:
        return {"drive": drive.label, "stop": stop, "error": type(exc).__name__}
    return {"drive": drive.label, "stop": stop, "stop_reason": path.stop_reason,
            "events": [{"kind": str(e.kind), "kinds": [str(k) for k in e.kinds],
                        "types": [str(t) for t in e.analysis.types] if e.analysis else [],
                        "locked_links": list(e.analysis.locked_links) if e.analysis else [],
                        "input": e.input} for e in path.events]}


def main() -> None:
    result = {}
    for name, source, mech in cases():
        t0 = time.perf_counter()
        result[source] = {"name": name, **events_of(mech)}
        print(f"{source}: {len(result[source].get('events', []))} events, {time.perf_counter() - t0:.1f} s",
              file=sys.stderr)
    OUT.write_text(json.dumps(result, indent=1) + "\n")


if __name__ == "__main__":
    main()
