"""The symbolic model of a mechanism: geometric matrices and singularity conditions.

:func:`symbolic_model` returns a :class:`SymbolicModel`, whose ``G`` is the paper's
geometric matrix (eq. 3; A5 for the appendix four-bar) as a sympy ``Matrix`` over all nodal
velocity components, built as ``Σ a aᵀ`` over exactly the constraint rows of the numeric
core (:mod:`symkin.rows <symkin.symbolic.rows>`), so that it evaluates at the model's
configuration to :func:`symkin.geometric_matrix`.  ``reduced_G`` is the free-coordinate
block (fixed nodes removed), ``boundary_G`` the paper's A6 form.  The conditions
(:meth:`SymbolicModel.im_condition`, :meth:`SymbolicModel.dkp_condition`) are derived by
:mod:`symkin.symbolic.conditions`.
"""
from __future__ import annotations

import math
from functools import cached_property, lru_cache

import numpy as np
import sympy as sp

from symkin.errors import SymkinError
from symkin.model.mechanism import AXES, Mechanism
from symkin.symbolic.rows import COORDINATES, RowBuilder, SymRow

__all__ = ["SymbolicModel", "symbolic_model", "LAMBDA"]

#: the eigenvalue symbol of the characteristic polynomial (eq. 8)
LAMBDA = sp.Symbol("lambda")


def symbolic_model(mech: Mechanism, coordinates: str = "nodes", design_symbols: bool = False) -> "SymbolicModel":
    """Build the symbolic geometric matrix of ``mech`` (paper eqs. 1-4, A1-A6).

    Parameters
    ----------
    mech : Mechanism
        Any model the core accepts, planar or spatial.
    coordinates : {"nodes", "angles"}
        Configuration variables: node coordinates ``x_B, y_B, ...`` or (planar only) one
        angle ``theta_<link>`` per link, the paper's form of A3/A5.
    design_symbols : bool
        Keep design parameters as symbols: lengths ``l_<link>`` and, in angle coordinates,
        the internal angles ``beta_<body>_<i>_<j>`` of bodies with 3+ nodes.  Otherwise they
        are replaced by their values (exact numbers; in nodal coordinates a length is
        ``sqrt((x_j - x_i)**2 + ...)``).

    Examples
    --------
    >>> from symkin.model.catalogue import get
    >>> sm = symbolic_model(get("fourbar_appendix"), coordinates="angles")
    >>> sm.config_symbols
    (theta_crank, theta_coupler, theta_rocker)
    >>> sm.reduced_G[0, 0]
    cos(theta_coupler)**2 + cos(theta_crank)**2
    """
    return _cached_model(mech, coordinates, bool(design_symbols))


@lru_cache(maxsize=32)
def _cached_model(mech: Mechanism, coordinates: str, design: bool) -> "SymbolicModel":
    return SymbolicModel(mech, coordinates, design)


