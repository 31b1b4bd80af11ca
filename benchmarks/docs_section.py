"""Write one benchmark's block between its markers in a docs page (the rest of the page is kept)."""
from __future__ import annotations

import re
from pathlib import Path


def write_section(doc: Path, name: str, lines: list[str]) -> str:
    """Replace (or append) the block <!-- name:begin --> ... <!-- name:end --> of `doc` by `lines`."""
    begin, end = f"<!-- {name}:begin -->", f"<!-- {name}:end -->"
    block = "\n".join([begin, "", *lines, "", end])
    text = doc.read_text() if doc.exists() else "# Performance\n\n"
    if begin in text:
        text = re.sub(re.escape(begin) + ".*?" + re.escape(end), lambda _: block, text, flags=re.S)
    else:
        text += "\n" + block + "\n"
    doc.write_text(text)
    return block
