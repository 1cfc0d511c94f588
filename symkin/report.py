"""Text and Markdown renderings of an :class:`~symkin.analysis.classification.Analysis`.

Only reads results; never computes.  JSON is ``Analysis.to_dict()``.
"""
from __future__ import annotations

from symkin.kinds import Kind, describe

__all__ = ["render_text", "render_markdown", "LISTED", "SUMMARISED", "LARGEST"]

#: self-stresses (and relations) listed in full in the text report up to this many; beyond,
#: the report gives their number and, for the first :data:`SUMMARISED`, the constraints with
#: the :data:`LARGEST` largest coefficients (a large model's thousands of stresses would bury
#: the report; ``--json`` lists every one, every coefficient)
LISTED = 20
SUMMARISED = 5
LARGEST = 4



def _vec(v) -> str:
    return "(" + ", ".join(f"{c:+.4g}" for c in v) + ")"


def _rank_sentence(which: str, labels, rank: int, f: int, dkp: bool) -> str:
    n = len(labels)
    if dkp:
        return f"The {which} {', '.join(labels)} are dependent: rank {rank} < min(F, {n}) = {min(f, n)}."
    if rank == n:
        return f"The {which} are independent (rank {rank})."
    return (f"The {which} have rank {rank}, not below min(F, {n}) = {min(f, n)}: no DKP; "
            f"{n - rank} relation(s) among them hold as expected:")


def _plural(k: int, word: str) -> str:
    return f"{k} {word}" + ("" if k == 1 else "es" if word.endswith("x") else "s")


def _structure_sentences(a) -> list[str]:
    """A structure (F = 0): rigid, or flexible with L infinitesimal flexes; no inputs or outputs."""
    L = a.dof
    if L == 0:
        out = ["The structure is rigid (L = 0, no infinitesimal flex): the configuration is not singular."]
    else:
        out = [f"The structure is flexible: {_plural(L, 'infinitesimal flex')} (L = {L} > F = 0); "
               "the configuration is singular: increased mobility (IM)."]
    if a.im_indicator is not None:
        out.append(f"Rigidity indicator (smallest eigenvalue λ_1 of the reduced geometric matrix): "
                   f"{a.im_indicator:.6g}.")
    if L and a.locked_links:
        out.append(f"Links that no flex moves: {', '.join(a.locked_links)}.")
    return out


def _mechanism_sentences(a) -> list[str]:
    out = []
    f, L = a.mobility, a.dof
    if a.types:
        out.append("The configuration is singular: " + ", ".join(describe(t) for t in a.types) + ".")
    else:
        out.append("The configuration is not singular.")
    if L > f:
        out.append(f"The instantaneous DOF is L = {L}, above the full-cycle mobility F = {f}: "
                   f"{L - f} extra instantaneous motion(s).")
    else:
        out.append(f"The instantaneous DOF is L = {L}, equal to the full-cycle mobility F = {f}."
                   if L == f else f"The instantaneous DOF is L = {L}, below F = {f} "
                   "(check 'mobility' in the model).")
    if a.im_indicator is not None:
        out.append(f"IM indicator (eigenvalue λ_{f + 1} of the reduced geometric matrix): {a.im_indicator:.6g}.")
    if a.input_rank is not None:
        out.append(_rank_sentence("inputs", a.input_labels, a.input_rank, f, Kind.DKP_INPUT in a.types))
        out += _listed(a.input_relations, lambda n, r: f"  input relation (r = {r.r}): {r}", "input relations", "input relation")
    if a.output_rank is not None:
        out.append(_rank_sentence("outputs", a.output_labels, a.output_rank, f, Kind.DKP_OUTPUT in a.types))
        out += _listed(a.output_relations, lambda n, r: f"  output relation (r = {r.r}): {r}", "output relations", "output relation")
    if a.locked_links:
        out.append(f"Locked links (no motion whatever the inputs): {', '.join(a.locked_links)}.")
    if a.locked_nodes:
        out.append(f"Motionless free nodes: {', '.join(a.locked_nodes)}.")
    return out


def _stress(rel) -> str:
    return ", ".join(f"{label} {c:+.4g}" for label, c in rel.coefficients)


def _largest(rel) -> str:
    """The :data:`LARGEST` largest coefficients of a relation, largest first, and how many there are."""
    top = sorted(rel.coefficients, key=lambda lc: -abs(lc[1]))[:LARGEST]
    more = f", … ({rel.r} constraints)" if rel.r > len(top) else ""
    return ", ".join(f"{label} {c:+.4g}" for label, c in top) + more


def _listed(items, line, what: str, one: str) -> list[str]:
    """``line(k, item)`` for each item, or, beyond :data:`LISTED`, a summary of the first few."""
    n = len(items)
    if n <= LISTED:
        return [line(k, items[k - 1]) for k in range(1, n + 1)]
    out = [f"  ({n} {what}: more than {LISTED}, so the first {SUMMARISED} are shown by their {LARGEST} "
           f"largest coefficients; --json lists all of them in full)"]
    return out + [f"  {one} {k}: {_largest(items[k - 1])}" for k in range(1, SUMMARISED + 1)]


