"""Regenerate the benchmark outputs of ``docs/performance.md`` by running the benchmarks.

Every measured block of the page follows a marker line naming the command that printed it::

    <!-- benchmark: python benchmarks/bench_rk4.py --repeats 7 -->
    ```text
    (the command's output)
    ```

This script runs each marked command from the repository root (one after the other: the
benchmarks time themselves and must not share the cores) and replaces the block after its
marker with the command's standard output, headed by the commit and the date of the run.
The prose around the blocks says what the numbers mean; the numbers themselves are only
ever in these blocks.  Run::

    python benchmarks/report.py                   # every block (about 20 minutes)
    python benchmarks/report.py bench_rk4         # only the blocks of these benchmarks
    python benchmarks/report.py --match "--modes 3"   # only the blocks whose command has this
    python benchmarks/report.py --list            # the commands, nothing run
"""

from __future__ import annotations

import argparse
import datetime
import re
import shlex
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "performance.md"
#: A marker line and the fenced block after it.
BLOCK = re.compile(r"(<!-- benchmark: (?P<command>[^\n]*?) -->\n)```text\n.*?^```\n", re.S | re.M)


def commands(text: str) -> list[str]:
    """The commands of the marked blocks of ``text``, in page order.

    Raises
    ------
    SystemExit
        If a marker is not followed by a ``text`` block (the page would not be rewritten
        there).
    """
    found = [m.group("command") for m in BLOCK.finditer(text)]
    if len(found) != text.count("<!-- benchmark: "):
        raise SystemExit(f"{PAGE}: a '<!-- benchmark: ... -->' marker is not directly followed by a ```text block")
    return found


def _run(command: str) -> str:
    argv = shlex.split(command)
    if argv[0] == "python":
        argv[0] = sys.executable
    proc = subprocess.run(argv, cwd=ROOT, capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"{command} failed (exit {proc.returncode}):\n{proc.stderr}")
    if "```" in proc.stdout:
        raise SystemExit(f"{command} printed a code fence (```), which would end its block early")
    return proc.stdout


def _stamp() -> str:
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                            text=True).stdout.strip() or "unknown"
    # the page itself does not count: an earlier run of this script may have rewritten it
    dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no", "--", ".",
                            f":!{PAGE.relative_to(ROOT)}"], cwd=ROOT, capture_output=True, text=True).stdout.strip()
    return f"# commit {commit}{' (with uncommitted changes)' if dirty else ''}, {datetime.date.today()}"


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("only", nargs="*", help="benchmark names (bench_rk4, ...): only their blocks")
    ap.add_argument("--match", default="", help="only the commands that contain this text")
    ap.add_argument("--list", action="store_true", help="print the commands and stop")
    args = ap.parse_args(argv)
    text = PAGE.read_text()
    wanted = [c for c in commands(text) if (not args.only or any(f"/{name}.py" in c for name in args.only))
              and args.match in c]
    if args.list or not wanted:
        print("\n".join(wanted) or "no marked block matches")
        return
    stamp = _stamp()
    outputs = {}
    for command in wanted:
        print(f"running {command}", flush=True)
        outputs[command] = _run(command)

    def replace(m):
        command = m.group("command")
        if command not in outputs:
            return m.group(0)
        return f"{m.group(1)}```text\n{stamp}\n{outputs[command].rstrip()}\n```\n"

    PAGE.write_text(BLOCK.sub(replace, text))
    print(f"wrote {PAGE.relative_to(ROOT)} ({len(outputs)} block(s))")


if __name__ == "__main__":
    main()
