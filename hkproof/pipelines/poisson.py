"""`poisson`: invariant Poisson bivectors Pi = Q / D of a Kahan map, searched mod p, rebuilt, proven, or excluded.

For each candidate denominator D and each degree d = 0, 1, ... up to the asked one, the invariance rows
Q(f(x)) D(x) = D(f(x)) Df Q(x) Df^T (hkproof.hk.poisson_system) at random points mod p, one block per character of the
map's sign symmetries, have their rank computed by FLINT. Full column rank in every block at the last degree is a
theorem (the class is excluded, hkproof.hk.poisson_proofs.exclusion_certificate); a kernel at the lowest degree d is
rebuilt with eps and the parameters symbolic by sparse functional reconstruction (its rref basis is canonical), and
each basis bivector is proven invariant, tested for Jacobi, its rank and Casimirs, pairs for compatibility, and the
integrals `discover` proves for involution (hkproof.hk.poisson_proofs).

With a torus (a linear symmetry diagonalized mod p) the ranks are taken on its weight blocks; a kernel seen in weight 0
only is rebuilt on the bivectors fixed by the symmetry's flow, a basis over Z in the field's coordinates
(hkproof.hk.fixed_columns), any other kernel on the sign blocks.
"""
from __future__ import annotations

import dataclasses
import itertools
import random
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable, Mapping, Sequence, TypeVar

import flint
import numpy as np

from hkproof.algebra.fraction import Frac, poly_str
from hkproof.algebra.linalg import lcm
from hkproof.algebra.modular import free_kernel_mod_p, nmod_matrix, random_prime
from hkproof.algebra.monomials import Exponents
from hkproof.algebra.reconstruction import memoized_values, reconstruct
from hkproof.algebra.ring import get_ring
from hkproof.algebra.sampling import random_point
from hkproof.budget import Budget, current
from hkproof.dynamics.field import EPS, STEP_CONVENTION
from hkproof.dynamics.kahan import KahanMap
from hkproof.dynamics.modular_map import ModularKahanMap
from hkproof.errors import BudgetExhausted, HKProofError, SingularSystemError, UnluckyPrimeError
from hkproof.experiments.weights import Weights, scaling_weights
from hkproof.hk.fixed_columns import FixedColumns, commutes_with_signs, fixed_columns
from hkproof.hk.jacobian import matrix_identity_holds
from hkproof.hk.nambu import NambuStructure, prove_nambu
from hkproof.hk.poisson import Bivector, brackets_independent_mod, pairs
from hkproof.hk.poisson_proofs import (BlockRank, StructureProof, compatibility_step, exclusion_certificate,
                                       involution_certificate, kernel_certificate, no_poisson_certificate,
                                       prove_structure)
from hkproof.hk.poisson_system import (Block, SignSymmetry, blocks, denominator_character, factored_mod,
                                       sign_symmetries, system_mod_p)
from hkproof.hk.torus import (Torus, commuting_linear_fields, eigen_coordinates, generic_generator, is_semi_invariant,
                              semi_invariance_character, torus_data)
from hkproof.pipelines.poisson_candidates import Denominator, candidate_denominators
from hkproof.pipelines.slices import Slice
from hkproof.pipelines.stages import Progress, Stages
from hkproof.proof.certificate import Certificate
from hkproof.proof.status import Status, specialized_label

if TYPE_CHECKING:
    from hkproof.pipelines.darboux import DarbouxSearch

__all__ = ["ExcludedClass", "MAX_POISSON_DEGREE", "NoPoisson", "PoissonReport", "ScreenedKernel", "search_poisson",
           "with_integrals"]

MAX_POISSON_DEGREE = 12
DENSE_MAX_DEGREE = 64
"""The largest degree of a coordinate in its one sampled control that the dense reconstruction takes."""
MAX_NO_POISSON_KERNEL = 6
"""The largest kernel whose members are tested for Jacobi together (its brackets: 21 at most)."""
Integrals = Callable[[KahanMap], list[tuple[str, Frac]]]
T = TypeVar("T", Frac, int)


@dataclass
class ExcludedClass:
    """A class Q/D, deg Q <= degree, with no invariant bivector: full column rank mod p in every block."""
    name: str
    denominator: flint.fmpz_mpoly
    text: str                       # D as the product of its factors (hkproof's parser reads it)
    degree: int
    prime: int
    values: dict[str, flint.fmpq]
    blocks: list[BlockRank]
    symmetries: list[SignSymmetry]
    certificate: Certificate
    torus: Torus | None = None


@dataclass
class NoPoisson:
    """The top degree's kernel in the field's coordinates: one block per sign character holding part of it (rank and
    points), the other characters' blocks (full column rank), and whether a member may satisfy Jacobi mod p (the
    brackets of the members are dependent); when none can, the certificate of "no invariant Q/D of the class is
    Poisson"."""
    kernels: list[BlockRank]      # one per sign character holding part of the kernel
    others: list[BlockRank]
    poisson_mod_p: bool
    certificate: Certificate | None
    prime: int
    values: dict[str, flint.fmpq]
    symmetries: list[SignSymmetry]
    torus: Torus | None
    fixed: list[bool]       # per kernel block: solved on the bivectors fixed by the torus' flow


@dataclass
class ScreenedKernel:
    """A class whose invariance rows have a kernel mod p at `degree` (the lowest; `--screen`: not rebuilt), with the
    test of the top degree's kernel (`member`, `_kernel_member`): whether a member may satisfy Jacobi mod p, and when
    none can, the theorem that the class has no invariant Poisson structure."""
    name: str
    text: str
    degree: int
    dimension: int
    certificate: Certificate
    member: NoPoisson | None = None
    rebuilt: bool = False       # found by the full search (its structures are rebuilt and listed), not --screen

    @property
    def jacobi_mod_p(self) -> bool | None:
        """False: no member of the top degree's kernel satisfies Jacobi mod p; True: one may; None: not tested."""
        return None if self.member is None else self.member.poisson_mod_p

    @property
    def no_poisson(self) -> Certificate | None:
        """The verified certificate "no invariant Poisson Q/D in this class", if there is one."""
        cert = None if self.member is None else self.member.certificate
        return cert if cert is not None and cert.status.is_verified else None