class SymbolicModel:
    """Symbolic geometric matrix and singularity conditions of one mechanism.

    Use :func:`symbolic_model` to build one (it caches).  Matrices are in the numeric core's
    coordinate order (``x_A, y_A, x_B, ...``, nodes in model order).

    Attributes
    ----------
    mechanism : Mechanism
    coordinates : str
        ``"nodes"`` or ``"angles"``.
    design : bool
        Whether design parameters stay symbols.
    config_symbols : tuple of Symbol
        Configuration variables.
    design_symbols : tuple of Symbol
        Design parameters kept as symbols (empty unless ``design_symbols=True``).
    symbols : tuple of Symbol
        ``config_symbols + design_symbols``: every symbol the matrices may contain.
    values : dict
        Symbol → float, the model's configuration (and design, when symbolic).
    """

    def __init__(self, mech: Mechanism, coordinates: str = "nodes", design: bool = False):
        if coordinates not in COORDINATES:
            raise SymkinError(f"coordinates must be one of {', '.join(COORDINATES)}, got {coordinates!r}")
        self.mechanism = mech
        self.coordinates = coordinates
        self.design = design
        self._builder = RowBuilder(mech, coordinates)
        b = self._builder
        # build the parameter rows once so that every design symbol is registered
        for params in (mech.inputs, mech.outputs):
            self._parameter_symrows(params)
        self.config_symbols = tuple(b.config_symbols)
        self.rows: tuple[SymRow, ...] = tuple(b.rows)
        self.dim = mech.dim
        self.ncoord = mech.dim * len(mech.nodes)
        fixed = set(mech.fixed)
        self.free = tuple(mech.dim * k + a for k, n in enumerate(mech.node_names) if n not in fixed
                          for a in range(mech.dim))

    def __repr__(self) -> str:
        return (f"SymbolicModel({self.mechanism.name!r}, coordinates={self.coordinates!r}, "
                f"design_symbols={self.design})")

    # ------------------------------------------------------------------ symbols
    @property
    def design_symbols(self) -> tuple[sp.Symbol, ...]:
        return tuple(self._builder.design_symbols) if self.design else ()

    @property
    def symbols(self) -> tuple[sp.Symbol, ...]:
        return self.config_symbols + self.design_symbols

    @property
    def values(self) -> dict[sp.Symbol, float]:
        return {s: self._builder.values[s] for s in self.symbols}

    @property
    def _subs(self) -> dict:
        return {} if self.design else self._builder.design_exact

    def symbol(self, name: str) -> sp.Symbol:
        """The symbol called ``name`` (configuration or design), e.g. ``"theta_crank"``."""
        for s in self._builder.config_symbols + self._builder.design_symbols:
            if s.name == name:
                return s
        raise KeyError(f"no symbol {name!r}; known: "
                       f"{', '.join(s.name for s in self._builder.config_symbols + self._builder.design_symbols)}")

    @property
    def all_values(self) -> dict[sp.Symbol, float]:
        """Every symbol used internally (including design parameters) → its value."""
        return dict(self._builder.values)

    def substitute_design(self, expr):
        """Replace design symbols by their values unless the model keeps them symbolic."""
        if not self._subs:
            return expr
        return expr.xreplace(self._subs)

    @property
    def coordinate_labels(self) -> tuple[str, ...]:
        """``x_A, y_A, x_B, ...``: the velocity components indexing the matrices."""
        return tuple(f"{AXES[c]}_{n}" for n in self.mechanism.node_names for c in range(self.dim))

    # ------------------------------------------------------------------ matrices
    def _row_vector(self, row: SymRow) -> list:
        """The dimensionless row ``a`` over all coordinates (design substituted)."""
        out = [sp.Integer(0)] * self.ncoord
        for col, e in row.entries(self.dim).items():
            out[col] = self.substitute_design(e / row.scale)
        return out

    def _assemble(self, rows) -> sp.Matrix:
        """``Σ a aᵀ`` over ``rows`` (eq. 3), entry by entry from the blocks."""
        acc: dict[tuple[int, int], list] = {}
        dim = self.dim
        for row in rows:
            s2 = row.scale ** 2
            for ni, ti in row.blocks:
                for nj, tj in row.blocks:
                    for a in range(dim):
                        for b in range(dim):
                            terms = acc.setdefault((dim * ni + a, dim * nj + b), [])
                            for c1, v1 in ti:
                                for c2, v2 in tj:
                                    if v1[a] != 0 and v2[b] != 0 and c1 != 0 and c2 != 0:
                                        terms.append((v1[a] * v2[b]) * (c1 * c2) / s2)
        g = sp.zeros(self.ncoord, self.ncoord)
        for (i, j), terms in acc.items():
            if terms:
                g[i, j] = self.substitute_design(sp.Add(*terms))
        return g

    @cached_property
    def G(self) -> sp.Matrix:
        """The geometric matrix over all nodal velocity components (eq. 3, A5)."""
        return self._assemble(self.rows)

    @cached_property
    def reduced_G(self) -> sp.Matrix:
        """The free-coordinate block of ``G``: fixed nodes removed (the matrix analysed)."""
        return self.G.extract(list(self.free), list(self.free))

    @cached_property
    def boundary_G(self) -> sp.Matrix:
        """The paper's A6 form: rows and columns of fixed coordinates replaced by the identity."""
        g = self.G.copy()
        free = set(self.free)
        for k in range(self.ncoord):
            if k not in free:
                g[k, :] = sp.zeros(1, self.ncoord)
                g[:, k] = sp.zeros(self.ncoord, 1)
                g[k, k] = sp.Integer(1)
        return g

    @cached_property
    def J(self) -> sp.Matrix:
        """The dimensionless constraint rows over all coordinates: ``G = Jᵀ J``."""
        if not self.rows:
            return sp.zeros(0, self.ncoord)
        return sp.Matrix([self._row_vector(r) for r in self.rows])

    @property
    def row_owners(self) -> tuple[str, ...]:
        """What each row of ``J`` expresses (as the numeric core's ``ConstraintRows.owners``)."""
        return tuple(r.owner for r in self.rows)

    def element_matrices(self) -> dict[str, sp.Matrix]:
        """Element name → its geometric matrix expanded to all coordinates (eq. 2, A3/A4).

        Elements are links (by name) and sliders (``"slider <id>"``); they sum to ``G``.
        """
        out: dict[str, list] = {}
        for r in self.rows:
            out.setdefault(r.element, []).append(r)
        return {name: self._assemble(rows) for name, rows in out.items()}

    def parameter_rows(self, params) -> tuple[sp.Matrix, tuple[str, ...]]:
        """Rows of kinematic parameters over all coordinates (physical units) and labels.

        They equal :func:`symkin.numeric.geometric_matrix.parameters_matrix` on the motion
        space (planar: entry by entry; spatial angular velocities are written from two edges
        of the body instead of a least-squares fit, which agrees on every rigid motion).
        """
        rows = self._parameter_symrows(params)
        if not rows:
            return sp.zeros(0, self.ncoord), ()
        return sp.Matrix([self._row_vector(r) for r in rows]), tuple(r.owner for r in rows)

    def parameter_symrows(self, params) -> list[SymRow]:
        """The rows of the kinematic parameters ``params`` as :class:`SymRow` (polynomial blocks, a scale)."""
        return self._parameter_symrows(params)

    def _parameter_symrows(self, params) -> list[SymRow]:
        out = []
        for p in params:
            out += self._builder.parameter_rows(p)
        return out

    # ------------------------------------------------------------------ evaluation
    def evaluate(self, obj, values: dict | None = None) -> np.ndarray | float:
        """Numeric value of a matrix or expression of this model.

        ``values`` maps symbols (or their names) to numbers and defaults to the model's
        configuration; missing symbols take the model's values.
        """
        vals = dict(self.all_values)
        if values:
            for k, v in values.items():
                vals[self.symbol(k) if isinstance(k, str) else k] = v
        syms = list(vals)
        if isinstance(obj, sp.Basic) and obj.has(sp.Determinant):
            obj = obj.replace(lambda e: isinstance(e, sp.Determinant), lambda e: e.doit())
        f = sp.lambdify(syms, obj, modules="numpy", cse=True)
        out = f(*[vals[s] for s in syms])
        if isinstance(obj, sp.MatrixBase):
            return np.array(out, dtype=float).reshape(obj.shape)
        return float(out)

    def values_at(self, configuration) -> dict[sp.Symbol, float]:
        """Values of every symbol (configuration and design) at another configuration.

        ``configuration`` is a :class:`Mechanism` of the same topology, a mapping node →
        coordinates or an ``(n, dim)`` array in node order.  Design symbols get the
        lengths and internal angles of *that* configuration, so with
        ``design_symbols=True`` any coordinates (even with other lengths) can be evaluated.

        Examples
        --------
        >>> from symkin.model.catalogue import get
        >>> sm = symbolic_model(get("fourbar_appendix"), "angles")
        >>> v = sm.values_at({"B": [0.0, 1.0]})
        >>> round(v[sm.symbol("theta_crank")], 6)
        1.570796
        """
        mech = configuration if isinstance(configuration, Mechanism) else \
            self.mechanism.with_coordinates(configuration)
        if not all(math.isfinite(v) for _, xyz in mech.nodes for v in xyz):
            raise SymkinError("values_at: the configuration has coordinates that are not finite numbers")
        b = RowBuilder(mech, self.coordinates)
        b.register_all()
        return {s: v for s, v in b.values.items() if s in self.all_values}

    # ------------------------------------------------------------------ polynomial and conditions
    def characteristic_polynomial(self, simplify: bool = False) -> sp.Poly:
        """``det(λI − G_r)`` of the reduced geometric matrix as a ``Poly`` in ``λ`` (eq. 8).

        Its coefficients are symmetric functions of the eigenvalues; the coefficient of
        ``λ^F`` is ``(−1)^r`` times the IM condition (:meth:`im_condition`), ``r = n − F``,
        and the lower ones vanish identically.

        With ``m`` constraint rows over ``n`` free coordinates, ``G_r = Jᵀ J`` and, when
        ``m < n``, ``det(λI − Jᵀ J) = λ^(n−m) det(λI − J Jᵀ)``: the smaller Gram matrix is used,
        whose entries are dot products of the rows (in angle coordinates ``cos(α − β)``).
        The polynomial is computed by the division-free Berkowitz algorithm in a polynomial
        ring, the row scales ``1/s²`` kept as symbols until the end.  The 3-RRR (12 free
        coordinates) takes well under a second in angle coordinates.

        Parameters
        ----------
        simplify : bool
            Simplify each coefficient (``trigsimp`` in angle coordinates, ``cancel`` in nodal ones).
        """
        from sympy.polys.matrices import DomainMatrix

        from symkin.symbolic.readable_forms import block_dot

        free = {c: k for k, c in enumerate(self.free)}
        n = len(free)
        rows = [r for r in self.rows if any(c in free and e != 0 for c, e in r.entries(self.dim).items())]
        weights: dict = {}

        def weight(row):
            if row.scale == 1:
                return sp.Integer(1)
            if row.scale not in weights:
                weights[row.scale] = sp.Dummy("w")
            return weights[row.scale]

        if len(rows) < n:  # Gram matrix of the rows: entries a_i · a_j
            free_nodes = {c // self.dim for c in free}
            blocks = [{k: t for k, t in r.blocks if k in free_nodes} for r in rows]
            size = len(rows)

            def dot(i, j):
                if self.coordinates == "angles":
                    e = sp.Add(*[block_dot(blocks[i][k], blocks[j][k]) for k in set(blocks[i]) & set(blocks[j])])
                else:
                    ei, ej = rows[i].entries(self.dim), rows[j].entries(self.dim)
                    e = sp.Add(*[ei[c] * ej[c] for c in ei if c in ej and c in free])
                wi, wj = weight(rows[i]), weight(rows[j])
                return sp.expand(e * (wi * wj if i != j else wi ** 2))

            g = sp.Matrix(size, size, dot)
            undo = {w: 1 / self.substitute_design(scale) for scale, w in weights.items()}
        else:  # the matrix itself: Σ w p pᵀ with w = 1/scale²
            acc = [[[] for _ in range(n)] for _ in range(n)]
            for row in rows:
                entries = {free[c]: e for c, e in row.entries(self.dim).items() if c in free}
                w = weight(row)
                for i, ei in entries.items():
                    for j, ej in entries.items():
                        acc[i][j].append(w * ei * ej)
            g = sp.Matrix(n, n, lambda i, j: sp.expand(sp.expand_trig(sp.Add(*acc[i][j]))))
            undo = {w: self.substitute_design(scale) ** -2 for scale, w in weights.items()}
            size = n
        atoms = sorted(g.atoms(sp.cos, sp.sin), key=sp.default_sort_key)
        dummies = [sp.Dummy() for _ in atoms]
        dm = DomainMatrix.from_Matrix(g.xreplace(dict(zip(atoms, dummies))))
        back = dict(zip(dummies, atoms))
        coeffs = [self.substitute_design(dm.domain.to_sympy(c).xreplace(back).xreplace(undo))
                  for c in dm.charpoly()]
        coeffs += [sp.Integer(0)] * (n - size)  # the factor λ^(n − m)
        if simplify:
            simp = sp.trigsimp if self.coordinates == "angles" else sp.cancel
            coeffs = [simp(c) for c in coeffs]
        return sp.Poly.from_list(coeffs, LAMBDA, domain=sp.EX)

    def im_condition(self, time_limit: float | None = None):
        """The increased-mobility condition (§III-A): ``L > F`` exactly where it vanishes.

        The lowest coefficient of the characteristic polynomial that is nonzero at generic
        configurations, ``e_r(G_r)`` with ``r = n − F``, computed by Cauchy–Binet as the
        sum of the squares of the maximal minors of the velocity equation (each minor
        factored through its block-triangular form).  See
        :func:`symkin.symbolic.conditions.im_condition`.

        Parameters
        ----------
        time_limit : float, optional
            Seconds after which the derivation stops with
            :class:`~symkin.symbolic.conditions.DerivationTimeout` (a ``SymkinError``).

        Examples
        --------
        >>> from symkin.model.catalogue import get
        >>> c = symbolic_model(get("fourbar_appendix"), "angles").im_condition()
        >>> c.readable
        sin(theta_coupler - theta_crank)**2 + sin(theta_coupler - theta_rocker)**2
        """
        from symkin.symbolic.conditions import im_condition

        return im_condition(self, time_limit=time_limit)

    def dkp_condition(self, which: str = "input", time_limit: float | None = None):
        """The DKP condition of the inputs (``"input"``) or the outputs (``"output"``).

        The determinant of the velocity equation augmented with the parameter rows (eq. 12),
        factored, with trivial factors separated; it vanishes exactly where some motion is
        left with those parameters locked: DKP configurations, and IM ones.  See
        :func:`symkin.symbolic.conditions.dkp_condition`.

        Parameters
        ----------
        which : {"input", "output"}
        time_limit : float, optional
            Seconds after which the derivation stops with
            :class:`~symkin.symbolic.conditions.DerivationTimeout`.

        Examples
        --------
        >>> from symkin.model.catalogue import get
        >>> c = symbolic_model(get("fourbar_appendix"), "angles").dkp_condition("input")
        >>> c.readable
        sin(theta_coupler - theta_rocker)
        """
        from symkin.symbolic.conditions import dkp_condition

        return dkp_condition(self, which, time_limit=time_limit)
