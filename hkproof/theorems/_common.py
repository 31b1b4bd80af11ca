"""Small helpers shared by the theorem modules: reading claimed formulas in a map's ring; the file steps of a Nambu
structure."""
from __future__ import annotations

from hkproof.algebra import formula
from hkproof.algebra.fraction import Frac
from hkproof.dynamics.kahan import KahanMap
from hkproof.hk.nambu import NambuStructure, bivector_steps
from hkproof.pipelines.discover.certificate import discover_steps
from hkproof.pipelines.discover.report import DiscoveryReport


def parse(kmap: KahanMap, text: str) -> Frac:
    """A claimed formula as an element of Q(x, eps, params) of the map."""
    return Frac.parse(kmap.ring, text)


def parse_matrix(kmap: KahanMap, text: str) -> list[list[Frac]]:
    """A claimed matrix written as a nested list '[[a, b], [c, d]]'."""
    return formula.parse_matrix(kmap.ring, text)


def nambu_checks(kmap: KahanMap, report: DiscoveryReport, structure: NambuStructure) -> list[dict]:
    """The re-checkable steps of a Nambu structure built on the integrals of `report`: discover's own steps for them,
    then the structure's (`hk.nambu.bivector_steps`: written out when small, else its density and a nambu step);
    none when the structure has none."""
    written = bivector_steps(kmap.field, structure, "Pi")
    return [*discover_steps(report), *written] if written else []