@dataclass
class PoissonReport:
    """Everything `hkproof poisson` reports (JSON: docs/poisson.md)."""
    system: str
    variables: list[str]
    degree: int
    structures: list[StructureProof] = field(default_factory=list)
    excluded: list[ExcludedClass] = field(default_factory=list)
    compatibility: list[tuple[int, int, bool]] = field(default_factory=list)
    integrals: list[tuple[str, Frac]] = field(default_factory=list)
    involution: list[tuple[int, Certificate]] = field(default_factory=list)
    costs: list[dict[str, Any]] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    fixed: dict[str, flint.fmpq] = field(default_factory=dict)
    seconds: dict[str, float] = field(default_factory=dict)
    stopped: str = ""
    kernels: list[ScreenedKernel] = field(default_factory=list)     # --screen: classes with a kernel; or no-poisson
    nambu: list[NambuStructure] = field(default_factory=list)      # P W(grad I): from the integrals and a density

    @property
    def complete(self) -> bool:
        return not self.stopped

    def to_dict(self) -> dict[str, Any]:
        """The JSON of `hkproof poisson`."""
        label = lambda status: specialized_label(status, self.fixed)  # noqa: E731
        return {
            "system": self.system, "degree": self.degree, "eps_convention": STEP_CONVENTION,
            "fixed": {k: str(v) for k, v in self.fixed.items()},
            "structures": [{"name": f"Pi{k + 1}", "matrix": s.bivector.texts(), "status": label(s.status),
                            "poisson": s.poisson, "rank": s.rank, "casimirs": [str(c) for _, c in s.casimirs],
                            "casimir_names": [n for n, _ in s.casimirs], "denominator": poly_str(s.bivector.denominator),
                            "certificate": s.certificate.to_dict()} for k, s in enumerate(self.structures)],
            "compatible": [{"pair": [f"Pi{a + 1}", f"Pi{b + 1}"], "compatible": ok} for a, b, ok in self.compatibility],
            "excluded": [{"denominator": e.text, "denominator_name": e.name, "degree": e.degree,
                          "status": label(e.certificate.status),
                          "prime": e.prime, "values": {k: str(v) for k, v in e.values.items()},
                          "symmetries": [list(s.signs) for s in e.symmetries],
                          "torus": None if e.torus is None else torus_data(e.torus),
                          "blocks": [{"character": list(b.character), "columns": b.columns, "rows": b.rows,
                                      "rank": b.rank, "points": [list(x) for x in b.points]} for b in e.blocks]}
                         for e in self.excluded],
            "integrals": [{"name": n, "expr": str(h)} for n, h in self.integrals],
            "involution": [{"structure": f"Pi{k + 1}", "status": label(c.status), "statement": c.statement}
                           for k, c in self.involution],
            "kernels": [{"denominator_name": k.name, "denominator": k.text, "degree": k.degree,
                         "dimension": k.dimension, "jacobi_mod_p": k.jacobi_mod_p,
                         "status": label(k.certificate.status),
                         "certificate": k.certificate.to_dict(), "rebuilt": k.rebuilt,
                         "no_poisson": None if k.no_poisson is None else {
                             "degree": self.degree, "status": label(k.no_poisson.status),
                             "statement": k.no_poisson.statement}} for k in self.kernels],
            "nambu": [s.to_dict(label) for s in self.nambu],
            "costs": self.costs,
            "seconds": {k: round(v, 3) for k, v in self.seconds.items()},
            "notes": self.notes, "complete": self.complete, "stopped": self.stopped or None}

    def text(self) -> str:
        """The report for a person."""
        d = self.to_dict()
        lines = [f"Kahan map of {self.system} ({STEP_CONVENTION}): invariant bivectors Pi = Q/D, deg Q <= "
                 f"{self.degree}"]
        for s in d["structures"]:
            jac = {True: "Poisson", False: "NOT Poisson ([Pi, Pi] != 0)", None: "Jacobi not decided"}[s["poisson"]]
            lines.append(f"  [{s['status']}] {s['name']}: invariant, {jac}, rank {s['rank']}, Casimirs "
                         f"{', '.join(s['casimir_names']) or 'none among the integrals'}")
            lines += [f"      {{{self.variables[i]}, {self.variables[j]}}} = {s['matrix'][i][j]}"
                      for i, j in pairs(len(self.variables)) if s["matrix"][i][j] != "0"]
        for c in d["compatible"]:
            lines.append(f"  [{'Pi' if c['compatible'] else 'not '}compatible] {c['pair'][0]}, {c['pair'][1]}"
                         .replace("[Pi", "["))
        for name, h in self.integrals:
            lines.append(f"  integral {name} = {h}")
        for inv in d["involution"]:
            lines.append(f"  [{inv['status']}] involution for {inv['structure']}: {inv['statement']}")
        for e in d["excluded"]:
            lines.append(f"  [{e['status']}] excluded: no invariant Q/D, D = {e['denominator_name']}, with deg Q <= "
                         f"{e['degree']} (full column rank mod {e['prime']} in {len(e['blocks'])} block(s), "
                         f"{sum(b['columns'] for b in e['blocks'])} unknowns)")
        names = {e.name: e for e in self.excluded}
        lines += [f"  D = {n}: {Denominator(n, e.denominator).formula()}" for n, e in names.items() if n != "1"]
        for k in d["kernels"]:
            jac = {None: "", True: f"; at degree {self.degree} a member may satisfy Jacobi mod p",
                   False: f"; at degree {self.degree} no member satisfies Jacobi mod p"}[k["jacobi_mod_p"]]
            if not k["rebuilt"]:
                lines.append(f"  [{k['status']}] D = {k['denominator_name']}: a kernel of dimension {k['dimension']} "
                             f"mod p at degree {k['degree']} (invariant bivectors Q/D likely; not rebuilt: --screen{jac})")
            if k["no_poisson"] is not None:
                lines.append(f"  [{k['no_poisson']['status']}] D = {k['denominator_name']}: no invariant Q/D with deg Q "
                             f"<= {self.degree} is Poisson (no member of its kernel mod p satisfies Jacobi)")
        for nb in d["nambu"]:
            la = "; with the further integral " + ", ".join(nb["hamiltonians"]) + ": Liouville-Arnold integrable " \
                "(r = 1)" if nb["liouville_arnold"] else ""
            lines.append(f"  [{nb['status']}] Nambu structure {nb['formula']}, P = {nb['density'][3:-1]}"[:160])
            size = "not expanded" if nb["terms"] is None else f"degree {nb['degree']}, {nb['terms']} terms"
            lines.append(f"      invariant and Poisson, rank {nb['rank']}, Casimirs {', '.join(nb['casimirs'])} "
                         f"({size}){la}")
        for c in self.costs:
            lines.append(f"  cost: D = {c['denominator']}, degree {c['degree']}: {c['columns']} unknowns in "
                         f"{c['blocks']} block(s), {c['rows']} rows, kernel {c['kernel']}, {c['seconds']:.2f} s")
        lines += [f"  note: {n}" for n in self.notes]
        if self.stopped:
            lines.append(f"INCOMPLETE: {self.stopped}")
        return "\n".join(lines)


