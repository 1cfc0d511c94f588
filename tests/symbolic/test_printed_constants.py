"""Constants in printed conditions are numbers, not 30-digit rationals (issue 7 §8).

On a Watt six-bar with measured (non-round) coordinates, ``symkin conditions`` used to print
trivial factors such as ``5000000000000000*sin(1832067535502911/2000000000000000)/7025568055324779``
and geometric factors with such a rational inside (``sin(theta_link - theta_rocker + p/q)``).
Every printed condition (text, LaTeX, JSON) must now show short exact forms or floats.
"""
from __future__ import annotations

import json
import math
import re

import pytest

from symkin.cli import main
from symkin.model import catalogue
from symkin.model.model_file import write_model

LONG_INTEGER = re.compile(r"(?<![\d.])\d{11,}(?![\d.])")      # a rational's numerator or denominator
FLOAT = re.compile(r"(?<![\w.])(\d+)\.(\d+)")


def assert_short_constants(text: str) -> None:
    """No integer of more than 10 digits; no float of more than 15 significant digits."""
    assert not LONG_INTEGER.search(text), LONG_INTEGER.search(text).group()
    for whole, frac in FLOAT.findall(text):
        digits = (whole + frac).lstrip("0")
        assert len(digits) <= 15, f"{whole}.{frac}"


def test_the_checker_rejects_the_old_output():
    with pytest.raises(AssertionError):
        assert_short_constants("5000000000000000*sin(1832067535502911/2000000000000000)/7025568055324779")
    with pytest.raises(AssertionError):
        assert_short_constants(r"\frac{85423171266413}{125000000000000}")
    assert_short_constants("0.656174494225246*sin(theta_rocker - 0.683385370131304) + 3/4 + atan(4/3)")


def _sin_between(mech, a, b, c, d) -> float:
    """|sin| of the angle between segments a→b and c→d (elementary geometry)."""
    xyz = mech.coordinates()
    u = [q - p for p, q in zip(xyz[a], xyz[b])]
    v = [q - p for p, q in zip(xyz[c], xyz[d])]
    return abs(u[0] * v[1] - u[1] * v[0]) / (math.hypot(*u) * math.hypot(*v))


# meaning of each factor -> the two segments whose alignment it states
SEGMENTS = {"coupler ∥ rocker (D-C)": ("B", "C", "D", "C"), "link ∥ output": ("E", "G", "F", "G"),
            "rocker (D-E) ∥ link": ("D", "E", "E", "G"), "crank ∥ coupler": ("A", "B", "B", "C")}


def test_watt_sixbar_dkp_conditions_print_short_constants_and_mean_the_right_alignments():
    from symkin.symbolic import symbolic_model

    mech = catalogue.get("watt_sixbar")
    sm = symbolic_model(mech, coordinates="angles")
    expected = {"input": {"coupler ∥ rocker (D-C)", "link ∥ output"},
                "output": {"rocker (D-E) ∥ link", "crank ∥ coupler"}}
    for which in ("input", "output"):
        cond = sm.dkp_condition(which)
        printed = {k: v for k, v in cond.as_dict().items() if k != "seconds"}       # the timing is no constant
        for text in (str(cond), cond.latex(), json.dumps(printed, ensure_ascii=False)):
            assert_short_constants(text)
        # the two dyads of the Watt II chain: with the input (output) locked, each dyad is stiff
        # unless its two bars are aligned
        factors = cond.geometric_factors
        assert {f.meaning for f in factors} == expected[which]
        for f, value in zip(factors, cond.evaluate_factors()):
            assert abs(value) == pytest.approx(_sin_between(mech, *SEGMENTS[f.meaning]), rel=1e-9)
        assert all(abs(cond.model.evaluate(t.readable)) > 0.1 for t in cond.trivial_factors)


@pytest.mark.slow
def test_watt_sixbar_conditions_command_prints_numbers(tmp_path, capsys):
    model = write_model(catalogue.get("watt_sixbar"), tmp_path / "watt.toml")
    assert main(["conditions", str(model)]) == 0
    text = capsys.readouterr().out
    assert "IM (L > F)" in text and "trivial factors (never zero)" in text
    assert_short_constants(text)
    assert main(["conditions", str(model), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert [c["kind"] for c in data["conditions"]] == ["IM", "DKP-input", "DKP-output"]
    for cond in data["conditions"]:
        assert_short_constants(json.dumps({k: v for k, v in cond.items() if k not in ("value_at_model", "seconds")}))
        assert abs(cond["value_at_model"]) > 1e-3                   # a generic configuration
