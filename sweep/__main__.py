"""``python -m sweep``: see :mod:`sweep.cli`."""

from sweep.cli import exit_main

exit_main()
