"""Strict reading of a certificate file (docs/certificates.md, "Threat model"): JSON with no duplicate key, no float,
no huge integer, no deep nesting; every entry of the type the format says (a boolean is not an integer); step kinds
and features gated by the file's version; field keys ASCII. Anything else is a CertificateError (malformed, exit 2).

>>> load(b'{"a": 1, "a": 2}')
Traceback (most recent call last):
hkproof.errors.CertificateError: the key 'a' appears twice in one JSON object: a reader could take either value
>>> integers({"iterates": [0, True]}, "iterates", "step 1")
Traceback (most recent call last):
hkproof.errors.CertificateError: step 1: every entry of 'iterates' must be a JSON integer (not a boolean or a string)
"""
from __future__ import annotations

import json
import re
from typing import Any

from hkproof.errors import CertificateError

__all__ = ["FORMAT", "VERSIONS", "CONVENTION", "SINCE", "MAX_BYTES", "load", "get", "optional_list", "strings",
           "integers", "entries", "field_key", "version_gate"]

FORMAT, CONVENTION = "hkproof-certificate", "eps = h/2"
VERSIONS = (1, 2, 3, 4, 5, 6, 7, 8, 9, 10)    # 2: darboux, recipe-g; 3: degrees, cofactor "det Df"; 4: prop-even blocks;
# 5: reparametrization; 6: every claimed integral and density names its field, field keys ASCII; 7: bivector steps
# (bivector-invariance, jacobi, casimir, involution, exclusion) and the claim's bivectors; 8: affine-change; 9: no-poisson;
# 10: nambu
SINCE = {"substitution": 1, "prop-even": 1, "darboux": 2, "recipe-g": 2, "densities": 2, "degrees": 3,
         "det Df": 3, "blocks": 4, "reparametrization": 5, "bivector-invariance": 7, "jacobi": 7, "casimir": 7,
         "involution": 7, "exclusion": 7, "bivectors": 7, "affine-change": 8, "no-poisson": 9, "nambu": 10}
MAX_BYTES = 200_000_000
MAX_INTEGER_DIGITS = 18          # JSON integers are versions, iterates and degrees: numbers are strings ('13/46')
_KEY = re.compile(r"[A-Za-z][A-Za-z0-9_.-]{0,99}\Z")


def load(raw: bytes) -> Any:
    """The decoded JSON of a certificate file, read strictly."""
    try:
        return json.loads(raw.decode("utf-8"), object_pairs_hook=_unique, parse_float=_no_float,
                          parse_constant=_no_float, parse_int=_small_int)
    except RecursionError:
        raise CertificateError("the JSON is nested too deeply to be a certificate") from None
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise CertificateError(f"not a JSON certificate: {exc}") from None


def _unique(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            raise CertificateError(f"the key {key!r} appears twice in one JSON object: a reader could take either "
                                   "value")
        out[key] = value
    return out


def _no_float(text: str) -> None:
    raise CertificateError(f"the number {text} is written as a JSON float; certificates write numbers as exact text "
                           "('3/7')")


def _small_int(text: str) -> int:
    if len(text.lstrip("-")) > MAX_INTEGER_DIGITS:
        raise CertificateError(f"a JSON integer of {len(text)} digits; certificates write integers of at most "
                               f"{MAX_INTEGER_DIGITS} digits (numbers are text such as '13/46')")
    return int(text)


def get(obj: Any, key: str, kind: type, where: str) -> Any:
    """obj[key] of the given JSON type (a boolean is no integer), or a CertificateError naming the place."""
    if not isinstance(obj, dict) or key not in obj:
        raise CertificateError(f"{where}: the entry {key!r} is missing")
    value = obj[key]
    if not isinstance(value, kind) or (isinstance(value, bool) and kind is not bool):
        raise CertificateError(f"{where}: {key!r} must be a JSON {_NAMES.get(kind, kind.__name__)}, got "
                               f"{_NAMES.get(type(value), type(value).__name__)}")
    return value


_NAMES = {dict: "object", list: "list", str: "string", int: "integer", bool: "boolean", type(None): "null"}


def optional_list(obj: dict, key: str, where: str) -> list:
    """obj[key] as a list, [] when absent."""
    return get(obj, key, list, where) if key in obj else []


def strings(obj: Any, key: str, where: str) -> list[str]:
    values = get(obj, key, list, where)
    if not all(isinstance(v, str) for v in values):
        raise CertificateError(f"{where}: every entry of {key!r} must be a string")
    return values


def integers(obj: Any, key: str, where: str) -> list[int]:
    values = get(obj, key, list, where)
    if not all(isinstance(v, int) and not isinstance(v, bool) for v in values):
        raise CertificateError(f"{where}: every entry of {key!r} must be a JSON integer (not a boolean or a string)")
    return values


def entries(obj: Any, key: str, where: str, required: bool = True) -> list[dict]:
    """obj[key], a list of JSON objects ([] when absent and not `required`)."""
    values = get(obj, key, list, where) if required or (isinstance(obj, dict) and key in obj) else []
    if not all(isinstance(v, dict) for v in values):
        raise CertificateError(f"{where}: every entry of {key!r} must be a JSON object")
    return values


def field_key(key: str, version: int) -> str:
    """A field's key: from version 6 on an ASCII identifier (a letter, then letters, digits, '_', '.', '-'), so that
    no look-alike character (a non-breaking hyphen) can name a second field that reads like the first."""
    if version >= 6 and not _KEY.match(key):
        raise CertificateError(f"the field key {key[:60]!r} is not an ASCII identifier (a letter, then letters, "
                               "digits, '_', '.' or '-', at most 100)")
    return key


def version_gate(feature: str, version: int, where: str) -> None:
    """Refuse a step kind or feature newer than the file's version: an old file means what it meant when written."""
    if version < SINCE.get(feature, 1):
        raise CertificateError(f"{where}: {feature!r} is a feature of version {SINCE[feature]}; a version-{version} "
                               "certificate cannot carry it")
