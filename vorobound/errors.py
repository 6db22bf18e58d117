"""The exceptions vorobound raises. Every one is a :class:`VoroboundError` (a ``ValueError``).

The command line turns any of them into one line on stderr and exit code 2. Callers that need
to tell the cases apart catch the subclass.
"""


class VoroboundError(ValueError):
    """Base class: bad input, or a problem whose answer cannot be computed."""


class InputError(VoroboundError):
    """A parameter or an input array is invalid or outside the supported range."""


class NoAdmissibleEps(VoroboundError):
    """No sampling density ε keeps the bound within the quality target.

    Sweeps turn this one error into an empty ε* cell (with the reason beside it); every other
    error stops the sweep. This family is the one representation of "no ε*": the batch solver's
    status codes name these classes (:data:`vorobound.bounds.eps_star.NO_EPS_STAR`) and an
    empty cell's note is the class's :attr:`reason`.
    """

    reason = "bound exceeds the target at the smallest eps with guide triangles"
    """Why there is no ε*, in a few words (each subclass says its own)."""


class NoCrossing(NoAdmissibleEps):
    """The bound stays below the target wherever it is defined: no root, so no ε*."""

    reason = "bound never reaches the target where it is defined"


class NotCertified(VoroboundError):
    """An interval search stopped without a certificate: ``counterexample`` (a feasible guide
    triangle above the target) or ``box`` (the box it could not resolve within its limits)."""

    def __init__(self, message: str, counterexample=None, box=None):
        super().__init__(message)
        self.counterexample = counterexample
        self.box = box


class EmptyConstraintSet(NoAdmissibleEps):
    """No guide triangle satisfies the constraint set (33)–(36) with H3 at this ε:
    σ(1 − ε) > √3. Every bound holds there vacuously, so nothing can be bounded or measured."""

    reason = "no feasible guide triangle at any supported eps"


class LatticeTooLarge(InputError):
    """The sampler's candidate lattice at this ε would not fit in memory."""


class ReadError(VoroboundError):
    """A file cannot be read or is not what the command expects (mesh, sizing, balls, ...)."""


class WriteError(VoroboundError):
    """An output file cannot be written (the previous file, if any, is left intact)."""


class CertificateError(VoroboundError):
    """A certificate is malformed, or re-checking it fails."""


class NoGuideTriangles(VoroboundError):
    """A set of balls has no guide triangle, so nothing can be measured against the bounds."""


class MissingDependency(VoroboundError):
    """An optional dependency a function needs is not installed (the message says how)."""


class VoroboundWarning(RuntimeWarning):
    """A warning that means something for the result (the CLI prints it as one line).

    Other runtime warnings (numpy's floating-point notices, chatter from readers) are
    silenced by the command line.
    """


_WARNED: set = set()
"""The (subject, message) pairs warned about in this process (:func:`warn_once`)."""


def warn_once(message: str, subject=None, stacklevel: int = 2) -> None:
    """Warn with :class:`VoroboundWarning` unless this ``message`` was already given about
    this ``subject`` (a mesh's fingerprint, say) in this process: the steps of one workflow
    (advise, sample, check) that each read the same mesh say what is wrong with it once."""
    import warnings

    if (subject, message) in _WARNED:
        return
    _WARNED.add((subject, message))
    warnings.warn(message, VoroboundWarning, stacklevel=stacklevel + 1)


def forget_warnings() -> None:
    """Let every :func:`warn_once` warning be given again (tests start from a clean slate)."""
    _WARNED.clear()


class WorkerError(VoroboundError):
    """A worker process or the cluster running a computation failed (killed, out of memory,
    unreachable); nothing was written."""
