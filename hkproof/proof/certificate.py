"""Certificates: a proof is a list of checked steps, each with its method, ring, time and outcome."""
from __future__ import annotations

import time
from array import array
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Callable, Iterator, Mapping, MutableMapping

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.printing import latex, markdown_table
from hkproof.algebra.ring import Ring
from hkproof.errors import BudgetExhausted, HKProofError, ProofStopped, Refuted
from hkproof.proof.status import Status

if TYPE_CHECKING:
    import sympy

__all__ = ["Certificate", "describe_ring", "Formulas", "PackedValues", "ProofStopped", "Refuted", "Step",
           "StepRecorder"]


class Formulas(MutableMapping[str, str]):
    """A certificate's formulas by name: a text recorded with its exact value is written out from that value when
    first read (the text of a big solution costs seconds, and a run that prints no formulas never reads it)."""

    def __init__(self, values: Mapping[str, Frac], texts: Mapping[str, str | None] | None = None,
                 withheld: frozenset[str] = frozenset()):
        self._values = values
        self._texts: dict[str, str | None] = texts.unwritten() if isinstance(texts, Formulas) else dict(texts or {})
        self.withheld = withheld     # formulas whose values stayed with the worker (Certificate.withhold_values)

    def __getitem__(self, name: str) -> str:
        text = self._texts[name]
        if text is None:
            if name in self.withheld:
                raise HKProofError(f"the formula {name} stayed with the worker that proved it: this run asked for "
                                   "no exact values of the claim (RunOptions.values)")
            text = self._texts[name] = str(self._values[name])
        return text

    def __setitem__(self, name: str, text: str) -> None:
        self._texts[name] = text

    def __delitem__(self, name: str) -> None:
        del self._texts[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._texts)

    def __len__(self) -> int:
        return len(self._texts)

    def from_value(self, name: str) -> None:
        """The formula `name` is the text of the exact value kept under that name (written out when read)."""
        self._texts[name] = None

    def unwritten(self) -> dict[str, str | None]:
        """The texts as recorded (None: not yet written out from its value), for pickling."""
        return dict(self._texts)

    def __repr__(self) -> str:
        return repr(dict(self))


class PackedValues(MutableMapping[str, Frac]):
    """A pickled certificate's exact values, each unpacked from its exponent bytes and coefficients when first read (a
    process that only prints or forwards a certificate never builds its polynomials)."""

    def __init__(self, packed: Mapping[str, tuple]):
        self._packed = dict(packed)
        self._values: dict[str, Frac] = {}
        self._rings: dict[tuple[str, ...], Ring] = {}

    def __getitem__(self, name: str) -> Frac:
        if name not in self._values:
            self._values[name] = _unpack(self._packed[name], self._rings)
        return self._values[name]

    def __setitem__(self, name: str, value: Frac) -> None:
        self._packed.pop(name, None)
        self._values[name] = value

    def __delitem__(self, name: str) -> None:
        if name not in self._packed and name not in self._values:
            raise KeyError(name)
        self._packed.pop(name, None)
        self._values.pop(name, None)

    def __iter__(self) -> Iterator[str]:
        return iter({**dict.fromkeys(self._packed), **dict.fromkeys(self._values)})

    def __len__(self) -> int:
        return len(self._packed.keys() | self._values.keys())

    def packed(self) -> dict[str, tuple]:
        """Every value packed: the arrived ones as they came, the others packed now."""
        seen: list[tuple[flint.fmpz_mpoly, tuple]] = []
        return {name: self._packed[name] if name in self._packed else _pack(self._values[name], seen) for name in self}


def describe_ring(ring: Ring | str, fixed: Mapping[str, object] | None = None) -> str:
    """'Q[x1, x2, eps, a1]' or 'Q[m1, ..., eps] with w1=1, w2=2' for a step's record."""
    text = ring if isinstance(ring, str) else f"Q[{', '.join(ring.names)}]"
    if fixed:
        text += " with " + ", ".join(f"{k}={v}" for k, v in fixed.items())
    return text


