"""Write the reference of the options, ``docs/options.md``: the analyses' ``OPTIONS``, the
models', the material laws' and the damping laws' constants.

Usage (from the repository root)::

    python -m sweep.options_doc [-o docs/options.md]

The test suite checks that the file in the repository is what this writes.
"""

from __future__ import annotations

import argparse
import importlib
from pathlib import Path

from dataclasses import fields

from model.damping import LAWS
from model.materials import LAW_CONSTANTS
from model.params import Membrane
from sweep import models
from sweep.analyses import BUILTIN
from sweep.models import BUILTIN as MODELS


def render() -> str:
    """The Markdown text of the options reference."""
    lines = ["# Options of the analyses", "",
             "The table `[<analysis>]` of a job file takes these keys (anything else is refused with the",
             "list of the allowed ones). Generated from the analyses' `OPTIONS` by",
             "`python -m sweep.options_doc`; do not edit by hand. Grid keys, `[grid] cases` and the",
             "`[job]` and `[membrane]` tables are described in `docs/running.md`; the `[model]` table,",
             "the material laws of `[membrane]` and the `[damping]` table come last.", ""]
    for name, target in BUILTIN.items():
        module, _, attribute = target.partition(":")
        analysis = getattr(importlib.import_module(module), attribute)
        lines += [f"## `{name}`", "", "| key | meaning |", "|---|---|"]
        lines += [f"| `{key}` | {text.replace('|', chr(92) + '|')} |" for key, text in analysis.OPTIONS.items()]
        lines.append("")
    lines += ["## `[model]`", "",
              "`kind` names the model that computes the tasks (default `\"rom\"`); the rest of the table",
              "is that model's. Models of one's own are registered through `SWEEP_EXTRA_MODELS`",
              "(`docs/architecture.md`).", "", "| kind | keys besides `kind` | membrane grid keys it needs |",
              "|---|---|---|"]
    for name in MODELS:
        model = models.get(name)
        keys = ", ".join(f"`{k}`: {t.replace('|', chr(92) + '|')}" for k, t in model.OPTIONS.items()) or "none (the ROM's `modes`, "\
            "`prestretch` and `steps` are the analysis' options)"
        lines.append(f"| `{name}` | {keys} | {', '.join(f'`{k}`' for k in model.required_grid) or 'none'} |")
    lines += ["", "## `[membrane]` law", "",
              "`law` chooses the strain-energy law (default `\"neo-hookean\"`); its constants may be given in",
              "`[membrane]` or as grid keys (not both), and a constant of another law is refused.",
              "`docs/model.md` (\"Material laws\") states each law; the other `[membrane]` keys are in",
              "`docs/running.md`.", "", "| law | constant | units | meaning |", "|---|---|---|---|"]
    meta = {f.name: f.metadata for f in fields(Membrane)}
    for name, constants in LAW_CONSTANTS.items():
        for key in ("C1", *constants):
            lines.append(f"| `{name}` | `{key}` | {meta[key]['units']} | {meta[key]['long_name']} |")
    lines += ["", "## `[damping]`", "",
              "`law` chooses the damping law (default `\"viscous\"`); its constants may be given here or as",
              "grid keys (not both). `docs/model.md` (\"Damping laws\") states each law.", "",
              "| law | constant | units | meaning |", "|---|---|---|---|"]
    for name, law in LAWS.items():
        for f in fields(law):
            lines.append(f"| `{name}` | `{f.name}` | {f.metadata['units']} | {f.metadata['long_name']} |")
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
