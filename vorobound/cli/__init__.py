"""The ``vorobound`` command line (typer). Thin: parse, call the library, format.

Heavy modules (numpy, scipy, matplotlib) are imported inside the commands, so that
``vorobound --help`` imports none of them. :func:`main` is the single place that turns failures
into exit codes: a :class:`~vorobound.errors.VoroboundError` or a usage error is one line on
stderr and code 2, Ctrl-C or SIGTERM is "interrupted" and code 130, and anything unexpected is
one line saying it is a bug (code 70; the traceback with ``--debug`` or ``VOROBOUND_DEBUG=1``).
A reader that stops reading the output (``vorobound ... | head``) ends the run quietly with
code 141, as a broken pipe ends a program in the shell.

For programs that stop a run with a signal (the tests do): with the environment variable
``VOROBOUND_SIGNALS_READY`` set to a non-empty value, the command prints the line
``vorobound: signal handlers installed`` on stderr once SIGINT and SIGTERM are handled; a
signal sent after that line ends the run with "interrupted" and code 130, never earlier.
"""

from __future__ import annotations

import contextlib
import errno
import os
import signal
import sys
import threading
import time
import warnings

import typer

from ..errors import VoroboundError, VoroboundWarning
from .advise_cmd import advise
from .bounds_cmd import bounds
from .certify_cmd import certify
from .check_cmd import check
from .cheng_cmd import cheng
from .figure_cmd import figure
from .lfs_cmd import lfs
from .reconstruct_cmd import reconstruct
from .reproduce_cmd import reproduce
from .sample_cmd import sample
from .solve_cmd import solve
from .sweep_cmd import sweep
from .triangle_cmd import triangle
from .validate_cmd import validate

EXIT_ERROR = 2
"""Bad input, or a result that cannot be computed."""
EXIT_BUG = 70
"""An unexpected exception (EX_SOFTWARE): a bug in vorobound."""
EXIT_INTERRUPTED = 130
"""Ctrl-C or SIGTERM."""
EXIT_BROKEN_PIPE = 128 + signal.SIGPIPE
"""The reader of the output went away (141: what a shell reports for a program that SIGPIPE
ended). Not 1, which for a verifying command would read as "found a violation"."""

app = typer.Typer(
    name="vorobound",
    no_args_is_help=True,
    add_completion=False,
    context_settings={"help_option_names": ["-h", "--help"]},
    help=(
        "Weighted-triangle geometry (circumradius vs orthoradius, Theorem 1) and the "
        "VoroCrust sampling bounds, audited."
    ),
)


def _print_version(value: bool) -> None:
    if value:
        from .. import __version__

        print(f"vorobound {__version__}")
        raise typer.Exit(0)


@app.callback()
def _root(
    debug: bool = typer.Option(
        False, "--debug", metavar="", help="Show the traceback of an unexpected error (a bug)."
    ),
    version: bool = typer.Option(
        False,
        "--version",
        metavar="",
        callback=_print_version,
        is_eager=True,
        help="Print the version and exit.",
    ),
) -> None:
    """Weighted-triangle geometry (Theorem 1) and the VoroCrust sampling bounds, audited.

    Every command has --help and prints a table for people or, with --json, one JSON object
    for programs. Errors print one line on stderr and exit with code 2; Ctrl-C exits with 130.
    """
    if debug:
        os.environ["VOROBOUND_DEBUG"] = "1"


app.command("reproduce")(reproduce)
app.command("figure")(figure)
app.command("triangle")(triangle)
app.command("bounds")(bounds)
app.command("solve")(solve)
app.command("validate")(validate)
app.command("sweep")(sweep)
app.command("advise")(advise)
app.command("cheng")(cheng)
app.command("certify")(certify)
app.command("sample")(sample)
app.command("check")(check)
app.command("lfs")(lfs)
app.command("reconstruct")(reconstruct)


class Interrupted(BaseException):
    """Raised by the SIGINT/SIGTERM handlers (not KeyboardInterrupt, which click swallows)."""


def _usage_errors() -> tuple[type[BaseException], ...]:
    """The usage-error base classes of the installed typer/click (they moved between versions)."""
    found = [getattr(typer, "TyperException", None)]
    with contextlib.suppress(ImportError):
        import click

        found.append(click.exceptions.ClickException)
    return tuple(t for t in found if isinstance(t, type))


SIGNALS_READY_VARIABLE = "VOROBOUND_SIGNALS_READY"
"""Environment variable: when set, a command says on stderr when its signal handlers are in."""
SIGNALS_READY_LINE = "vorobound: signal handlers installed"


