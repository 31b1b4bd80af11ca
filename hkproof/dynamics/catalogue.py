"""The systems of the paper as data: every entry is built by the one QuadraticField constructor."""
from __future__ import annotations

from pathlib import Path

from hkproof.dynamics.field import QuadraticField
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import UnknownSystemError

__all__ = ["CLEBSCH_VARS", "get_system", "kahan_map", "SO4_VARS", "SYSTEMS"]

CLEBSCH_VARS = ("m1", "m2", "m3", "p1", "p2", "p3")

# general flow (eq. "gcl"): m' = m x Cm + p x Bp, p' = p x Cm, c_i from eq. "c thru b"
_C = {"c1": "(b2 - b3)/(w2 - w3)", "c2": "(b3 - b1)/(w3 - w1)", "c3": "(b1 - b2)/(w1 - w2)"}


def _general_flow_rhs(b: dict[str, str], c: dict[str, str]) -> tuple[str, ...]:
    def s(k: str) -> str:
        return f"({b.get(k) or c.get(k)})"
    return (
        f"({s('c3')} - {s('c2')})*m2*m3 + ({s('b3')} - {s('b2')})*p2*p3",
        f"({s('c1')} - {s('c3')})*m3*m1 + ({s('b1')} - {s('b3')})*p3*p1",
        f"({s('c2')} - {s('c1')})*m1*m2 + ({s('b2')} - {s('b1')})*p1*p2",
        f"{s('c3')}*m3*p2 - {s('c2')}*m2*p3",
        f"{s('c1')}*m1*p3 - {s('c3')}*m3*p1",
        f"{s('c2')}*m2*p1 - {s('c1')}*m1*p2",
    )


SYSTEMS: dict[str, QuadraticField] = {}


def _register(f: QuadraticField) -> None:
    SYSTEMS[f.name] = f


_register(QuadraticField(
    "lotka-volterra", ("x", "y"), (), ("x*(1 - y)", "y*(x - 1)"),
    "Lotka-Volterra predator-prey system, eq. \"LV\" (section 2)"))
_register(QuadraticField(
    "euler-top", ("x1", "x2", "x3"), ("a1", "a2", "a3"), ("a1*x2*x3", "a2*x3*x1", "a3*x1*x2"),
    "Euler top, eq. \"ET x\" (section 5); a_k stands for alpha_k"))
_register(QuadraticField(
    "clebsch", CLEBSCH_VARS, ("w1", "w2", "w3"),
    _general_flow_rhs({"b1": "w1", "b2": "w2", "b3": "w3"}, {"c1": "1", "c2": "1", "c3": "1"}),
    "Clebsch system, first flow (section 6); w_k stands for omega_k"))
_register(QuadraticField(
    "clebsch-flow2", CLEBSCH_VARS, ("w1", "w2", "w3"),
    _general_flow_rhs({"b1": "-w2*w3", "b2": "-w3*w1", "b3": "-w1*w2"}, {"c1": "w1", "c2": "w2", "c3": "w3"}),
    "Clebsch system, second flow (H = H2/2; eqs. \"Clebsch 2 b\", \"Clebsch 2 c\")"))
_register(QuadraticField(
    "clebsch-general", CLEBSCH_VARS, ("w1", "w2", "w3", "b1", "b2", "b3"),
    _general_flow_rhs({"b1": "b1", "b2": "b2", "b3": "b3"}, _C),
    "Clebsch system, general flow (eq. \"gcl\") with c_k from eq. \"c thru b\""))


# ---- the atlas beyond the paper (docs/atlas.md: sources and conventions) --------------------------------------
SO4_VARS = ("m12", "m13", "m14", "m23", "m24", "m34")
_register(QuadraticField(
    "so4-euler-top", SO4_VARS, ("a1", "a2", "a3", "a4"),
    ("(a1 - a2)*(m13*m23 + m14*m24)", "-(a1 - a3)*(m12*m23 - m14*m34)", "-(a1 - a4)*(m12*m24 + m13*m34)",
     "(a2 - a3)*(m12*m13 + m24*m34)", "(a2 - a4)*(m12*m14 - m23*m34)", "(a3 - a4)*(m13*m14 + m23*m24)"),
    "Euler top on so(4), Manakov case: M' = [M, Omega], Omega_ij = (a_i + a_j) M_ij"))
