"""The kinds of singular configuration and of curve event, defined once.

Every stage speaks of the same kinds: the classifier's *types* (paper §III–V: IM, DKP in
the input or output, LIM, constraint singularities), the *events* a traced curve meets
(the types again, plus the geometric events of a curve: a branch point, a cusp of a
locus' image, a fold where a curve leaves the assembled region, a closed curve, leaving
the box, the end of a path) and the *points* of a map (a ``meeting`` of two loci).

:class:`Kind` is a :class:`enum.StrEnum`: each member *is* its JSON string
(``Kind.DKP_INPUT == "DKP-input"``, ``json.dumps`` writes ``"DKP-input"``), so the strings
of the JSON output, the command line and the plots are contracts that this module keeps,
and code compares with members instead of spelling the strings again.

>>> Kind.DKP_INPUT == "DKP-input", str(Kind.LIM), Kind("IM") is Kind.IM
(True, 'LIM', True)
>>> (Kind.DKP_OUTPUT, Kind.LIM)  # a result's types print as their strings
('DKP-output', 'LIM')
>>> [str(k) for k in TYPES]
['IM', 'DKP-input', 'DKP-output', 'LIM', 'constraint']
>>> describe(Kind.LIM)
'link impossible motion (LIM)'
"""
from __future__ import annotations

from enum import StrEnum

__all__ = ["Kind", "TYPES", "DKP_KINDS", "LOCUS_KINDS", "describe", "latex"]


class Kind(StrEnum):
    """A kind of singular configuration (a classifier type) or of curve event."""

    # the classifier's types (paper §III–V), in the order reports list them
    IM = "IM"
    DKP_INPUT = "DKP-input"
    DKP_OUTPUT = "DKP-output"
    LIM = "LIM"
    CONSTRAINT = "constraint"
    # events of a traced curve and points of a map
    BRANCH_POINT = "bifurcation"   # a simple branch point located by det[J_H; tᵀ] (an IM configuration)
    CUSP = "cusp"                  # a locus' image in the map's axes turns back
    MEETING = "meeting"            # a curve ends on another locus (two or more types)
    FOLD = "fold"                  # a curve reaches the boundary of the assembled region
    CLOSED = "closed"              # a curve closed on its start
    BOX = "box"                    # a curve left the map's box
    END = "end"                    # a path's input reached its target

    def __repr__(self) -> str:
        # printed as the plain string it stands for: ``print(result.types)`` shows ('IM', 'LIM')
        return repr(self.value)


TYPES: tuple[Kind, ...] = (Kind.IM, Kind.DKP_INPUT, Kind.DKP_OUTPUT, Kind.LIM, Kind.CONSTRAINT)
"""The classifier's types, in report order (``Analysis.types`` is a subset, in this order)."""

DKP_KINDS: tuple[Kind, ...] = (Kind.DKP_INPUT, Kind.DKP_OUTPUT)
"""The two DKP types, input first."""

LOCUS_KINDS: tuple[Kind, ...] = (Kind.DKP_INPUT, Kind.DKP_OUTPUT, Kind.IM)
"""The kinds of singularity locus a map or an implicit locus draws, in drawing order."""

_DESCRIPTIONS = {
    Kind.IM: "increased mobility (IM)",
    Kind.DKP_INPUT: "dependent kinematic parameters in the input (DKP-input)",
    Kind.DKP_OUTPUT: "dependent kinematic parameters in the output (DKP-output)",
    Kind.LIM: "link impossible motion (LIM)",
    Kind.CONSTRAINT: "a constraint singularity",
    Kind.BRANCH_POINT: "a branch point (IM)",
    Kind.CUSP: "a cusp of the locus' image",
    Kind.MEETING: "a meeting of two singularity loci",
    Kind.FOLD: "the boundary of the assembled region",
    Kind.CLOSED: "the curve closed on its start",
    Kind.BOX: "the curve left the box",
    Kind.END: "the end of the path",
}


def describe(kind: str) -> str:
    """The words a report uses for ``kind`` (a :class:`Kind` or its string)."""
    return _DESCRIPTIONS[Kind(kind)]


_LATEX = {Kind.IM: r"\mathrm{IM}", Kind.DKP_INPUT: r"\mathrm{DKP}_{\mathrm{in}}",
          Kind.DKP_OUTPUT: r"\mathrm{DKP}_{\mathrm{out}}", Kind.LIM: r"\mathrm{LIM}"}


def latex(kind: str) -> str:
    """The LaTeX name of a singularity kind, as conditions and loci print it.

    >>> print(latex("DKP-input"))
    \\mathrm{DKP}_{\\mathrm{in}}
    """
    return _LATEX[Kind(kind)]
