"""The ``vorobound`` command line (typer). Thin: parse, call the library, format.

Heavy modules (numpy-based geometry, scipy, matplotlib) are imported inside the commands so
that ``vorobound --help`` starts fast.
"""

from __future__ import annotations

import sys

import typer

from ..errors import VoroboundError
from .advise_cmd import advise
from .bounds_cmd import bounds, solve
from .cheng_cmd import cheng
from .figures_cmd import figure, reproduce
from .sweep_cmd import sweep
from .triangle_cmd import triangle
from .validate_cmd import validate

app = typer.Typer(
    name="vorobound",
    no_args_is_help=True,
    add_completion=False,
    help=(
        "Weighted-triangle geometry (circumradius vs orthoradius, Theorem 1) and the "
        "VoroCrust sampling bounds, audited."
    ),
)


@app.callback()
def _root() -> None:
    """Weighted-triangle geometry (Theorem 1) and the VoroCrust sampling bounds, audited.

    Every command has --help and --json; errors print one line and exit with code 2.
    """


app.command("reproduce")(reproduce)
app.command("figure")(figure)
app.command("triangle")(triangle)
app.command("bounds")(bounds)
app.command("solve")(solve)
app.command("validate")(validate)
app.command("sweep")(sweep)
app.command("advise")(advise)
app.command("cheng")(cheng)


def main(argv: list[str] | None = None) -> int:
    """Run the CLI and return its exit code; errors become one line on stderr and code 2."""
    args = sys.argv[1:] if argv is None else list(argv)
    if not args:
        args = ["--help"]
    try:
        result = app(args=args, prog_name="vorobound", standalone_mode=False)
    except VoroboundError as exc:
        return _fail(str(exc), 2)
    except typer.TyperException as exc:  # usage errors (exit code 2) and friends
        return _fail(exc.format_message(), getattr(exc, "exit_code", 1))
    except typer.Exit as exc:
        return exc.exit_code
    except typer.Abort:
        return _fail("aborted", 1)
    except KeyboardInterrupt:
        return _fail("interrupted", 130)
    return result if isinstance(result, int) else 0


def _fail(message: str, code: int) -> int:
    print(f"error: {' '.join(str(message).split())}", file=sys.stderr)
    return code


def entry() -> None:
    """Console-script entry point."""
    sys.exit(main())