_register(QuadraticField(
    "so4-euler-top-flow2", SO4_VARS, ("a1", "a2", "a3", "a4"),
    ("(a1 - a2)*((a1 + a2 + a3)*m13*m23 + (a1 + a2 + a4)*m14*m24)",
     "-(a1 - a3)*((a1 + a2 + a3)*m12*m23 - (a1 + a3 + a4)*m14*m34)",
     "-(a1 - a4)*((a1 + a2 + a4)*m12*m24 + (a1 + a3 + a4)*m13*m34)",
     "(a2 - a3)*((a1 + a2 + a3)*m12*m13 + (a2 + a3 + a4)*m24*m34)",
     "(a2 - a4)*((a1 + a2 + a4)*m12*m14 - (a2 + a3 + a4)*m23*m34)",
     "(a3 - a4)*((a1 + a3 + a4)*m13*m14 + (a2 + a3 + a4)*m23*m24)"),
    "Commuting Manakov flow on so(4): M' = [M, Omega], Omega_ij = (a_i^2 + a_i a_j + a_j^2) M_ij"))
# so(4) = so(3) + so(3): the same Manakov flow in the self-dual / anti-self-dual coordinates u, v (a linear chart,
# checked by hkproof.hk.conjugacy; only b1, b2, b3 of the a_i enter)
SO4_SPLIT = {"u1": "m23 + m14", "u2": "m24 - m13", "u3": "m12 + m34",
             "v1": "m23 - m14", "v2": "-m13 - m24", "v3": "m12 - m34",
             "b1": "(a1 + a2 - a3 - a4)/2", "b2": "(a1 - a2 + a3 - a4)/2", "b3": "(a1 - a2 - a3 + a4)/2"}
_register(QuadraticField(
    "so4-euler-top-split", ("u1", "u2", "u3", "v1", "v2", "v3"), ("b1", "b2", "b3"),
    ("-b1*u2*v3 + b2*u3*v2", "b1*u1*v3 + b3*u3*v1", "-b2*u1*v2 - b3*u2*v1",
     "b2*u2*v3 - b1*u3*v2", "b3*u1*v3 + b1*u3*v1", "-b3*u1*v2 - b2*u2*v1"),
    "Euler top on so(4), Manakov case, in the coordinates of so(4) = so(3) + so(3): u = (m23 + m14, m24 - m13, "
    "m12 + m34), v = (m23 - m14, -m13 - m24, m12 - m34), b1 = (a1 + a2 - a3 - a4)/2, b2 = (a1 - a2 + a3 - a4)/2, "
    "b3 = (a1 - a2 - a3 + a4)/2"))
# the commuting flow in the same chart: b1, b2, b3 as above and s = a1 + a2 + a3 + a4 (checked by hk.conjugacy)
SO4_SPLIT_FLOW2 = {**SO4_SPLIT, "s": "a1 + a2 + a3 + a4"}
_register(QuadraticField(
    "so4-euler-top-flow2-split", ("u1", "u2", "u3", "v1", "v2", "v3"), ("b1", "b2", "b3", "s"),
    ("-(2*(b1**2 - b2**2)*u2*u3 - 2*b1*b3*u3*v2 + (3*b1*s + 2*b2*b3)*u2*v3 - 3*b2*s*u3*v2)/4",
     "(2*(b1**2 - b3**2)*u1*u3 + (2*b1*b2 + 3*b3*s)*u3*v1 + (3*b1*s + 2*b2*b3)*u1*v3)/4",
     "-(2*(b2**2 - b3**2)*u1*u2 + (2*b1*b2 + 3*b3*s)*u2*v1 + (2*b1*b3 + 3*b2*s)*u1*v2)/4",
     "(-2*(b1**2 - b2**2)*v2*v3 + 2*b1*b3*u2*v3 - (3*b1*s + 2*b2*b3)*u3*v2 + 3*b2*s*u2*v3)/4",
     "(2*(b1**2 - b3**2)*v1*v3 + (2*b1*b2 + 3*b3*s)*u1*v3 + (3*b1*s + 2*b2*b3)*u3*v1)/4",
     "-(2*(b2**2 - b3**2)*v1*v2 + (2*b1*b2 + 3*b3*s)*u1*v2 + (2*b1*b3 + 3*b2*s)*u2*v1)/4"),
    "Commuting Manakov flow on so(4) in the chart so(4) = so(3) + so(3) of so4-euler-top-split, with "
    "s = a1 + a2 + a3 + a4"))


def _volterra(n: int) -> QuadraticField:
    x = [f"x{k}" for k in range(1, n + 1)]
    return QuadraticField(f"volterra-{n}", tuple(x), (),
                          tuple(f"{x[k]}*({x[(k + 1) % n]} - {x[k - 1]})" for k in range(n)),
                          f"Periodic Volterra lattice, N = {n}: x_k' = x_k (x_(k+1) - x_(k-1)), indices mod {n}")