# ---- the modular search ---------------------------------------------------------------------------------------------
@dataclass
class _Scene:
    """The map mod p at the search's values, the denominator there, the symmetries that keep D and split the columns,
    and the torus of a linear symmetry (eigen-coordinates mod p) when it splits them finer; or, with `fixed` (the
    symmetry's generator A), the unknowns are the coordinates on the bivectors fixed by its flow."""
    kmap: KahanMap
    prime: int
    values: dict[str, flint.fmpq]
    den: Denominator
    symmetries: list[SignSymmetry]
    torus: Torus | None = None
    fixed: flint.fmpq_mat | None = None
    _bases: dict[Block, FixedColumns] = field(default_factory=dict, repr=False)

    @property
    def name(self) -> str:
        return self.den.name

    @property
    def denominator(self) -> flint.fmpz_mpoly:
        return self.den.poly

    def system(self, block: Block, rng: random.Random, extra: int = 4) -> tuple[np.ndarray, list[list[int]]]:
        return self.rows(self.kmap.mod(self.prime, self.values), block, rng, extra)

    def rows(self, mmap: ModularKahanMap, block: Block, rng: random.Random, extra: int
             ) -> tuple[np.ndarray, list[list[int]]]:
        """The invariance rows of the block at random points of `mmap`, `extra` more than its unknowns, on its
        unknowns (the fixed coordinates when the scene has a generator): (rows mod p, points)."""
        basis = self.basis(block)
        rows, points = system_mod_p(mmap, factored_mod(mmap, self.den.parts()), block, rng, extra, self.torus,
                                    need=self.width(block) + extra)
        return (basis.project(rows, mmap.p) if basis is not None else rows), points

    def basis(self, block: Block) -> FixedColumns | None:
        """The bivectors fixed by the generator's flow on the block (None without a generator)."""
        if self.fixed is None:
            return None
        if block not in self._bases:
            chi = semi_invariance_character(self.kmap, self.fixed, self.denominator)
            if chi is None:
                raise HKProofError(f"D = {self.name} is not semi-invariant under the symmetry")
            self._bases[block] = fixed_columns(self.kmap, block, self.fixed, chi)
        return self._bases[block]

    def width(self, block: Block) -> int:
        """The block's unknowns: its columns, or its fixed coordinates."""
        basis = self.basis(block)
        return len(block.columns) if basis is None else len(basis)

    def terms(self, block: Block, unknown: int) -> Sequence[tuple[int, int]]:
        """The columns of an unknown with their integer coefficients."""
        basis = self.basis(block)
        return ((unknown, 1),) if basis is None else basis.vectors[unknown]

    def blocks(self, degree: int) -> list[Block]:
        every = blocks(self.kmap, degree, self.symmetries, self.torus)
        return [b for b in every if self.width(b)] if self.fixed is not None else every

    def cost(self, degree: int) -> int:
        """sum of (unknowns of a block)^3: what the dense ranks cost."""
        return sum(self.width(b) ** 3 for b in self.blocks(degree))

    def split(self, torus: Torus | None, degree: int) -> _Scene:
        """The scene with the torus (and -I, the only sign symmetry diagonal in every chart) when its blocks cost less
        and D is semi-invariant under the torus' generator; this scene otherwise."""
        if torus is None or not is_semi_invariant(self.kmap, torus.generator, self.denominator):
            return self
        central = [s for s in self.symmetries if all(v < 0 for v in s.signs)]
        finer = dataclasses.replace(self, symmetries=central, torus=torus)
        return finer if finer.cost(degree) < self.cost(degree) else self