@dataclass
class Step:
    """One checked step of a proof."""

    name: str
    method: str
    ring: str
    status: Status = Status.UNKNOWN
    seconds: float = 0.0
    detail: str = ""
    points: int | None = None
    stopped_by_budget: bool = False      # a BudgetExhausted stopped this step (unknown: not refuted, not decided)

    def to_dict(self) -> dict:
        return {"name": self.name, "method": self.method, "ring": self.ring, "status": self.status.label,
                "seconds": round(self.seconds, 4), "detail": self.detail, "points": self.points}


class StepRecorder:
    """What a running step may do: require exact facts, lower its status to evidence, add detail."""

    def __init__(self, step: Step, specialized: bool):
        self.step = step
        self.status = Status.VERIFIED_SPECIALIZED if specialized else Status.VERIFIED
        self._details: list[str] = []

    def require(self, condition: bool, message: str | Callable[[], str]) -> None:
        """The claim of this step holds iff `condition`; otherwise the step (and claim) is refuted with `message` (a
        callable is written only then: the text of a big rational function costs seconds)."""
        if not condition:
            raise Refuted(message if isinstance(message, str) else message())

    def require_equal(self, found: Frac, claimed: Frac, what: str) -> None:
        """An exact identity of rational functions; the refutation shows the difference."""
        if found != claimed:
            raise Refuted(f"{what}: computed {found} differs from the claimed {claimed} "
                          f"(difference {found - claimed})")

    def evidence(self, status: Status, points: int | None = None) -> None:
        """Mark this step as evidence only (numeric or sampled), never verified."""
        self.status = min(self.status, status)
        if points is not None:
            self.step.points = points

    def inconclusive(self, message: str) -> None:
        """Stop this step as 'unknown': the method could not decide (not a refutation)."""
        raise ProofStopped(message)

    def note(self, text: str) -> None:
        self._details.append(text)


