"""The position problem (finite displacement analysis): the configuration for given input values.

Newton's method on the CasADi-generated closure residual and Jacobian
(:class:`~symkin.paths.system.MechanismCurve`) with least-squares steps, so redundant
constraints (overconstrained mechanisms) are harmless.  Input values are measured from
the model's configuration.  Newton alone can jump between assembly modes when the new
inputs are far from the model's; :func:`solve_position` therefore walks there by
continuation along a straight segment in input space by default, and uses plain Newton
only with ``continuation=False``.
"""
from __future__ import annotations

import math

from symkin.errors import NotConvergedError, SymkinError
from symkin.model.mechanism import Mechanism
from symkin.curves.stepper import correct
from symkin.numeric.coordinates import LinearInput, input_coordinates, parse_input_label
from symkin.paths.system import MechanismCurve
from symkin.tolerances import DEFAULT

__all__ = ["solve_position"]

#: Newton iterations of the position problem without continuation (a start far from the solution)
POSITION_ITERATIONS = 50


def solve_position(mech: Mechanism, values: dict[str, float], unit: str = "rad", tol: float = DEFAULT.newton,
                   continuation: bool = True) -> Mechanism:
    """The mechanism at the configuration where its inputs take ``values``.

    Parameters
    ----------
    values : dict
        Input label → value measured from the model's configuration (angles in ``unit``,
        lengths in model units).  Inputs of the model not named stay at their values; F
        scalar inputs must be fixed in all.
    continuation : bool
        Walk from the model's configuration along the straight segment in input space (no
        jump to another assembly mode); with False, Newton starts from the model's
        configuration directly.

    Raises
    ------
    NotConvergedError
        The configuration cannot be assembled (or Newton diverged); the message says how
        close it got (``.data["residual"]``, in units of the model's length scale).

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> m = solve_position(get("fourbar_appendix"), {"rotation:crank": 10.0}, unit="deg")
    >>> round(math.degrees(math.atan2(m.coordinates()["B"][1], m.coordinates()["B"][0])), 9)
    87.471192291
    """
    if unit not in ("rad", "deg"):
        raise SymkinError(f"unit must be 'rad' or 'deg', got {unit!r}")
    coords = {c.label: c for c in input_coordinates(mech)}
    for label in values:
        if label not in coords:
            coords[label] = parse_input_label(mech, label)
    target = {}
    for label, c in coords.items():
        v = float(values.get(label, 0.0))
        target[label] = v * (math.pi / 180.0 if (unit == "deg" and c.kind == "angle") else 1.0)
    f = mech.mobility_value
    if len(coords) < f:
        raise SymkinError(f"{mech.name}: F = {f} but only {len(coords)} input(s): the position is not determined")
    moving = {label: v for label, v in target.items() if v != 0.0}
    if not moving:
        return mech
    if continuation:
        from symkin.paths.trace import trace

        path = trace(mech, input=moving, start=0.0, stop=1.0, branch_analysis=False)
        if path.stop_reason != "reached":
            raise NotConvergedError(f"{mech.name}: cannot reach the requested inputs by continuation "
                                    f"({path.message})", residual=math.nan)
        return mech.with_coordinates(path.points[-1].coordinates)
    singles = [LinearInput.single(c) for c in coords.values()]
    curve = MechanismCurve(mech, singles[0], tuple(singles), tuple(
        target[c.label] / (mech.length_scale if c.kind == "length" else 1.0) for c in coords.values()))
    try:
        y, _, res = correct(curve, curve.y0(), tol=tol, max_iterations=POSITION_ITERATIONS)
    except NotConvergedError as exc:
        res = exc.data.get("best_residual", exc.data.get("residual", math.nan))
        raise NotConvergedError(f"{mech.name}: the configuration cannot be assembled for these inputs: "
                                f"Newton reached a residual of {res:.3g} (relative to the model's length "
                                "scale) and no closer", residual=res) from None
    return mech.with_coordinates(curve.x_of(y))