def confirming_rows(cols: int, torus: bool = False) -> list[int]:
    """The surplus rows (beyond the columns) with which a kernel is confirmed, tried in turn: a few surplus rows can
    fake a kernel, since the rows of one point are not independent (the Lagrange top at degree 4 showed a
    4-dimensional kernel with 4 surplus rows and none with 200); on the weight blocks of a torus a point gives fewer
    independent rows still (the Gaudin magnet's weight blocks at degree 4: 99 columns need 20 points, 32 need 16, 5
    need 3, not 7, 3 and 1; the large blocks need no more than the sign blocks: 1 172 columns at degree 5 have full
    rank with 1 185 rows), so about twice and then five times the columns are drawn there to confirm a kernel (cheap:
    only small blocks need it; the fixed coordinates of a flow are screened likewise, although there the Gaudin
    magnet's 2 110 coordinates at degree 6 show their one-dimensional kernel with 16 surplus rows). The first entry is
    the surplus of a rebuild (whose probes are checked against the reference kernel's free columns)."""
    return [cols + 60, 4 * cols + 200] if torus else [cols // 4 + 16]


def search_poisson(kmap: KahanMap, degree: int = 3, *, denominators: Sequence[Denominator] | None = None,
                   seed: int = 0, integrals: Integrals | None = None, progress: Progress | None = None,
                   fixed: Mapping[str, flint.fmpq] | None = None, budget: Budget | None = None,
                   screen: bool = False) -> PoissonReport:
    """Invariant bivectors Q/D with deg Q <= `degree` for each D in `denominators` (default: 1), proven or excluded.
    `integrals(kmap)` gives the proven integrals for Casimirs and involution (asked only when a structure is found).
    `screen`: ranks only; a class with a kernel is reported with its lowest degree and the kernel's dimension mod p
    (evidence), not rebuilt."""
    if not 0 <= degree <= MAX_POISSON_DEGREE:
        raise HKProofError(f"the degree of Q must be between 0 and {MAX_POISSON_DEGREE}, got {degree}")
    if len(kmap.variables) < 2:
        raise HKProofError("a bivector needs at least two phase variables")
    budget = budget or current()
    report = PoissonReport(kmap.field.name, list(kmap.variables), degree, fixed=dict(fixed or {}))
    stages = Stages("poisson", progress)
    rng = random.Random(seed)
    generator = generic_generator(commuting_linear_fields(kmap.field), rng)
    prime, torus = _prime_and_torus(rng, generator)
    values = random_point(rng, (EPS,) + kmap.field.parameters, 10**6)
    symmetries = sign_symmetries(kmap)
    lemma = matrix_identity_holds(kmap)
    try:
        for den in denominators or [Denominator("1", kmap.ring.constant(1))]:
            keep = [s for s in symmetries if denominator_character(kmap, den.poly, s) is not None]
            scene = _Scene(kmap, prime, values, den, keep)
            if screen:
                _screen_class(scene.split(torus, degree), scene, degree, rng, report, stages, budget)
            else:
                _search_class(scene.split(torus, degree), scene, degree, rng, report, stages, budget, lemma,
                              integrals)
    except BudgetExhausted as exc:
        report.stopped = str(exc)
    stages.stop()
    report.seconds = dict(stages.seconds)
    return report


def _prime_and_torus(rng: random.Random, generator: flint.fmpq_mat | None) -> tuple[int, Torus | None]:
    """A random 31-bit prime, one modulo which the linear symmetry diagonalizes when the field has one (p = 1 mod 4 for
    a rotation), with its eigen-coordinates."""
    if generator is not None:
        for _ in range(64):
            p = random_prime(rng, 31)
            torus = eigen_coordinates(generator, p)
            if torus is not None:
                return p, torus
    return random_prime(rng, 31), None


def _search_class(scene: _Scene, plain: _Scene, degree: int, rng: random.Random, report: PoissonReport,
                  stages: Stages, budget: Budget, lemma: bool, integrals: Integrals | None, top: bool = True) -> None:
    """One D: the top degree first (full column rank there excludes every lower degree too, the columns of a lower
    degree being a subset); with a kernel there, the no-poisson theorem when it holds (`_kernel_member`, recorded
    under the report's kernels as rebuilt), and the lowest degree with a kernel rebuilt and proven, in the `plain`
    scene (sign symmetries of x only: the kernel is rebuilt in the field's own coordinates), on the coordinates fixed
    by the torus' flow when the kernel has weight 0 only."""
    ranks, with_kernel = _ranks(scene, degree, rng, report, stages, budget)
    if all(b.rank == b.columns for b in ranks):
        if scene.fixed is not None:     # the torus saw a kernel here: a rank mod p that differs is not an exclusion
            raise SingularSystemError(f"D = {scene.name}: the fixed coordinates have full rank mod p where the "
                                      "torus' weight 0 had a kernel")
        _exclude(scene, degree, ranks, report)
        return
    if top:
        member = _kernel_member(scene, degree, ranks, rng, report, budget)
        if member is not None and member.certificate is not None and member.certificate.status.is_verified:
            _record_kernel(scene, degree, ranks, member, report, rebuilt=True)
    if scene.torus is not None:
        if all(b.character[-1] == 0 for b in ranks if b.rank < b.columns) and _fixed_route(scene, plain):
            plain = dataclasses.replace(plain, fixed=scene.torus.generator, _bases={})
        _search_class(plain, plain, degree, rng, report, stages, budget, lemma, integrals, top=False)
        return
    if not with_kernel:
        report.notes.append(f"D = {scene.name}, deg Q <= {degree}: every invariant Q/D is a combination of the "
                            "structures found with a smaller D (times D over their denominators): the kernels mod p "
                            "have no larger dimension")
        return
    for d in range(degree):
        lower = _ranks(scene, d, rng, report, stages, budget)[1]
        if lower:
            _found(scene, d, lower, rng, report, stages, budget, lemma, integrals)
            return
    _found(scene, degree, with_kernel, rng, report, stages, budget, lemma, integrals)


def _screen_class(scene: _Scene, plain: _Scene, degree: int, rng: random.Random, report: PoissonReport,
                  stages: Stages, budget: Budget) -> None:
    """One D, ranks only: excluded (a theorem, as in _search_class), or its lowest degree with a kernel mod p and
    the kernel's dimension reported (evidence: not rebuilt), with the Jacobi test of the top degree's kernel
    (`_kernel_member`: a theorem when no member can be Poisson)."""
    top = _ranks(scene, degree, rng, report, stages, budget)[0]
    if all(b.rank == b.columns for b in top):
        _exclude(scene, degree, top, report)
        return
    member = _kernel_member(scene, degree, top, rng, report, budget)
    for d in range(degree + 1):
        ranks = top if d == degree else _ranks(scene, d, rng, report, stages, budget)[0]
        if any(b.rank < b.columns for b in ranks):
            _record_kernel(scene, d, ranks, member, report)
            return


def _record_kernel(scene: _Scene, degree: int, ranks: list[BlockRank], member: NoPoisson | None,
                   report: PoissonReport, rebuilt: bool = False) -> None:
    """A class's kernel mod p at `degree` in the report's kernels, with the certificate of its proof kernel."""
    dimension = sum(b.columns - b.rank for b in ranks)
    cert = kernel_certificate(scene.kmap, scene.den.text(), degree, scene.prime, dimension, report.fixed)
    report.kernels.append(ScreenedKernel(scene.name, scene.den.text(), degree, dimension, cert, member,
                                         rebuilt=rebuilt))


def _kernel_member(scene: _Scene, degree: int, top: list[BlockRank], rng: random.Random, report: PoissonReport,
                   budget: Budget) -> NoPoisson | None:
    """The top degree's kernel solved again, for each sign character that holds part of it, on that character's block
    in the field's coordinates (the same sign symmetries, no torus): on the bivectors fixed by the torus' flow when
    that part has the weight chi of D only and the fixed basis has as many vectors as that weight's columns
    (`_fixed_kernel`), on all the columns otherwise. With at most MAX_NO_POISSON_KERNEL members in all, whether the
    brackets of all of them are independent mod p (no member Poisson), and then the certificate of "no invariant
    Poisson Q/D" (hkproof.hk.poisson_proofs.no_poisson_certificate). None when the kernel is larger."""
    k = len(scene.symmetries)
    short = [b for b in top if b.rank < b.columns]
    if sum(b.columns - b.rank for b in short) > MAX_NO_POISSON_KERNEL:
        return None
    kernels: list[BlockRank] = []
    fixed_flags: list[bool] = []
    kept: set[tuple[int, ...]] = set()
    members: list[Bivector] = []
    coordinates = dataclasses.replace(scene, torus=None, fixed=None, _bases={})
    for character in dict.fromkeys(b.character[:k] for b in short):
        [block] = [b for b in coordinates.blocks(degree) if b.character == character]
        fixed = _fixed_kernel(scene, block, [b for b in short if b.character[:k] == character], top)
        plain = coordinates
        if fixed is not None and scene.torus is not None:
            plain = dataclasses.replace(coordinates, fixed=scene.torus.generator, _bases={block: fixed[1]})
            kept.add(fixed[0])
        else:
            kept |= {b.character for b in top if b.character[:k] == character}
        budget.check(f"the invariance rows of degree {degree} in the field's coordinates")
        rows, points = plain.system(block, rng, confirming_rows(plain.width(block))[0])
        found = budget.call(f"the kernel mod p of {rows.shape[0]} x {rows.shape[1]} invariance rows",
                            free_kernel_mod_p, rows, scene.prime, 1)
        if not 1 <= len(found) + len(members) <= MAX_NO_POISSON_KERNEL:
            return None
        kernels.append(BlockRank(character, plain.width(block), rows.shape[0], plain.width(block) - len(found),
                                 tuple(tuple(x) for x in points)))
        fixed_flags.append(fixed is not None)
        members += [_residue_bivector(plain, block, _on_columns(plain, block, {c: x for c, x in enumerate(v) if x}))
                    for _, v in found]
    excluded = brackets_independent_mod(members, scene.prime) if members else False
    others = [b for b in top if b.character not in kept]
    cert = None if not excluded else no_poisson_certificate(
        scene.kmap, scene.denominator, degree, scene.prime, scene.values, [s.how for s in scene.symmetries], others,
        kernels, report.fixed, scene.torus, on_fixed=any(fixed_flags), text=scene.den.text())
    return NoPoisson(kernels, others, not excluded, cert, scene.prime, dict(scene.values), list(scene.symmetries),
                     scene.torus, fixed_flags)


def _fixed_kernel(scene: _Scene, block: Block, short: list[BlockRank], top: list[BlockRank]
                  ) -> tuple[tuple[int, ...], FixedColumns] | None:
    """The torus block (sign character, weight chi mod p) of a kernel that has that weight only, with the flow's fixed
    bivectors on `block`, when these are exactly as many as that block's columns (no other weight is chi mod p: every
    invariant Q/D of the class is then fixed by the flow); None otherwise."""
    if scene.torus is None or not commutes_with_signs(scene.torus.generator, scene.symmetries):
        return None
    chi = semi_invariance_character(scene.kmap, scene.torus.generator, scene.denominator)
    if chi is None:                 # with commuting signs, the conditions of _fixed_route
        return None
    weight = int(chi.p) * pow(int(chi.q), -1, scene.prime) % scene.prime
    kept = short[0].character[:-1] + (weight,)
    fixed = fixed_columns(scene.kmap, block, scene.torus.generator, chi)
    same = [b for b in top if b.character == kept]
    if any(b.character != kept for b in short) or not same or len(fixed) != same[0].columns:
        return None
    if any(v[0][1] % scene.prime == 0 for v in fixed.vectors):      # the basis must stay independent mod p
        return None
    return kept, fixed


def _residue_bivector(scene: _Scene, block: Block, coefficients: Mapping[int, int]) -> Bivector:
    """Q/D at the scene's specialization, coefficients lifted from their residues, in a ring of the phase variables."""
    kmap, p = scene.kmap, scene.prime
    ring = get_ring(tuple(kmap.variables))
    entries: list[dict[tuple[int, ...], int]] = [{} for _ in pairs(len(kmap.variables))]
    for col, c in coefficients.items():
        k, m = block.columns[col]
        entries[k][tuple(m)] = (entries[k].get(tuple(m), 0) + c) % p
    den = scene.kmap.mod(p, scene.values).reduce(scene.denominator)
    return Bivector(ring, tuple(kmap.variables), tuple(ring.ctx.from_dict(e) for e in entries),
                    ring.ctx.from_dict({tuple(int(x) for x in m): int(c) for m, c in den.to_dict().items()}))


def _fixed_route(scene: _Scene, plain: _Scene) -> bool:
    """The torus' generator commutes with the sign symmetries and keeps the class: the fixed coordinates apply."""
    generator = scene.torus.generator if scene.torus is not None else None
    return (generator is not None and commutes_with_signs(generator, plain.symmetries)
            and semi_invariance_character(scene.kmap, generator, scene.denominator) is not None)


def _exclude(scene: _Scene, degree: int, ranks: list[BlockRank], report: PoissonReport) -> None:
    """The class is excluded: full column rank mod p in every block at the top degree (its certificate)."""
    cert = exclusion_certificate(scene.kmap, scene.denominator, degree, scene.prime, scene.values,
                                 [s.how for s in scene.symmetries], ranks, report.fixed, scene.torus)
    report.excluded.append(ExcludedClass(scene.name, scene.denominator, scene.den.text(), degree, scene.prime,
                                         dict(scene.values), ranks, list(scene.symmetries), cert, scene.torus))


Kernel = tuple[Block, np.ndarray, list[list[int]]]     # a block with new invariant bivectors: rows, known vectors


def _ranks(scene: _Scene, d: int, rng: random.Random, report: PoissonReport, stages: Stages, budget: Budget
           ) -> tuple[list[BlockRank], list[Kernel]]:
    """The rank mod p of each block at degree d (a kernel confirmed on more points), its cost in the report, and the
    blocks whose kernel is larger than the span of the structures already found (`_known_vectors`), with their rows
    and those vectors."""
    stages.start("rank mod p", f"D = {scene.name}, degree {d}: rank mod p")
    start = time.perf_counter()
    ranks: list[BlockRank] = []
    with_kernel: list[Kernel] = []
    for block in scene.blocks(d):
        budget.check(f"the invariance rows of degree {d}")
        rows, points = scene.system(block, rng)
        rank = budget.call(f"the rank mod p of {rows.shape[0]} x {rows.shape[1]} invariance rows",
                           _rank, rows, scene.prime)
        width = scene.width(block)
        for extra in confirming_rows(width, scene.torus is not None or scene.fixed is not None):
            if rank == width:                                         # a kernel: confirmed on more points
                break
            rows, points = scene.system(block, rng, extra)
            rank = budget.call(f"the rank mod p of {rows.shape[0]} x {rows.shape[1]} invariance rows",
                               _rank, rows, scene.prime)
        ranks.append(BlockRank(block.character, width, rows.shape[0], rank, tuple(tuple(x) for x in points)))
        if rank < width:
            known = [] if scene.torus else _known_vectors(scene, block, [s.bivector for s in report.structures])
            spanned = _rank(np.array(known, dtype=np.int64), scene.prime) if known else 0
            if width - rank > spanned:
                with_kernel.append((block, rows, known))
    report.costs.append({"denominator": scene.name, "degree": d, "columns": sum(b.columns for b in ranks),
                         "blocks": len(ranks), "rows": sum(b.rows for b in ranks),
                         "kernel": sum(b.columns - b.rank for b in ranks), "torus": scene.torus is not None,
                         "seconds": round(time.perf_counter() - start, 4)})
    return ranks, with_kernel


def _known_vectors(scene: _Scene, block: Block, known: Sequence[Bivector]) -> list[list[int]]:
    """The coefficient vectors mod p, on the block's columns, of Q_k D/D_k for each structure Q_k/D_k already found
    whose denominator divides D and whose numerator then lies in the block's degrees (its part of the block's
    character: invariant, since the invariant bivectors split by characters); on the fixed coordinates when the scene
    has them (a structure of a class whose kernel has weight 0 is fixed by the flow)."""
    mmap = scene.kmap.mod(scene.prime, scene.values)
    where = {c: k for k, c in enumerate(block.columns)}
    top = max(sum(m) for _, m in block.columns)
    out = []
    for pi in known:
        quotient, remainder = divmod(scene.denominator, pi.denominator)
        if not remainder.is_zero():
            continue
        entries = [mmap.reduce(q * quotient).to_dict() for q in pi.upper]
        if any(sum(m) > top for e in entries for m in e):
            continue
        vector = [0] * len(block.columns)
        for k, e in enumerate(entries):
            for m, c in e.items():
                if (k, tuple(m)) in where:
                    vector[where[(k, tuple(m))]] = int(c)
        basis = scene.basis(block)
        coordinates = basis.coordinates(vector, scene.prime) if basis is not None else vector
        if coordinates is not None and any(vector):
            out.append(coordinates)
    return out


def _rank(rows: np.ndarray, p: int) -> int:
    return int(nmod_matrix(rows, p).rank())


def _found(scene: _Scene, degree: int, with_kernel: Sequence[Kernel], rng: random.Random,
           report: PoissonReport, stages: Stages, budget: Budget, lemma: bool, integrals: Integrals | None) -> None:
    """Rebuild each block's kernel with eps and the parameters symbolic, prove each basis bivector, pairs, integrals."""
    kmap = scene.kmap
    stages.start("reconstruction", f"degree {degree}: rebuilding {len(with_kernel)} kernel block(s)")
    built: list[Bivector] = []
    for block, rows, known in with_kernel:
        built += _rebuild_block(scene, block, rows, known, rng, budget)
    stages.start("proofs", f"proving {len(built)} invariant bivector(s)")
    if integrals is not None and not report.integrals:
        report.integrals = integrals(kmap)
    first = len(report.structures)
    for k, pi in enumerate(built):
        budget.check("proving invariant bivectors")
        report.structures.append(prove_structure(kmap, pi, report.integrals, lemma, report.fixed,
                                                 name=f"Pi{first + k + 1}"))
    proven = [(first + k, s) for k, s in enumerate(report.structures[first:]) if s.status.is_verified and s.poisson]
    for (a, sa), (b, sb) in itertools.combinations(proven, 2):
        ok = compatibility_step(sa.certificate, kmap, (f"Pi{a + 1}", sa.bivector), (f"Pi{b + 1}", sb.bivector))
        report.compatibility.append((a, b, ok))
    invariant = [(first + k, s) for k, s in enumerate(report.structures[first:]) if s.status.is_verified]
    for k, s in invariant:          # a bivector that is not Poisson too: {I, J} = 0 is then a fact about it, no more
        others = [(n, h) for n, h in report.integrals if n not in {c for c, _ in s.casimirs}]
        report.involution.append((k, involution_certificate(kmap, s.bivector, others, report.fixed)))
    alone = report.structures[first] if len(built) == 1 and not any(known for _, _, known in with_kernel) else None
    if alone is not None and alone.status.is_verified and alone.poisson is False:
        report.notes.append(f"D = {scene.name}, deg Q <= {degree}: the invariant bivectors of this class are the "
                            f"multiples c Pi{first + 1} (a kernel of dimension 1 mod p bounds their space, Pi{first + 1} "
                            f"is proven invariant), and [c Pi, c Pi] = c^2 [Pi, Pi] != 0: the class has no invariant "
                            "Poisson structure")
    if len(built) > 1:
        report.notes.append(f"D = {scene.name}: the invariant bivectors of degree {degree} form a space of dimension "
                            f"{len(built)} over "
                            "Q(eps, params); a member sum c_k Pi_k is Poisson iff sum c_a c_b [Pi_a, Pi_b] = 0 "
                            "(the basis members and compatible pairs are listed)")


# ---- reconstruction of a kernel block ------------------------------------------------------------------------------------
def _rebuild_block(scene: _Scene, block: Block, rows: np.ndarray, known: Sequence[Sequence[int]], rng: random.Random,
                   budget: Budget) -> list[Bivector]:
    """The members of the rref kernel basis of the block (canonical, so each coordinate is a rational function of eps
    and the parameters) that are new modulo the `known` vectors, rebuilt by sparse reconstruction with the weights of
    the scaling symmetries normalized."""
    kmap, p = scene.kmap, scene.prime
    reference = free_kernel_mod_p(rows, p, free_value=1)
    frees = [f for f, _ in reference]
    chosen = _new_members([v for _, v in reference], known, p)
    targets = [(k, c) for k, (f, v) in enumerate(reference) if k in chosen for c, x in enumerate(v) if x and c != f]
    weights = scaling_weights(kmap, [Frac(kmap.ring, scene.denominator)])
    normalized = list(weights.normalized)
    where = _slice_for(kmap, scene.denominator, normalized)
    pivots = [] if where is None else [shift.pivot for shift in where.shifts]
    sampled = [n for n in kmap.field.control_names if n not in normalized and n not in pivots]
    seed = rng.randrange(2**32)

    def box(q: int, points: Sequence[Sequence[int]]) -> list[list[int] | None]:
        out: list[list[int] | None] = []
        local = random.Random(seed)
        for t in points:
            controls = {**{n: 1 for n in normalized}, **{n: 0 for n in pivots}, **dict(zip(sampled, t))}
            try:
                matrix, _ = scene.rows(kmap.mod(q, controls), block, local, confirming_rows(scene.width(block))[0])
            except (UnluckyPrimeError, ZeroDivisionError):
                out.append(None)
                continue
            kernel = free_kernel_mod_p(matrix, q, free_value=1)
            if [f for f, _ in kernel] != frees:
                out.append(None)
                continue
            out.append([kernel[k][1][c] for k, c in targets])
        return out
    values = _reconstruct(box, max(1, len(sampled)), len(targets), rng, budget)
    names = tuple(sampled) if sampled else ("_unused",)
    small = get_ring(names)
    ring = kmap.ring
    coefficients: dict[int, dict[int, Frac]] = {k: {frees[k]: Frac(ring, 1)} for k in chosen}
    for (k, c), (num, den) in zip(targets, values, strict=True):
        h = Frac(ring, small.project(small.ctx.from_dict(num), ring) if sampled else ring.constant(_const(num)),
                 small.project(small.ctx.from_dict(den), ring) if sampled else ring.constant(_const(den)))
        restored = weights.restore_frac(h, _weight(weights, kmap, block, scene.terms(block, frees[k])[0][0],
                                                   scene.terms(block, c)[0][0]))
        if restored is None:
            raise SingularSystemError(f"a rebuilt coefficient {h} is not weighted homogeneous")
        coefficients[k][c] = restored if where is None else where.lift(restored.to_ring(where.searched.ring), ring)
    return [_bivector(kmap, block, _on_columns(scene, block, coeffs), scene.denominator)
            for coeffs in coefficients.values()]


def _slice_for(kmap: KahanMap, denominator: flint.fmpz_mpoly, normalized: Sequence[str]) -> Slice | None:
    """The slice of the field's parameter translations on which a kernel is rebuilt (one parameter fewer), when D is
    invariant under them and no pivot is normalized by a scaling: then the invariance rows at the parameters a and at
    their translate are the same system, so the kernel's rref coordinates are invariant functions, the lifts of their
    restrictions to the slice (a candidate only: every bivector is then proven on the whole map). None otherwise."""
    where = Slice.of(kmap.field)
    if not where.shifts or any(shift.pivot in normalized for shift in where.shifts):
        return None
    d = restricted = Frac(kmap.ring, denominator)
    for shift in where.shifts:
        restricted = shift.restrict(restricted)
    return where if where.lift(restricted, kmap.ring) == d else None


def _on_columns(scene: _Scene, block: Block, coeffs: Mapping[int, T]) -> dict[int, T]:
    """The coefficients of the block's columns from those of the unknowns (the same, without fixed coordinates);
    rational functions of a rebuild or residues of a kernel mod p."""
    out: dict[int, T] = {}
    for c, h in coeffs.items():
        for col, k in scene.terms(block, c):
            out[col] = out[col] + h * k if col in out else h * k
    return out


def _new_members(basis: Sequence[Sequence[int]], known: Sequence[Sequence[int]], p: int) -> list[int]:
    """The indices of the basis vectors that raise the rank mod p of the known vectors and those chosen before."""
    chosen: list[int] = []
    span = [list(v) for v in known]
    rank = flint.nmod_mat(span, p).rank() if span else 0
    for k, v in enumerate(basis):
        trial = span + [list(v)]
        if flint.nmod_mat(trial, p).rank() > rank:
            span, chosen, rank = trial, chosen + [k], rank + 1
    return chosen


def _const(poly: Mapping[Exponents, int]) -> int:
    if any(any(m) for m in poly):
        raise SingularSystemError("a coefficient expected constant depends on the dummy variable")
    return int(sum(poly.values()))


def _weight(weights: Weights, kmap: KahanMap, block: Block, free: int, col: int) -> list[flint.fmpq]:
    """w(free column) - w(column), w(ij, x^m) = w(x^m) - w(x_i) - w(x_j): the weight of the coefficient (of a fixed
    coordinate: of one of its columns, all of one weight, as the symmetry commutes with the scalings)."""
    def w(c: int) -> list[flint.fmpq]:
        k, m = block.columns[c]
        i, j = pairs(len(kmap.variables))[k]
        exps = dict(zip(kmap.variables, m, strict=True))
        exps[kmap.variables[i]] -= 1
        exps[kmap.variables[j]] -= 1
        return weights.of_monomial(exps)
    return [a - b for a, b in zip(w(free), w(col), strict=True)]


def _bivector(kmap: KahanMap, block: Block, coeffs: Mapping[int, Frac], den: flint.fmpz_mpoly) -> Bivector:
    """Q = sum_c coeff_c x^m e_ij over the columns, cleared of the coefficients' denominators and content, over D."""
    ring = kmap.ring
    common = lcm([c.den for c in coeffs.values()])
    upper = [ring.constant(0) for _ in pairs(len(kmap.variables))]
    for c, h in coeffs.items():
        k, m = block.columns[c]
        mono = ring.constant(1)
        for v, e in zip(kmap.variables, m, strict=True):
            mono *= ring.gen(v) ** e
        upper[k] += h.num * (common / h.den) * mono
    content: flint.fmpz = flint.fmpz(0)          # an integer only: a factor with x would change the bivector
    for q in upper:
        for coefficient in q.coeffs():
            content = content.gcd(coefficient)
    return Bivector(ring, tuple(kmap.variables), tuple(q / content if content > 1 else q for q in upper), den)


def _reconstruct(box: Callable[[int, Sequence[Sequence[int]]], list[list[int] | None]], n: int, count: int,
                 rng: random.Random, budget: Budget) -> list[tuple[dict, dict]]:
    """The one call of the reconstruction interface: `count` rational functions of n variables (num, den), on 31-bit
    primes, where the invariance rows are numpy int64 (a 62-bit prime makes them Python integers, several times slower
    per probe). One variable (every other control normalized by a scaling): method "dense", all coordinates on the same
    probes (the Gaudin magnet's 704 coordinates at degree 6: each probe is an elimination of 2 110 unknowns, and one
    sparse reconstruction per coordinate spent 25 s each). More variables: method "sparse", one at a time with the
    same seed, so that the components meet on the same points whatever their degrees (the engine's keyed random
    streams, hkproof.algebra.sparse_reconstruction) and each kernel vector is computed once (memoized)."""
    if count == 0:
        return []
    if n == 1:
        budget.check("rebuilding the coordinates of invariant bivectors")
        return [(r.numerator, r.denominator)
                for r in reconstruct(box, 1, count, method="dense", rng=rng, bits=31, max_degree=DENSE_MAX_DEGREE)]
    memos: dict[int, dict[tuple[int, ...], list[int] | None]] = {}

    def vectors(q: int, points: Sequence[Sequence[int]]) -> list[list[int] | None]:
        return memoized_values(memos.setdefault(q, {}), points, lambda missing: box(q, missing))
    seed = rng.randrange(2**32)
    out = []
    for k in range(count):
        budget.check("rebuilding the coordinates of invariant bivectors")

        def component(q: int, points: Sequence[Sequence[int]], k: int = k) -> list[list[int] | None]:
            return [None if v is None else [v[k]] for v in vectors(q, points)]
        r = reconstruct(component, n, 1, method="sparse", rng=random.Random(seed), budget=budget, bits=31)[0]
        out.append((r.numerator, r.denominator))
    return out


def with_integrals(kmap: KahanMap, degree: int, denominators: Sequence[Frac] = (), integrals_degree: int = 2, *,
                   darboux_degree: int = 4, seed: int = 0, fixed: Mapping[str, flint.fmpq] | None = None,
                   progress: Progress | None = None, budget: Budget | None = None,
                   screen: bool = False, only: Sequence[str] = ()) -> PoissonReport:
    """search_poisson with the integrals `discover` proves (degree `integrals_degree`, 0: none) for Casimirs and
    involution, and the candidate denominators of hkproof.pipelines.poisson_candidates: 1, the given ones, each
    integral's denominator and the Darboux polynomials `measure` finds (degree `darboux_degree`, 0: none), factored,
    and the products of two factors; `only`: the classes of these names alone."""
    from hkproof.pipelines.darboux import search_darboux
    from hkproof.pipelines.discover import discover
    budget = budget or current()
    found: list[tuple[str, Frac]] = []
    if integrals_degree > 0:
        rep = discover(kmap.field, integrals_degree, seed=seed, budget=budget, progress=progress)
        found = [(i.name, i.frac) for i in rep.integrals if i.frac is not None and i.status.is_verified]
    densities: list[tuple[str, flint.fmpz_mpoly, Status]] = []
    sources = []
    for k, d in enumerate(denominators):
        if not d.is_polynomial() or d.num.is_zero():
            raise HKProofError(f"a denominator must be a non-zero polynomial, got {d}")
        sources.append((f"the given D{k + 1}", d.num))
    sources += [(f"den({name})", h.den) for name, h in found]
    if darboux_degree > 0:
        with budget.active():
            search = search_darboux(kmap, darboux_degree, seed=seed, fixed=fixed)
        if search.symbolic:         # at fixed values otherwise: not a candidate for every parameter value
            sources += [(f"P{k + 1} of measure", p.poly) for k, p in enumerate(search.darboux)]
            densities = nambu_densities(kmap, search)
    candidates = candidate_denominators(kmap.ring.constant(1), kmap.variables, sources)
    if only:
        unknown = [name for name in only if name not in {d.name for d in candidates}]
        if unknown:
            raise HKProofError(f"no candidate class {', '.join(unknown)}: the candidates are "
                               + ", ".join(d.name for d in candidates))
        candidates = [d for d in candidates if d.name in only]
    report = search_poisson(kmap, degree, denominators=candidates, seed=seed, integrals=lambda _: found,
                            progress=progress, fixed=fixed, budget=budget, screen=screen)
    n = len(kmap.variables)
    if densities and n >= 3 and len(found) >= n - 2:
        started = time.perf_counter()
        with budget.active():
            report.nambu.append(prove_nambu(kmap, [(a, h, Status.VERIFIED) for a, h in found], densities[0], fixed))
        report.seconds["nambu"] = time.perf_counter() - started
    return report


def nambu_densities(kmap: KahanMap, search: DarbouxSearch) -> list[tuple[str, flint.fmpz_mpoly, Status]]:
    """The invariant densities 1/P of `measure`'s search (P = 1 when det Df = 1), fewest terms first."""
    out = [("1", kmap.ring.constant(1), Status.VERIFIED if search.jacobian_lemma else Status.UNKNOWN)
           ] if not any(search.jacobian.exponents) else []
    out += sorted(((poly_str(d.poly), d.poly, d.status) for d in search.darboux if d.cofactor == search.jacobian),
                  key=lambda d: len(d[1]))
    return out
