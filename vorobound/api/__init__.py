"""The workflows behind the commands: one function per ``vorobound`` command.

Each function takes keyword arguments named like the command's options, runs the whole
workflow (the bounds, sampling, reports, figures and files it needs) and returns a frozen
result whose :meth:`~vorobound.api.result.Result.to_dict` is exactly what the command prints
with ``--json``. The command line parses, calls one of these, and renders; ``vorobound.solve``
and the other top-level names are these functions.
"""