def _statics_sentences(a) -> list[str]:
    """Redundant constraints and their self-stresses (forces up to a common factor, tension +)."""
    k = a.redundant_constraints
    if k == 0:
        return ["No self-stress: the structure is statically determinate."] if a.structure and a.dof == 0 else []
    if not len(a.self_stresses):  # a large model whose stresses are counted, not listed (see the warnings)
        return [f"{_plural(k, 'redundant constraint')} (self-stresses counted, not listed: see the warning)."]
    shown = a.self_stresses if len(a.self_stresses) <= LISTED else a.self_stresses[:SUMMARISED]
    labels = [label for r in shown for label, _ in r.coefficients]
    bars = all("[" not in x and ":" not in x for x in labels)
    # the link (or slider) that owns each row: coupler[B-C] → coupler, slider:s → slider s
    owners = dict.fromkeys(x.replace("slider:", "slider ").split("[")[0].split(":rigidity")[0] for x in labels)
    where = ("bars " if bars else "") + ", ".join(owners)
    head = f"{_plural(k, 'redundant constraint')}: " + (f"a self-stress in {where}" if k == 1 else
                                                          f"{k} independent self-stresses in {where}"
                                                          if len(a.self_stresses) <= LISTED else
                                                          f"{k} independent self-stresses")
    out = [head + " (forces up to a common factor, tension positive):"]
    out += _listed(a.self_stresses, lambda n, r: f"  self-stress {n}: {_stress(r)}", "self-stresses", "self-stress")
    return out


#: what each decision compares with its threshold
_DECIDED = {"rank": "rank of the constraint matrix", Kind.IM: "IM: (F+1)-th smallest singular value",
            Kind.DKP_INPUT: "DKP-input: min(F, k)-th singular value of the restricted inputs",
            Kind.DKP_OUTPUT: "DKP-output: min(F, k)-th singular value of the restricted outputs"}


def _decision(name: str, value: float, threshold: float, margin: float) -> str:
    side = "above" if value > threshold else "below"
    times = "∞" if margin == float("inf") else f"{margin:.3g}"
    return f"{_DECIDED.get(name, name)} {value:.3g}, {side} {threshold:.3g}: ×{times}"


def _sentences(a) -> list[str]:
    out = _structure_sentences(a) if a.structure else _mechanism_sentences(a)
    if a.platform is not None:
        msg = f"The platform (link {a.platform}) has {a.platform_dof} instantaneous DOF (generic {a.platform_dof_generic})"
        msg += "; this exceeds the generic DOF: constraint singularity." if Kind.CONSTRAINT in a.types else "."
        out.append(msg)
        out += _listed(a.platform_relations, lambda n, r: f"  platform relation (r = {r.r}): {r}", "platform relations", "platform relation")
    if a.uncontrolled_motions:
        out.append(f"With every input locked, {len(a.uncontrolled_motions)} uncontrolled motion(s) remain "
                   "(nodal velocities, scaled to a largest component of 1):")
        for k, m in enumerate(a.uncontrolled_motions, 1):
            moving = [f"{n} {_vec(v)}" for n, v in m.velocities if max(abs(c) for c in v) > a.tolerance]
            flags = []
            if m.moves_outputs is not None:
                flags.append("moves the outputs" if m.moves_outputs else "does not move the outputs")
            if m.moves_platform is not None:
                flags.append("moves the platform" if m.moves_platform else "does not move the platform")
            out.append(f"  motion {k}: " + ", ".join(moving) + (f" — {'; '.join(flags)}" if flags else ""))
    if not a.structure and (a.gosselin_angeles or a.zlatanov):
        parts = []
        if a.gosselin_angeles:
            parts.append(f"Gosselin–Angeles {a.gosselin_angeles}")
        if a.zlatanov:
            parts.append("Zlatanov " + ", ".join(a.zlatanov))
        out.append("In other classifications: " + "; ".join(parts) + ".")
    sv = ", ".join(f"{s:.3g}" for s in a.singular_values)
    margin = "∞" if a.margin is None or a.margin == float("inf") else f"{a.margin:.3g}"
    out.append(f"Decision: singular values of the constraint matrix (smallest first) {sv}; "
               f"zero below {a.threshold:.3g} (tolerance {a.tolerance:g} × largest); margin ×{margin}.")
    if a.dkp_input is not None or a.dkp_output is not None:
        values = [f"{side} {v:+.6g}" for side, v in (("input", a.dkp_input), ("output", a.dkp_output))
                  if v is not None]
        out.append("DKP values (signed; they change sign through a DKP configuration): " + ", ".join(values) + ".")
    if getattr(a, "decisions", ()):
        out.append("Margins of the decisions (value / threshold, or threshold / value for a zero): "
                   + "; ".join(_decision(*d) for d in a.decisions) + ".")
    out += _statics_sentences(a)
    out += [f"Warning: {w}" for w in a.warnings]
    return out


def render_text(a) -> str:
    """Plain-text report of an analysis, in sentences."""
    head = f"{a.name} ({'planar' if a.dim == 2 else 'spatial'})"
    return "\n".join([head, "=" * len(head)] + _sentences(a)) + "\n"


def render_markdown(a) -> str:
    """Markdown report (used by ``symkin reproduce``)."""
    lines = [f"**{a.name}** — types: {', '.join(a.types) or 'none'}; L = {a.dof}, F = {a.mobility}", ""]
    lines += [f"- {s.strip()}" for s in _sentences(a)]
    return "\n".join(lines)
