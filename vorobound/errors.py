"""The one exception type the library raises for bad input."""


class VoroboundError(ValueError):
    """Raised for invalid input or a problem without a solution; the CLI prints its message."""
