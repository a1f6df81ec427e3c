"""A minimal cvc5 command line for SyGuS-IF v2 files, on top of cvc5's Python API.

The cvc5 wheel ships no binary; this stands in for ``cvc5 --lang=sygus2 FILE`` so that
a compiled .sl file can be rerun by hand, and so that the ``external`` backend can be
exercised end to end with a real solver::

    python -m plansynth.grid.backends.cvc5_cli figure1-l6.sl
    python -m plansynth.grid.backends.cvc5_cli --sygus-enum=fast figure1-l6.sl

It prints what the commands print (for ``(check-synth)``: the ``define-fun``s,
``infeasible`` or ``fail``). Options are cvc5's, written ``--KEY=VALUE``. Exit status 0
on success, 1 on a parse or solver error (the message goes to stderr).
"""

from __future__ import annotations

import sys

from plansynth.errors import InvalidProblem
from plansynth.grid.backends.cvc5 import parse_options, run_sygus_text
from plansynth.io import read_text


def main(argv: list[str] | None = None) -> int:
    args = list(sys.argv[1:] if argv is None else argv)
    files = [a for a in args if not a.startswith("--")]
    if len(files) != 1 or "--help" in args:
        print(__doc__.strip(), file=sys.stderr)
        return 0 if "--help" in args else 2
    options = parse_options([a for a in args if a.startswith("--")])
    try:
        text, _ = read_text(files[0])  # regular UTF-8 file within plansynth's size limit
        sys.stdout.write(run_sygus_text(text, options, files[0]))
    except (OSError, RuntimeError, InvalidProblem) as exc:
        print(f'(error "{str(exc).strip()}")', file=sys.stderr)
        return 1
    sys.stdout.flush()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
