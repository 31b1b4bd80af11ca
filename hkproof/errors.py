"""Exceptions of hkproof: each message says what was wrong and what to do about it."""

import signal

__all__ = ["BudgetExhausted", "CertificateError", "CitationCycleError", "DependenceSearchError", "DependentBasisError",
           "FormulaTooLargeError", "HKProofError", "Interrupted", "MissingDependencyError", "NotHamiltonianError",
           "NotQuadraticError", "OutputError", "ParseError", "ProofStopped", "Refutation", "Refuted", "RelationSearchError",
           "ResourceLimitError", "RingMismatchError", "ShapeError", "SingularPointError", "SingularSystemError",
           "UnknownClaimError", "UnknownSymbolError", "UnknownSystemError", "UnluckyPrimeError", "UsageError"]


class HKProofError(Exception):
    """Base class of every error hkproof raises on purpose."""


class ParseError(HKProofError):
    """An expression could not be read as a rational function in the ring's variables."""


class UnknownSymbolError(ParseError):
    """An expression uses a symbol that is neither a variable nor a parameter of the system."""


class FormulaTooLargeError(ParseError):
    """A formula asks for more than the documented limits allow (a huge literal, exponent or expansion)."""


class RingMismatchError(HKProofError):
    """Two rational functions from different rings were combined; convert one with Frac.to_ring first."""


class NotQuadraticError(HKProofError):
    """A vector field is not of degree <= 2 in the phase variables (Kahan's scheme needs eq. "Kahan gen")."""


class SingularPointError(HKProofError):
    """The Kahan map is not defined at a point: det M(x, eps) = 0 there."""


class SingularSystemError(HKProofError):
    """A linear system has a determinant that vanishes identically, so it has no unique solution."""


class UnknownSystemError(HKProofError):
    """A system name is neither in the catalogue nor a readable TOML file."""


class UnknownClaimError(HKProofError):
    """A theorem id is not in the registry."""


class DependentBasisError(ParseError):
    """The functions of a candidate HK-basis are linearly dependent (Def. "Hirota mech" needs independence)."""


class UsageError(HKProofError):
    """A command line that does not fit the command's options (a missing argument, a bad count, an unknown name)."""


class MissingDependencyError(HKProofError):
    """An optional extra is needed and not installed (e.g. Sage interop: pip install 'hkproof[sage]')."""


class OutputError(HKProofError):
    """Output could not be written where it was asked to go (a FILE that is no regular file, a directory that takes
    no new file, a closed or failing output stream)."""


class CertificateError(HKProofError):
    """A certificate file that cannot be checked: not JSON, another format or version, a missing or ill-typed entry,
    a step kind the checker does not know, or a step whose data does not make the claimed argument (exit 2)."""


class ShapeError(HKProofError):
    """Matrices or vectors whose sizes do not fit (a row of another length, a vector of the wrong dimension)."""


class ResourceLimitError(HKProofError):
    """A computation would exceed one of hkproof's documented limits (not bad input: the input is fine, the search is
    too large). The message says what happened; `limit` names the limit and `raise_with` how to raise it (or that no
    option raises it), for `--json` and for scripts.

    >>> e = ResourceLimitError("too many cofactors", limit="400 candidate cofactors", raise_with="no option raises it")
    >>> str(e), e.limit, e.raise_with
    ('too many cofactors', '400 candidate cofactors', 'no option raises it')
    """

    def __init__(self, message: str, *, limit: str | None = None, raise_with: str | None = None) -> None:
        super().__init__(message)
        self.limit = limit
        self.raise_with = raise_with

    def __reduce__(self) -> tuple:
        """Pickled with its limit (an error raised in a worker process reaches the parent whole)."""
        return type(self), (str(self),), {"limit": self.limit, "raise_with": self.raise_with}


class BudgetExhausted(ResourceLimitError):
    """The time or memory budget ran out; what was covered so far is reported."""


class UnluckyPrimeError(SingularPointError):
    """A computation mod p failed where it may succeed over Q (a denominator or det M divisible by p): try another
    prime."""


class CitationCycleError(UnknownClaimError):
    """The declared citations of the registry form a cycle: no claim on it can be proven first."""


class DependenceSearchError(HKProofError):
    """The search could not collect enough exact samples (every point hit a pole)."""


class RelationSearchError(HKProofError):
    """Relation finding could not proceed (no one-dimensional kernel, or not enough good samples)."""


class NotHamiltonianError(ParseError):
    """H, J and the field do not fit: J not constant or not skew, H not cubic, or F != J grad H."""


class Refuted(Exception):
    """Raised inside a proof step when the claim checked there is false (control flow of the proof kernel)."""


class ProofStopped(Exception):
    """A proof step did not verify; the remaining steps are not run (control flow of the proof kernel)."""


class Refutation(Exception):
    """A stated identity of a certificate is false (control flow inside the checker)."""


class Interrupted(KeyboardInterrupt):
    """An interrupt signal arrived; a KeyboardInterrupt, so everything that stops cleanly on Ctrl-C stops on it."""

    def __init__(self, signum: int) -> None:
        super().__init__(signal.Signals(signum).name)
        self.signum = signum

    def __reduce__(self) -> tuple:
        return type(self), (self.signum,)

    @property
    def label(self) -> str:
        """How the summary names the interrupt: Ctrl-C for SIGINT, the signal's name otherwise."""
        return "Ctrl-C" if self.signum == signal.SIGINT else signal.Signals(self.signum).name