@dataclass
class Certificate:
    """The record of a claim's proof: steps, the formulas found, and corrections to the paper."""

    claim_id: str
    title: str
    paper_ref: str
    statement: str
    steps: list[Step] = field(default_factory=list)
    formulas: MutableMapping[str, str] = field(default_factory=dict)
    corrections: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    error: str = ""
    cites: list[str] = field(default_factory=list)
    values: MutableMapping[str, Frac] = field(default_factory=dict, compare=False, repr=False)  # of `formulas`
    fixed: dict[str, str] = field(default_factory=dict)    # parameter values the whole proof holds at (specialized)
    checks: list[dict] = field(default_factory=list, compare=False, repr=False)  # re-checkable steps (proof.export)
    elapsed: float | None = field(default=None, compare=False, repr=False)   # the prover's whole time, if measured

    @property
    def status(self) -> Status:
        if self.error and not any(s.status is Status.REFUTED for s in self.steps):
            return Status.UNKNOWN
        if not self.steps:
            return Status.UNKNOWN
        return min(s.status for s in self.steps)

    @property
    def seconds(self) -> float:
        """The prover's whole wall time when it was measured (`Claim.certify`: the work between steps too, such as a
        search whose result the steps then check, and a cited claim proven on the way outside a run), else the sum
        of the steps' times."""
        return self.elapsed if self.elapsed is not None else sum(s.seconds for s in self.steps)

    @property
    def stopped_by_budget(self) -> bool:
        """Whether the proof stopped because the budget ran out in its last step (not refuted, not decided)."""
        return bool(self.steps) and self.steps[-1].stopped_by_budget

    @contextmanager
    def step(self, name: str, method: str, ring: Ring | str,
             fixed: Mapping[str, object] | None = None) -> Iterator[StepRecorder]:
        """Run one step; a Refuted inside refutes the claim, any other exception (HKProofError, or an error of the
        prover itself: IndexError, RecursionError, ...) stops the proof as `unknown` with the error recorded."""
        fixed = {**self.fixed, **(fixed or {})}
        record = Step(name, method, describe_ring(ring, fixed))
        recorder = StepRecorder(record, specialized=bool(fixed))
        self.steps.append(record)
        start = time.perf_counter()
        try:
            yield recorder
        except Refuted as exc:
            record.status = Status.REFUTED
            record.detail = str(exc)
            raise ProofStopped(str(exc)) from None
        except ProofStopped as exc:
            record.status = Status.UNKNOWN
            record.detail = str(exc)
            raise
        except Exception as exc:  # noqa: BLE001 -- KeyboardInterrupt passes; everything else is recorded
            record.status = Status.UNKNOWN
            record.detail = f"{type(exc).__name__}: {exc}"
            record.stopped_by_budget = isinstance(exc, BudgetExhausted)
            raise ProofStopped(record.detail) from None
        else:
            record.status = recorder.status
            record.detail = "; ".join(recorder._details)
        finally:
            record.seconds = time.perf_counter() - start

    def __post_init__(self) -> None:
        self.formulas = Formulas(self.values, self.formulas)

    def formula(self, name: str, value: Frac | str) -> None:
        """Record a formula found (sympy-parsable, in the system's own names), and its exact value if given one
        (the text is then written out from the value when first read)."""
        if isinstance(value, Frac):
            self.values[name] = value
            self.formulas.from_value(name)   # type: ignore[attr-defined]  # a Formulas since __post_init__
        else:
            self.formulas[name] = str(value)

    def correction(self, text: str) -> None:
        """Record a place where the paper is wrong or imprecise, with the corrected statement."""
        self.corrections.append(text)

    def to_dict(self) -> dict:
        return {"id": self.claim_id, "title": self.title, "paper_ref": self.paper_ref,
                "statement": self.statement, "status": self.status.label,
                "seconds": round(self.seconds, 4), "steps": [s.to_dict() for s in self.steps],
                "formulas": dict(self.formulas), "corrections": list(self.corrections),
                "notes": list(self.notes), "error": self.error, "cites": list(self.cites),
                **({"fixed": dict(self.fixed)} if self.fixed else {})}

    def withhold_values(self) -> None:
        """Drop the exact values before this certificate is sent back from a worker to a run that reads none of them
        (packing a big one costs seconds): the formulas written out from them can no longer be read here."""
        unwritten = self.formulas.unwritten()       # type: ignore[attr-defined]  # see __post_init__
        self.values = {}
        self.formulas = Formulas(self.values, unwritten, frozenset(k for k, v in unwritten.items() if v is None))

    @property
    def values_withheld(self) -> bool:
        """Whether `withhold_values` dropped values that formulas were to be written from."""
        return bool(self.formulas.withheld)         # type: ignore[attr-defined]  # see __post_init__

    def __getstate__(self) -> dict:
        """Pickled (for a worker process or a Dask worker) with its exact values packed as exponent bytes and
        integer coefficients; values that arrived pickled are passed on without unpacking or packing them again."""
        state = dict(self.__dict__)
        state["formulas"] = self.formulas.unwritten()     # type: ignore[attr-defined]  # see __post_init__
        state["withheld"] = self.formulas.withheld        # type: ignore[attr-defined]
        values = self.values
        seen: list[tuple[flint.fmpz_mpoly, tuple]] = []
        state["values"] = values.packed() if isinstance(values, PackedValues) else \
            {k: _pack(v, seen) for k, v in values.items()}
        return state

    def __setstate__(self, state: dict) -> None:
        withheld = state.pop("withheld", frozenset())
        self.__dict__.update(state)
        self.values = PackedValues(state["values"])
        self.formulas = Formulas(self.values, state["formulas"], withheld)

    def to_sympy(self) -> dict[str, sympy.Expr]:
        """The formulas found that carry exact values, as sympy expressions in the system's own names."""
        return {name: value.to_sympy() for name, value in self.values.items()}

    def _repr_markdown_(self) -> str:
        """Status, claim, formulas (LaTeX), steps and time: how Jupyter shows a certificate."""
        import sympy
        lines = [f"**[{self.status.label}] {self.claim_id}**: {self.title} ({self.paper_ref}; {self.seconds:.3f} s)",
                 "", f"claim: {self.statement}", ""]
        if self.fixed:
            lines += ["at " + ", ".join(f"{k} = {v}" for k, v in self.fixed.items()), ""]
        exact = self.to_sympy()
        lines += [f"- ${latex(sympy.Symbol(name))} = {latex(exact[name])}$" if name in exact else f"- {name} = `{text}`"
                  for name, text in self.formulas.items()]
        rows = [[s.status.label, s.name, s.method, s.ring + (f", {s.points} points" if s.points else ""),
                 f"{s.seconds:.3f} s", s.detail] for s in self.steps]
        lines += ["", markdown_table(["status", "step", "method", "ring", "time", "detail"], rows)]
        lines += [f"- paper correction: {c}" for c in self.corrections] + [f"- note: {n}" for n in self.notes]
        if self.error:
            lines.append(f"- stopped: {self.error}")
        return "\n".join(lines)

    def render(self) -> str:
        """A readable certificate for the terminal."""
        lines = [f"[{self.status.label}] {self.claim_id}: {self.title}  ({self.paper_ref}; {self.seconds:.3f} s)",
                 f"    claim: {self.statement}"]
        for s in self.steps:
            pts = f", {s.points} points" if s.points else ""
            lines.append(f"    - {s.status.label:<22} {s.name} [{s.method}; {s.ring}{pts}; {s.seconds:.3f} s]")
            if s.detail:
                lines.append(f"        {s.detail}")
        for c in self.corrections:
            lines.append(f"    ! paper correction: {c}")
        for n in self.notes:
            lines.append(f"    note: {n}")
        if self.error:
            lines.append(f"    stopped: {self.error}")
        return "\n".join(lines)


