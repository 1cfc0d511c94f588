"""C for an SX Function evaluated at several configurations at once, lane by lane (SIMD).

CasADi's generated C evaluates a mapped Function one configuration after another: the
scalar code of the indicator kernel (about 3,500 instructions for the 3-RRR, mostly
multiplications, additions and selections) runs at about one instruction per cycle.
:func:`lanes_source` writes the same instruction list — CasADi's own algorithm of the
Function (``Function.instruction_id`` and friends), in CasADi's order — with every work
variable a vector of ``lanes`` doubles (GCC/Clang vector extensions), so one instruction
serves ``lanes`` configurations.

Every operation is the IEEE operation CasADi's C performs (``+ - * /``, ``sqrt``, and the
selections, comparisons and ``fmax``/``fmin`` of CasADi's runtime with C99 semantics:
``fmax(x, NaN) = x``, and the second argument on a tie of signed zeros, as x86-64 glibc;
on other platforms the sign of a zero from such a tie may differ), in the same order, so with the
same compiler flags (``-ffp-contract=off``: no fused multiply-add) each lane gives the
scalar code's result bit for bit; the tests check it.  A Function with an operation not
listed in :data:`SUPPORTED` gets no vector source (``None``) and keeps CasADi's loop.

The vector code replaces the bodies of a generated Function and of its ``*_batch`` map
(see :func:`patch`: one configuration is one partial group of lanes), guarded by
:data:`GUARD`: another compiler than GCC or Clang, or ``-DSYMKIN_NO_VECTOR``, keeps
CasADi's bodies.

Examples
--------
>>> import casadi as ca
>>> x = ca.SX.sym("x", 2)
>>> f = ca.Function("f", [x], [ca.sqrt(x[0] * x[0] + x[1] * x[1])])
>>> src = lanes_source(f, "f_lanes")
>>> "sk_f_lanes(const casadi_real** arg, casadi_real** res, casadi_int n)" in src
True
"""
from __future__ import annotations

import math
import re

import casadi as ca

__all__ = ["lanes_source", "patch", "patch_batch", "SUPPORTED", "GUARD"]

#: the vector code is compiled by GCC and Clang (vector extensions) unless SYMKIN_NO_VECTOR is
#: defined (``-DSYMKIN_NO_VECTOR``: CasADi's scalar bodies, the same numbers)
GUARD = "defined(__GNUC__) && !defined(SYMKIN_NO_VECTOR)"

_BIN = {ca.OP_ADD: "+", ca.OP_SUB: "-", ca.OP_MUL: "*", ca.OP_DIV: "/"}
_CMP = {ca.OP_LT: "<", ca.OP_LE: "<=", ca.OP_EQ: "==", ca.OP_NE: "!="}
#: CasADi operations translated (everything the indicator kernel uses)
SUPPORTED = frozenset([*_BIN, *_CMP, ca.OP_NEG, ca.OP_SQ, ca.OP_TWICE, ca.OP_INV, ca.OP_SQRT, ca.OP_FABS,
                       ca.OP_FMAX, ca.OP_FMIN, ca.OP_NOT, ca.OP_AND, ca.OP_OR, ca.OP_IF_ELSE_ZERO,
                       ca.OP_SIGN, ca.OP_CONST, ca.OP_INPUT, ca.OP_OUTPUT, ca.OP_ASSIGN])


