"""The position problem of a mechanism as a curve ``H(y) = 0`` for continuation (paper §IV-A).

``y = q / ℓ`` are the free nodal coordinates made dimensionless by the model's length
scale ``ℓ``.  ``H`` stacks the closure equations ``Φ(q)/ℓ`` and, for a mechanism with F > 1, the F − 1 *held*
input combinations, so that the solution set is the 1-D curve along which the driving
input moves (a straight segment in input space).  Residual, Jacobian, second derivatives
and the drive are CasADi Functions of ``y``.

The curve is built on the mechanism's evaluators (:func:`symkin.analysis.batch.evaluators_for`,
shared per model content): ``Φ`` is the closure expression of ``symkin.evaluators(mech)``
and the geometric / parameter rows at a point are its ``J`` and ``parameters`` Functions,
so that paths, batch evaluation and :func:`symkin.analyze` see the same rows.
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from symkin.analysis.batch import Evaluators, evaluators_for
from symkin.errors import SymkinError
from symkin.model.mechanism import Mechanism
from symkin.numeric.coordinates import LinearInput, input_coordinates, parse_input_label, segment_inputs

__all__ = ["MechanismCurve"]


@dataclass(eq=False)
class MechanismCurve:
    """Curve problem of ``mech`` driven by ``drive`` with ``held`` inputs fixed at ``held_values``.

    Implements the :class:`~symkin.curves.stepper.CurveProblem` protocol (residual,
    Jacobian and, from CasADi Hessians, ``second_derivative``) in the dimensionless
    coordinates ``y``.  Everything is one CasADi expression graph: the closure, the held
    input coordinates and the drive, differentiated automatically.
    """

    mech: Mechanism
    drive: LinearInput
    held: tuple[LinearInput, ...] = ()
    held_values: tuple[float, ...] = ()
    generated: str | bool = "compiled"  # "compiled" (C, cached), "vm" (in-process CasADi) or False

    def __post_init__(self):
        self._fast = False
        if len(self.held) != len(self.held_values):
            raise ValueError("one held value per held input")
        self.evaluators: Evaluators = evaluators_for(self.mech)
        self.model = self.evaluators.model
        self.scale = self.mech.length_scale
        self.x0 = np.array([c for _, c in self.mech.nodes], dtype=float)
        self.free = self.model.free
        m = self.model
        y = ca.SX.sym("y", m.q.numel())
        x = ca.substitute(m.x, m.q, self.scale * y)
        phi = ca.substitute(m.closure, m.q, self.scale * y)
        if m.p.numel():
            phi = ca.substitute(phi, m.p, ca.DM(m.p0))
        # rows between fixed nodes only (a ground link's bars) do not involve y: drop them
        live = [k for k in range(phi.numel()) if ca.depends_on(phi[k], y)]
        phi = phi[live] if live else ca.SX(0, 1)
        parts = [phi / self.scale]
        for c, v in zip(self.held, self.held_values):
            expr = c.expression(self.mech, x, self.x0)
            parts.append(expr / self.scale - v if c.kind == "length" else expr - v)
        h = ca.vertcat(*parts)
        jac = ca.jacobian(h, y)
        v = ca.SX.sym("v", y.numel())
        drive = self.drive.expression(self.mech, x, self.x0)
        drive_scale = self.scale if self.drive.kind == "length" else 1.0
        self._hj = ca.Function("curve", [y], [h, jac], ["y"], ["H", "J"])
        self._d2 = ca.Function("curve_second", [y, v], [ca.jtimes(ca.mtimes(jac, v), y, v)],
                               ["y", "v"], ["d2H"])
        self._drive = ca.Function("drive", [y], [drive, ca.jacobian(drive, y).T / drive_scale],
                                  ["y"], ["value", "gradient"])

    # ------------------------------------------------------------------ coordinates
    def q_of(self, y: np.ndarray) -> np.ndarray:
        return np.asarray(y, float) * self.scale

    def y_of(self, q: np.ndarray) -> np.ndarray:
        return np.asarray(q, float) / self.scale

    def x_of(self, y: np.ndarray) -> np.ndarray:
        """All nodal coordinates, shape (n, dim)."""
        flat = self.x0.ravel().copy()
        flat[self.free] = self.q_of(y)
        return flat.reshape(self.x0.shape)

    def y0(self) -> np.ndarray:
        return self.y_of(self.x0.ravel()[self.free])

    @property
    def casadi_function(self) -> ca.Function:
        """``y ↦ (H, J)``, the CasADi Function behind :meth:`residual_and_jacobian` (callable on SX)."""
        return self._hj

    # ------------------------------------------------------------------ CurveProblem
    def residual_and_jacobian(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        h, j = self._hj(y)
        return np.array(h).ravel(), np.array(j)

    def residual(self, y: np.ndarray) -> np.ndarray:
        return np.array(self._hj(y)[0]).ravel()

    def jacobian(self, y: np.ndarray) -> np.ndarray:
        return np.array(self._hj(y)[1])

    def second_derivative(self, y: np.ndarray, v: np.ndarray) -> np.ndarray:
        """``H''(y)[v, v]`` from CasADi's forward-over-forward derivatives."""
        return np.array(self._d2(y, v)).ravel()

    # ------------------------------------------------------------------ quantities at a point
    def input_value(self, y: np.ndarray) -> float:
        """Value of the driving input (radians or model length units) from the model's configuration."""
        return float(self._drive(y)[0])

    def drive_rate(self, y: np.ndarray, t: np.ndarray) -> float:
        """d(input)/ds along the unit tangent ``t`` (dimensionless)."""
        return float(np.array(self._drive(y)[1]).ravel() @ t)

    def rows(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Geometric rows ``J_f`` and input / output parameter rows at ``y`` (free coordinates).

        From the evaluators' ``J`` and ``parameters`` Functions at ``q = ℓ y``.
        """
        fn = self.evaluators.functions
        q = ca.DM(self.q_of(y))
        jf = np.array(fn["J"](q)[1])
        pin, pout = (np.array(v)[:, self.free] for v in fn["parameters"](q)[:2])
        return jf, pin, pout

    def mechanism_at(self, y: np.ndarray) -> Mechanism:
        return self.mech.with_coordinates(self.x_of(y))

    @property
    def fast_corrector(self):
        """The generated corrector (:mod:`symkin.paths.generated`), or None (see ``generated``)."""
        if not self.generated:
            return None
        if self._fast is False:
            from symkin.paths.generated import generated_corrector

            self._fast = generated_corrector(self, compile=self.generated == "compiled")
        return self._fast


def make_curve(mech: Mechanism, drive: str | dict[str, float] | None = None) -> MechanismCurve:
    """Curve of ``mech`` for a path driven by one input or along a straight segment in input space.

    ``drive`` is an input label (that input moves, the model's other inputs are held at their
    values), a mapping ``{label: rate}`` (the named inputs move as ``λ · rate``, the others
    are held), or None (the model's first input).  Raises :class:`SymkinError` when this
    does not leave a 1-D curve (F − 1 independent held combinations are needed).
    """
    f = mech.mobility_value
    if f < 1:
        raise SymkinError(f"{mech.name}: mobility F = {f}; a path needs a mechanism that moves")
    if isinstance(drive, dict):
        moving, held = segment_inputs(mech, drive, mech.length_scale)
    else:
        if drive is None:
            coords = input_coordinates(mech)
            if not coords:
                raise SymkinError(f"{mech.name}: the model has no inputs; name one with --input")
            one = coords[0]
        else:
            one = parse_input_label(mech, drive)
        moving = LinearInput.single(one)
        held = tuple(LinearInput.single(c) for c in input_coordinates(mech) if c.label != one.label)
    if len(held) < f - 1:
        raise SymkinError(f"{mech.name}: F = {f} but only {len(held)} input combination(s) to hold; "
                          "a path moves along one direction and holds F - 1 others")
    return MechanismCurve(mech, moving, held[: f - 1], tuple(0.0 for _ in held[: f - 1]))