def _pack(q: Frac, seen: list[tuple[flint.fmpz_mpoly, tuple]] | None = None) -> tuple:
    """A rational function as compact picklable data: its ring's names, then numerator and denominator as (width,
    exponent bytes, integer coefficients), each exponent in the fewest bytes its largest degree needs. A polynomial
    equal to one in `seen` (packed earlier for the same certificate) reuses that one's data, which pickle then
    writes once (the components of a solution share their denominator)."""
    return (q.ring.names,) + tuple(_pack_polynomial(p, seen if seen is not None else []) for p in (q.num, q.den))


def _pack_polynomial(p: flint.fmpz_mpoly, seen: list[tuple[flint.fmpz_mpoly, tuple]]) -> tuple:
    for q, data in seen:
        if q is p or (len(q) == len(p) and q.context() is p.context() and q == p):
            return data
    top = max(p.degrees(), default=0)
    width = "B" if top < 1 << 8 else "H" if top < 1 << 16 else "Q"
    data = (width, array(width, [e for m in p.monoms() for e in m]).tobytes(), [int(c) for c in p.coeffs()])
    seen.append((p, data))
    return data


def _unpack(packed: tuple, rings: dict[tuple[str, ...], Ring]) -> Frac:
    names, *polys = packed
    if names not in rings:
        rings[names] = Ring(names)
    ring = rings[names]
    num, den = (ring.ctx.from_dict(dict(zip(_exponents(width, raw, len(names)), coeffs, strict=True)))
                for width, raw, coeffs in polys)
    return Frac(ring, num, den, reduced=True)


def _exponents(width: str, raw: bytes, nvars: int) -> Iterator[tuple[int, ...]]:
    flat = array(width)
    flat.frombytes(raw)
    return zip(*[iter(flat)] * nvars, strict=True)
