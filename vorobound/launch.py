"""The console-script and ``python -m vorobound`` entry: imports the command line inside a
guard, so that Ctrl-C while it loads (about half a second: typer, rich) ends the run with one
line and exit 130, as it does once a command runs, instead of a traceback of the import."""

import os
import sys

EXIT_INTERRUPTED = 130


def entry() -> None:
    """Load and run the command line (:func:`vorobound.cli.entry`)."""
    try:
        from .cli import entry as run
    except KeyboardInterrupt:
        _interrupted()
    try:
        run()
    except KeyboardInterrupt:  # before main() put its handlers in place
        _interrupted()


def _interrupted() -> None:
    try:
        sys.stderr.write("interrupted\n")
        sys.stderr.flush()
    except (OSError, ValueError, AttributeError):
        pass
    os._exit(EXIT_INTERRUPTED)