_PRELUDE = """
#if defined(__AVX512F__)
#define SK_LANES 8
#elif defined(__AVX__)
#define SK_LANES 4
#else
#define SK_LANES 2
#endif
typedef double sk_v __attribute__((vector_size(8 * SK_LANES)));
typedef long long sk_m __attribute__((vector_size(8 * SK_LANES)));
/* comparisons give -1 / 0 per lane; the casts name the mask type (GCC and Clang differ in it) */
/* constants in every lane (initialisers: exact for -0, inf and NaN, and cheap to compile) */
#if SK_LANES == 2
#define sk_splat(c) ((sk_v){(c), (c)})
#define sk_msplat(c) ((sk_m){(c), (c)})
#elif SK_LANES == 4
#define sk_splat(c) ((sk_v){(c), (c), (c), (c)})
#define sk_msplat(c) ((sk_m){(c), (c), (c), (c)})
#else
#define sk_splat(c) ((sk_v){(c), (c), (c), (c), (c), (c), (c), (c)})
#define sk_msplat(c) ((sk_m){(c), (c), (c), (c), (c), (c), (c), (c)})
#endif
static inline sk_v sk_sel(sk_m m, sk_v a, sk_v b) { return (sk_v)(((sk_m)a & m) | ((sk_m)b & ~m)); }
static inline sk_v sk_bool(sk_m m) { return (sk_v)(m & sk_msplat(0x3ff0000000000000LL)); }
static inline sk_v sk_fabs(sk_v x) { return (sk_v)((sk_m)x & sk_msplat(0x7fffffffffffffffLL)); }
static inline sk_v sk_sqrt(sk_v x) { sk_v r; int l; for (l = 0; l < SK_LANES; ++l) r[l] = sqrt(x[l]); return r; }
/* C99 fmax / fmin as x86-64 glibc (maxsd / minsd): the second argument on ties such as
   (+0, -0), the other argument when one is NaN */
static inline sk_v sk_fmax(sk_v x, sk_v y) {
  return sk_sel((sk_m)(x > y), x, sk_sel((sk_m)(x <= y), y, sk_sel((sk_m)(y != y), x, y)));
}
static inline sk_v sk_fmin(sk_v x, sk_v y) {
  return sk_sel((sk_m)(x < y), x, sk_sel((sk_m)(x >= y), y, sk_sel((sk_m)(y != y), x, y)));
}
/* casadi_sign: x<0 ? -1 : x>0 ? 1 : x */
static inline sk_v sk_sign(sk_v x) {
  return sk_sel((sk_m)(x < 0), sk_splat(-1.), sk_sel((sk_m)(x > 0), sk_splat(1.), x));
}
/* lane l reads configuration c[l] (its input i has `stride` entries); a NULL input reads zeros */
static inline sk_v sk_load(const casadi_real* a, const casadi_int* c, casadi_int stride, casadi_int nz) {
  sk_v r; int l; for (l = 0; l < SK_LANES; ++l) r[l] = a ? a[c[l] * stride + nz] : 0; return r;
}
static inline void sk_store(casadi_real* r, sk_v v, casadi_int b, int live, casadi_int stride, casadi_int nz) {
  int l; if (r) for (l = 0; l < live; ++l) r[(b + l) * stride + nz] = v[l];
}
"""


def _literal(value: float) -> str:
    if math.isnan(value):
        return "NAN"
    if math.isinf(value):
        return "INFINITY" if value > 0 else "-INFINITY"
    return value.hex()


def _expr(op: int, a: list[str], const: float) -> str:
    if op in _BIN:
        return f"{a[0]} {_BIN[op]} {a[1]}"
    if op in _CMP:
        return f"sk_bool((sk_m)({a[0]} {_CMP[op]} {a[1]}))"
    unary = {ca.OP_NEG: "-{0}", ca.OP_SQ: "{0} * {0}", ca.OP_TWICE: "2. * {0}", ca.OP_INV: "1. / {0}",
             ca.OP_SQRT: "sk_sqrt({0})", ca.OP_FABS: "sk_fabs({0})", ca.OP_SIGN: "sk_sign({0})",
             ca.OP_NOT: "sk_bool((sk_m)({0} == 0))", ca.OP_ASSIGN: "{0}"}
    if op in unary:
        return unary[op].format(*a)
    binary = {ca.OP_FMAX: "sk_fmax({0}, {1})", ca.OP_FMIN: "sk_fmin({0}, {1})",
              ca.OP_AND: "sk_bool((sk_m)({0} != 0) & (sk_m)({1} != 0))",
              ca.OP_OR: "sk_bool((sk_m)({0} != 0) | (sk_m)({1} != 0))",
              ca.OP_IF_ELSE_ZERO: "(sk_v)((sk_m){1} & (sk_m)({0} != 0))"}
    if op in binary:
        return binary[op].format(*a)
    if op == ca.OP_CONST:
        return f"sk_splat({_literal(const)})"
    raise ValueError(op)


