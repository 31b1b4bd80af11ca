"""Every registered theorem: proven (status verified, citing exactly what it declares) and not verified when any
claimed formula is perturbed: by a value, or (a matrix or list) by its shape."""
from __future__ import annotations

import re

import pytest

from hkproof.orchestration.registry import load_all
from hkproof.proof.status import Status
from tests.conftest import THEOREM_RESULTS

CLAIMS = list(load_all().values())


def _param(c):
    return pytest.param(c, id=c.id, marks=[pytest.mark.slow] if c.slow else [])


def perturb(text: str) -> str:
    """A small change of a claimed formula: add 1/7 (to the first entry of a matrix or vector)."""
    if text.lstrip().startswith("["):
        return re.sub(r"^(\s*\[+)", r"\g<1>1/7 + ", text, count=1)
    return f"({text}) + 1/7"


def _items(text: str) -> list[str]:
    """The top-level entries of '[a, b, [c, d]]' (commas inside brackets or parentheses do not split)."""
    items, depth, start = [], 0, 1
    body = text.strip()
    for k, ch in enumerate(body[1:-1], start=1):
        depth += ch in "([" and 1 or (ch in ")]" and -1 or 0)
        if ch == "," and depth == 0:
            items.append(body[start:k].strip())
            start = k + 1
    return items + [body[start:-1].strip()]


def _rows(text: str) -> tuple[list[list[str]], bool, str] | None:
    """A claimed matrix or list as rows of entries, whether it is a matrix, and its notation; None for a formula."""
    if text.lstrip().startswith("["):
        items = _items(text)
        if all(i.startswith("[") for i in items):
            return [_items(i) for i in items], True, "brackets"
        return [items], False, "brackets"
    if re.fullmatch(r"[\d\s;]+", text) and " " in text.strip():
        return [row.split() for row in text.split(";")], ";" in text, "table"
    return None


def _text(rows: list[list[str]], matrix: bool, notation: str) -> str:
    if notation == "table":
        return "; ".join(" ".join(row) for row in rows)
    inner = ", ".join("[" + ", ".join(row) + "]" for row in rows) if matrix else ", ".join(rows[0])
    return f"[{inner}]"


def _swapped(seq: list) -> list | None:
    """`seq` with its first two different entries exchanged (None if all entries are equal)."""
    for i in range(len(seq)):
        for j in range(i + 1, len(seq)):
            if seq[i] != seq[j]:
                out = list(seq)
                out[i], out[j] = out[j], out[i]
                return out
    return None


def shape_perturbations(text: str) -> dict[str, str]:
    """A claimed matrix or list with the right entries in the wrong shape: an extra row (or entry), a missing
    entry, a swapped pair (two different rows of a matrix, two different entries of a list)."""
    parsed = _rows(text)
    if parsed is None:
        return {}
    rows, matrix, notation = parsed
    out = {"extra-row": rows + [rows[-1]] if matrix else [rows[0] + [rows[0][-1]]],
           "missing-entry": [rows[0][:-1]] + rows[1:]}
    swapped = _swapped(rows) if matrix else (_swapped(rows[0]) and [_swapped(rows[0])])
    if swapped:
        out["swapped-pair"] = swapped
    return {kind: _text(new, matrix, notation) for kind, new in out.items()}


@pytest.mark.parametrize("claim", [_param(c) for c in CLAIMS])
def test_theorem_verified(claim, record_property):
    cert = claim.prove()
    THEOREM_RESULTS.append((claim.id, cert.status.label, cert.seconds))
    record_property("status", cert.status.label)
    record_property("seconds", round(cert.seconds, 4))
    assert claim.succeeded(cert), cert.render()
    if not claim.is_open:
        assert cert.status is Status.VERIFIED
    assert sorted(cert.cites) == sorted(claim.uses), f"{claim.id} cites {cert.cites}, declares uses={claim.uses}"


PERTURBATIONS = [pytest.param(c, key, id=f"{c.id}:{key}", marks=[pytest.mark.slow] if c.slow else [])
                 for c in CLAIMS for key in c.claimed]


@pytest.mark.parametrize("claim,key", PERTURBATIONS)
def test_perturbed_claim_not_verified(claim, key):
    cert = claim.prove({key: perturb(claim.claimed[key])})
    assert not claim.succeeded(cert), f"perturbing {key} left {claim.id} {cert.status.label}"


# Shape perturbations (an extra row, a missing entry, a swapped pair): every prover compares lengths (issue 11, item 6).
SHAPES = [pytest.param(c, key, text, id=f"{c.id}:{key}:{kind}", marks=[pytest.mark.slow] if c.slow else [])
          for c in CLAIMS for key in c.claimed for kind, text in shape_perturbations(c.claimed[key]).items()]


@pytest.mark.parametrize("claim,key,text", SHAPES)
def test_shape_perturbed_claim_not_verified(claim, key, text):
    cert = claim.prove({key: text})
    assert not claim.succeeded(cert), f"{key} = {text} left {claim.id} {cert.status.label}"