for _n in (3, 4, 5):
    _register(_volterra(_n))
_register(QuadraticField(
    "toda-3", ("a1", "a2", "a3", "b1", "b2", "b3"), (),
    ("a1*(b2 - b1)", "a2*(b3 - b2)", "a3*(b1 - b3)",
     "2*(a1**2 - a3**2)", "2*(a2**2 - a1**2)", "2*(a3**2 - a2**2)"),
    "Periodic Toda lattice, N = 3, Flaschka variables: a_k' = a_k (b_(k+1) - b_k), b_k' = 2 (a_k^2 - a_(k-1)^2)"))
_register(QuadraticField(
    "gaudin-2", ("s1", "s2", "s3", "t1", "t2", "t3"), ("b", "g"),
    ("s2*b + g*(s2*t3 - s3*t2)", "-s1*b + g*(s3*t1 - s1*t3)", "g*(s1*t2 - s2*t1)",
     "g*(t2*s3 - t3*s2)", "g*(t3*s1 - t1*s3)", "g*(t1*s2 - t2*s1)"),
    "Classical rational Gaudin magnet, two spins s, t in the field (0, 0, b), flow of "
    "H = b s3 + g <s, t>: s' = s x (B + g t), t' = g t x s"))
_register(QuadraticField(
    "kirchhoff", CLEBSCH_VARS, ("a", "a3", "b", "b3"),
    ("(a3 - a)*m2*m3 + (b3 - b)*p2*p3", "(a - a3)*m3*m1 + (b - b3)*p3*p1", "0",
     "a3*p2*m3 - a*p3*m2", "a*p3*m1 - a3*p1*m3", "a*(p1*m2 - p2*m1)"),
    "Kirchhoff case of a rigid body in an ideal fluid: m' = m x dH/dm + p x dH/dp, p' = p x dH/dm, "
    "H = (a (m1^2 + m2^2) + a3 m3^2 + b (p1^2 + p2^2) + b3 p3^2)/2"))




def _gyrostat(name: str, beta: tuple[str, str, str], what: str) -> QuadraticField:
    """x' = x X (A x + beta): the quadratic part of the Euler top plus the cross product with the moment beta (a zero
    entry of beta is left out)."""
    x = ("x1", "x2", "x3")
    rhs = []
    for i in range(3):
        j, k = (i + 1) % 3, (i + 2) % 3
        terms = [f"(a{j + 1} - a{k + 1})*{x[j]}*{x[k]}"]
        terms += [f"{sign}{beta[m]}*{x[n]}" for sign, m, n in ((" + ", k, j), (" - ", j, k)) if beta[m] != "0"]
        rhs.append("".join(terms))
    return QuadraticField(name, x, ("a1", "a2", "a3") + tuple(b for b in beta if b != "0"), tuple(rhs),
                          f"Zhukovsky-Volterra gyrostat, {what}: x' = x X (A x + beta), A = diag(a1, a2, a3)")


_register(QuadraticField(
    "lagrange-top", CLEBSCH_VARS, ("a",),
    ("(a - 1)*m2*m3 + p2", "(1 - a)*m3*m1 - p1", "0", "a*p2*m3 - p3*m2", "p3*m1 - a*p1*m3", "p1*m2 - p2*m1"),
    "Lagrange top (Kimura-Hirota): m' = m x dH/dm + p x dH/dp, p' = p x dH/dm, "
    "H = (m1^2 + m2^2 + a m3^2)/2 + p3"))
_register(_gyrostat("zhukovsky-volterra", ("b1", "b2", "b3"), "beta = (b1, b2, b3)"))
_register(_gyrostat("zhukovsky-volterra-1", ("b1", "0", "0"), "one gyrostatic moment, beta = (b1, 0, 0)"))


def get_system(name_or_path: str) -> QuadraticField:
    """A catalogue system by name, or a user's system from a TOML file."""
    if name_or_path in SYSTEMS:
        return SYSTEMS[name_or_path]
    path = Path(name_or_path)
    if path.suffix == ".toml" or path.exists():
        return QuadraticField.from_toml(path)
    raise UnknownSystemError(
        f"unknown system '{name_or_path}': use one of {sorted(SYSTEMS)} or the path of a TOML file")


_MAPS: dict[QuadraticField, KahanMap] = {}


def kahan_map(system: str | QuadraticField) -> KahanMap:
    """The Kahan map of a system (catalogue name, TOML path or field); built once per field."""
    field = get_system(system) if isinstance(system, str) else system
    if field not in _MAPS:
        _MAPS[field] = KahanMap(field)
    return _MAPS[field]