def lanes_source(f: ca.Function, name: str) -> str | None:
    """C of ``static int sk_<name>(arg, res, n)``: ``f`` at ``n`` configurations, ``SK_LANES`` at a time.

    ``arg[i]`` holds ``n`` consecutive copies of input ``i`` (each ``f.numel_in(i)``
    doubles, as a mapped Function's inputs), ``res[i]`` likewise for output ``i``; a
    NULL ``arg[i]`` reads zeros and a NULL ``res[i]`` is skipped, as CasADi's C does.
    The width follows the target the compiler flags enable: 8 doubles with AVX-512, 4
    with AVX, else 2 (SSE2, the x86-64 baseline; NEON on ARM).  The last, partial group
    of lanes repeats the last configuration and stores only the lanes that exist.
    Returns ``None`` when ``f`` is not an SX Function or uses an operation outside
    :data:`SUPPORTED`.
    """
    if not f.is_a("SXFunction"):
        return None
    ops = [f.instruction_id(k) for k in range(f.n_instructions())]
    if any(op not in SUPPORTED for op in ops):
        return None
    size_in = [f.numel_in(i) for i in range(f.n_in())]
    size_out = [f.numel_out(i) for i in range(f.n_out())]
    lines = []
    for k, op in enumerate(ops):
        ins, outs = f.instruction_input(k), f.instruction_output(k)
        if op == ca.OP_INPUT:
            i, nz = ins
            lines.append(f"    w{outs[0]} = sk_load(arg[{i}], c, {size_in[i]}, {nz});")
        elif op == ca.OP_OUTPUT:
            i, nz = outs
            lines.append(f"    sk_store(res[{i}], w{ins[0]}, b, live, {size_out[i]}, {nz});")
        else:
            args = [f"w{j}" for j in ins]
            lines.append(f"    w{outs[0]} = {_expr(op, args, f.instruction_constant(k))};")
    decl = "    sk_v " + ", ".join(f"w{j}" for j in range(max(f.sz_w(), 1))) + ";"
    return "\n".join([
        _PRELUDE,
        f"static int sk_{name}(const casadi_real** arg, casadi_real** res, casadi_int n) {{",
        "  casadi_int b, c[SK_LANES];",
        "  int l, live;",
        "  for (b = 0; b < n; b += SK_LANES) {",
        "    live = n - b < SK_LANES ? (int)(n - b) : SK_LANES;",
        "    for (l = 0; l < SK_LANES; ++l) c[l] = l < live ? b + l : n - 1;",
        decl,
        *lines,
        "  }",
        "  return 0;",
        "}",
    ]) + "\n"


def patch(c_text: str, f: ca.Function, entries: dict[str, int]) -> str:
    """Replace the bodies of the exported Functions ``entries`` by the vector loop of ``f``.

    ``entries`` maps the name of each exported Function generated by CasADi into
    ``c_text`` to its number of configurations: ``f`` itself (1) and its
    ``Function.map(..., "serial", n)`` (n).  Each entry point keeps CasADi's signature
    and calls one ``sk_<f>`` under :data:`GUARD` (else CasADi's bodies).  The
    scalar code is then unreferenced and the compiler drops it, so the kernel is compiled
    once.  ``c_text`` is returned unchanged when ``f`` cannot be translated.
    """
    src = lanes_source(f, f.name())
    if src is None:
        return c_text
    first = None
    for exported, size in entries.items():
        head = re.compile(r"(CASADI_SYMBOL_EXPORT int " + re.escape(exported)
                          + r"\(const casadi_real\*\* arg, casadi_real\*\* res, casadi_int\* iw, "
                            r"casadi_real\* w, int mem\)\{\n)(  return [^\n]*\n)(\})")
        m = head.search(c_text)
        if m is None:
            raise ValueError(f"no exported function {exported!r} in the generated C")
        body = f"#if {GUARD}\n  return sk_{f.name()}(arg, res, {size});\n#else\n{m.group(2)}#endif\n"
        c_text = c_text[:m.start()] + m.group(1) + body + m.group(3) + c_text[m.end():]
        first = m.start() if first is None else min(first, m.start())
    return c_text[:first] + f"#if {GUARD}\n" + src + "#endif\n\n" + c_text[first:]


def patch_batch(c_text: str, exported: str, f: ca.Function, size: int) -> str:
    """:func:`patch` of one mapped Function ``exported`` (``size`` configurations) of ``f``."""
    return patch(c_text, f, {exported: size})