@contextlib.contextmanager
def _signals_raise_interrupted():
    """While running a command, SIGINT and SIGTERM raise :class:`Interrupted` (main thread)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def handler(signum, frame):
        _wait_for_native_workers()
        raise Interrupted

    previous = {sig: signal.signal(sig, handler) for sig in (signal.SIGINT, signal.SIGTERM)}
    if os.environ.get(SIGNALS_READY_VARIABLE):
        # For tests: SIGUSR1 prints every thread's stack (where a run that does not stop is).
        import faulthandler

        with contextlib.suppress(AttributeError, ValueError, RuntimeError, OSError):
            faulthandler.register(signal.SIGUSR1, all_threads=True)
        print(SIGNALS_READY_LINE, file=sys.stderr, flush=True)
    try:
        yield
    finally:
        for sig, old in previous.items():
            signal.signal(sig, old)


NATIVE_WORKER_WAIT = 60.0
"""Seconds an interrupt waits at most for native worker threads to finish (see below)."""
NATIVE_START_WAIT = 1.0
"""Seconds an interrupt waits at most for a native worker thread listed but not started."""


def _wait_for_native_workers() -> None:
    """Let scipy's k-d tree worker threads finish before the main thread unwinds: they write
    into arrays that the unwinding frees, so raising while they run can crash the process
    instead of exiting with 130. They finish their share of one query.

    A signal can come while a query is starting its threads: one may be listed but not yet
    started, which ``join`` refuses (RuntimeError, an exit 70 "internal error" instead of 130,
    and the half-started thread's KeyError traceback). Such a thread is given
    :data:`NATIVE_START_WAIT` to start (the signal may also have come before its system thread
    was made: then it never starts), then joined."""
    deadline = time.monotonic() + NATIVE_WORKER_WAIT
    for thread in threading.enumerate():
        target = getattr(thread, "_target", None)
        module = getattr(target, "__module__", None) or ""
        if thread is threading.current_thread() or not module.startswith("scipy."):
            continue
        started = getattr(thread, "_started", None)
        if started is not None:
            started.wait(min(NATIVE_START_WAIT, max(0.0, deadline - time.monotonic())))
        with contextlib.suppress(RuntimeError):  # still not started: nothing of it runs
            thread.join(max(0.0, deadline - time.monotonic()))


class _ClosedStream:
    """Stands for a standard stream the process was started without (``>&-``): writing to it
    fails like writing to a closed descriptor, so the run ends with one line and exit 2."""

    def write(self, text: str) -> int:
        raise OSError(errno.EBADF, "standard output is closed")

    def flush(self) -> None:
        pass

    def isatty(self) -> bool:
        return False


def _tolerant_streams() -> None:
    """Never fail on characters the terminal's encoding lacks (e.g. PYTHONIOENCODING=ascii),
    nor on a standard stream that is missing."""
    if sys.stdout is None:
        sys.stdout = _ClosedStream()
    if sys.stderr is None:
        sys.stderr = open(os.devnull, "w")  # noqa: SIM115 (for the life of the process)
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(AttributeError, ValueError, OSError):
            stream.reconfigure(errors="replace")  # type: ignore[union-attr]
    from .notation import ascii_stream  # ε, R̂, ≤ spelt eps, R_hat, <= where they cannot show

    sys.stdout, sys.stderr = ascii_stream(sys.stdout), ascii_stream(sys.stderr)


@contextlib.contextmanager
def _warnings_as_lines():
    """Runtime chatter (numpy's floating-point notices, readers) is silenced; a
    :class:`~vorobound.errors.VoroboundWarning` is printed as one "warning:" line on stderr."""

    def show(message, category, filename, lineno, file=None, line=None):
        text = " ".join(str(message).split())
        with contextlib.suppress(OSError, ValueError):
            print(f"warning: {text}", file=sys.stderr)

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        warnings.simplefilter("always", VoroboundWarning)
        previous, warnings.showwarning = warnings.showwarning, show
        try:
            yield
        finally:
            warnings.showwarning = previous


def main(argv: list[str] | None = None) -> int:
    """Run the CLI and return its exit code (see the module docstring)."""
    args = sys.argv[1:] if argv is None else list(argv)
    if not args:
        args = ["--help"]
    _tolerant_streams()
    empty = _empty_value(args)
    if empty is not None:
        # typer would read "" as the current folder (an unset shell variable, most likely).
        return _fail(f"{empty} needs a value, got an empty string", EXIT_ERROR)
    try:
        with _signals_raise_interrupted(), _warnings_as_lines():
            result = _click_command()(args=args, prog_name="vorobound", standalone_mode=False)
            sys.stdout.flush()
    except Interrupted:
        return _fail("interrupted", EXIT_INTERRUPTED, prefix="")
    except BrokenPipeError:
        return _broken_pipe()
    except SystemExit as exc:  # click ends a run with exit(1) when stdout's pipe breaks
        if isinstance(exc.__context__, BrokenPipeError):
            return _broken_pipe()
        raise
    except VoroboundError as exc:
        return _fail(str(exc), EXIT_ERROR)
    except typer.Exit as exc:
        return exc.exit_code
    except typer.Abort as exc:
        if isinstance(exc.__context__, EOFError):  # click turns any EOFError into Abort
            return _bug(exc.__context__)
        return _fail("interrupted", EXIT_INTERRUPTED, prefix="")
    except _usage_errors() as exc:
        message = exc.format_message()  # type: ignore[attr-defined]
        return _fail(message, getattr(exc, "exit_code", EXIT_ERROR) or EXIT_ERROR)
    except OSError as exc:
        if exc.errno is None:
            return _bug(exc)
        _silence_stdout()
        return _fail(f"cannot write the output: {exc.strerror or exc}", EXIT_ERROR)
    except MemoryError:
        return _fail("out of memory: use smaller inputs", EXIT_ERROR)
    except Exception as exc:  # the last line of defence: one line, traceback only on request
        return _bug(exc)
    return result if isinstance(result, int) else 0


_CLICK_COMMAND: list = []
"""The click command typer makes of ``app``, once per process."""


def _click_command():
    """What ``app(...)`` runs: typer builds the whole click group (every command's options) on
    each call, about 10 ms of every in-process run; it is built once here and kept. Exceptions
    reach :func:`main` as from ``app(...)`` (typer only tags them for its traceback hook, and
    every one that escapes main is a BaseException, which it does not tag)."""
    if not _CLICK_COMMAND:
        _CLICK_COMMAND.append(typer.main.get_command(app))
    return _CLICK_COMMAND[0]


def _empty_value(args: list[str]) -> str | None:
    """The option given an empty value (``--out ""`` or ``--out=``), if any."""
    for before, arg in zip(["", *args], args, strict=False):
        if arg == "" and before.startswith("-"):
            return before
        if arg.startswith("--") and arg.endswith("=") and len(arg) > 3:
            return arg[:-1]
    return None


def _bug(exc: BaseException) -> int:
    if os.environ.get("VOROBOUND_DEBUG") == "1":
        import traceback

        traceback.print_exception(exc, file=sys.stderr)
    summary = f"{type(exc).__name__}: {exc}"
    return _fail(
        f"internal error (a bug in vorobound, please report it): {summary}; "
        "rerun with --debug for the traceback",
        EXIT_BUG,
    )


def _broken_pipe() -> int:
    """Nobody reads the output any more: say nothing (stderr may be the same pipe) and make the
    final flush at exit harmless."""
    _silence_stdout()
    return EXIT_BROKEN_PIPE


def _silence_stdout() -> None:
    """After a failed write to stdout, point it at /dev/null so the exit flush cannot fail."""
    if isinstance(sys.stdout, _ClosedStream):
        return
    with contextlib.suppress(OSError, ValueError, AttributeError):
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())


def _fail(message: str, code: int, prefix: str = "error: ") -> int:
    text = " ".join(str(message).split())
    with contextlib.suppress(OSError, ValueError):
        print(f"{prefix}{text}", file=sys.stderr)
    return code


EXIT_HANDLER_SECONDS = 15.0
"""After an interrupt, the longest wait for the exit handlers (temporary folders, multiprocessing's
cleanup): one that blocks (a queue thread writing to a pipe nobody reads) must not turn Ctrl-C
into a hang."""


def _run_exit_handlers(seconds: float) -> bool:
    """Run the ``atexit`` handlers in a daemon thread for at most ``seconds``; whether they
    ended."""
    import atexit

    def run() -> None:
        with contextlib.suppress(Exception):
            atexit._run_exitfuncs()  # multiprocessing's cleanup, among others

    thread = threading.Thread(target=run, name="vorobound-exit", daemon=True)
    thread.start()
    thread.join(seconds)
    return not thread.is_alive()


def entry() -> None:
    """Console-script entry point.

    The process ends by ``os._exit`` once the exit handlers have run, whatever the code:

    * after an interrupt, extension threads that were busy when the signal came (scipy's k-d
      tree workers) can otherwise crash the interpreter while it tears itself down;
    * a Ctrl-C (or SIGTERM) in the last moments, while the exit handlers run, used to end the
      process with no line at all; it is now told as any other interrupt (one line, 130).

    Outputs are complete, or cleaned up, before this point.
    """
    code = main()
    late: list[int] = []
    with contextlib.suppress(ValueError, OSError):  # not the main thread: no handlers to set
        for number in (signal.SIGINT, signal.SIGTERM):
            signal.signal(number, lambda signum, frame: late.append(signum))
    _run_exit_handlers(EXIT_HANDLER_SECONDS)
    if late and code != EXIT_INTERRUPTED:
        with contextlib.suppress(OSError, ValueError):
            sys.stderr.write("interrupted\n")
        code = EXIT_INTERRUPTED
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(OSError, ValueError):
            stream.flush()
    os._exit(code)
