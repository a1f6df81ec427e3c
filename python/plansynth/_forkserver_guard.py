"""Imported by the multiprocessing fork server (see :mod:`plansynth.isolate`): the
fork server then dies when the process that started it dies, so that ``SIGKILL`` of a
``plansynth`` command leaves no fork server behind (its children die with it in turn).

Imported anywhere else (by a doctest collector, say) it does nothing: it acts only when
called from :func:`multiprocessing.forkserver.main`.
"""

import sys


def _in_forkserver() -> bool:
    frame = sys._getframe(1)
    while frame is not None:
        code = frame.f_code
        if code.co_name == "main" and code.co_filename.replace("\\", "/").endswith("multiprocessing/forkserver.py"):
            return True
        frame = frame.f_back
    return False


if _in_forkserver():
    from plansynth.procs import die_with_parent

    die_with_parent()
