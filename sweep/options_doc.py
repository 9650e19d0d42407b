"""Write the reference of the analyses' options, ``docs/options.md``, from their ``OPTIONS``.

Usage (from the repository root)::

    python -m sweep.options_doc [-o docs/options.md]

The test suite checks that the file in the repository is what this writes.
"""

from __future__ import annotations

import argparse
import importlib
from pathlib import Path

from sweep.analyses import BUILTIN


def render() -> str:
    """The Markdown text of the options reference."""
    lines = ["# Options of the analyses", "",
             "The table `[<analysis>]` of a job file takes these keys (anything else is refused with the",
             "list of the allowed ones). Generated from the analyses' `OPTIONS` by",
             "`python -m sweep.options_doc`; do not edit by hand. Grid keys, `[grid] cases` and the",
             "`[job]` and `[membrane]` tables are described in `docs/running.md`.", ""]
    for name, target in BUILTIN.items():
        module, _, attribute = target.partition(":")
        analysis = getattr(importlib.import_module(module), attribute)
        lines += [f"## `{name}`", "", "| key | meaning |", "|---|---|"]
        lines += [f"| `{key}` | {text.replace('|', chr(92) + '|')} |" for key, text in analysis.OPTIONS.items()]
        lines.append("")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m sweep.options_doc", description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", type=Path, default=Path("docs/options.md"))
    args = parser.parse_args(argv)
    args.output.write_text(render())
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
