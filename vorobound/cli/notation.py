"""One notation on the terminal: the paper's symbols (ε, σ, δ/ε, ρ_f, R̂, ≤) where the terminal
can show them, plain ASCII (eps, sigma, delta, rho_f, R_hat, <=) where it cannot.

Tables are written in Unicode and footers (long sentences shared with the JSON, which stays
ASCII) in ASCII; :func:`footer` gives a footer the table's notation and wraps it to the
terminal, and :func:`ascii_stream` turns everything written to a stream that cannot encode
Unicode into the ASCII spelling.
"""

from __future__ import annotations

import re
import shutil
import textwrap

NOTATION_PROBE = "εσδρ̂≤−·×°"
"""Characters a terminal must encode for the Unicode notation."""
FALLBACK_WIDTH = 100
"""Width footers are wrapped at when the output is not a terminal."""

_SUPERSCRIPTS = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻", "0123456789-")
_TO_ASCII = (
    ("\u0302", "_hat"),  # combining circumflex: R̂ -> R_hat, M̂ -> M_hat
    ("ε*", "eps_star"),
    ("ε", "eps"),
    ("σ", "sigma"),
    ("δ", "delta"),
    ("ρ", "rho"),
    ("λ", "lambda"),
    ("μ", "mu"),
    ("θ", "theta"),
    ("π", "pi"),
    ("≤", "<="),
    ("≥", ">="),
    ("≈", "~"),
    ("∈", "in"),
    ("−", "-"),
    ("–", "-"),
    ("—", "-"),
    ("·", "*"),
    ("×", "x"),
    ("°", " deg"),
    ("∞", "inf"),
    ("√", "sqrt"),
    ("→", "->"),
    ("…", "..."),
    ("✓", "ok"),
    ("✗", "x"),
)
_WORD = r"(?<![\w\-`'])"
"""No symbol inside a longer name, an option (--eps) or a quoted command."""
_TO_UNICODE = (
    (re.compile(r"(?<=[\w)])(?:\*| \* )(?=[\w(])"), "·"),  # a*b or a * b; not ε* for
    (re.compile(_WORD + r"eps_star\b"), "ε*"),
    (re.compile(r"(?<=\d)-(?=eps\b)"), "−"),
    (re.compile(_WORD + r"eps\b"), "ε"),
    (re.compile(_WORD + r"rho_f\b"), "ρ_f"),
    (re.compile(_WORD + r"R_hat\b|\bR\^"), "R̂"),
    (re.compile(_WORD + r"sigma\b"), "σ"),
    (re.compile(_WORD + r"delta\b"), "δ"),
    (re.compile(_WORD + r"lambda\b"), "λ"),
    (re.compile(r"<="), "≤"),
    (re.compile(r">="), "≥"),
    (re.compile(r" - "), " − "),
)


def to_ascii(text: str) -> str:
    """``text`` with every symbol of the notation spelt in ASCII (R̂ -> R_hat, ε -> eps)."""
    for symbol, word in _TO_ASCII:
        text = text.replace(symbol, word)
    return re.sub(r"[⁰¹²³⁴⁵⁶⁷⁸⁹⁻]+", lambda m: "^" + m.group().translate(_SUPERSCRIPTS), text)


def to_unicode(text: str) -> str:
    """``text`` written in ASCII (eps, rho_f, R_hat, <=) in the paper's symbols; options
    (``--eps``), names (``h3_ratio_max``) and quoted commands are left alone."""
    for pattern, symbol in _TO_UNICODE:
        text = pattern.sub(symbol, text)
    return text


def shows_unicode(stream) -> bool:
    """Whether ``stream`` can encode the Unicode notation."""
    encoding = getattr(stream, "encoding", None) or "ascii"
    try:
        NOTATION_PROBE.encode(encoding)
    except (UnicodeEncodeError, LookupError):
        return False
    return True


class AsciiStream:
    """A text stream that writes the notation in ASCII to the stream it wraps."""

    def __init__(self, stream):
        self._stream = stream

    def write(self, text: str) -> int:
        return self._stream.write(to_ascii(text))

    def __getattr__(self, name):
        return getattr(self._stream, name)


def ascii_stream(stream):
    """``stream`` itself when it shows the Unicode notation, else an :class:`AsciiStream`."""
    if stream is None or isinstance(stream, AsciiStream) or shows_unicode(stream):
        return stream
    return AsciiStream(stream)


def footer(text: str, stream=None) -> str:
    """A footer (one sentence or several, possibly written in ASCII) in the notation of the
    tables and wrapped to the terminal's width (:data:`FALLBACK_WIDTH` when not a terminal);
    continuation lines are indented by two spaces."""
    import sys

    stream = sys.stdout if stream is None else stream
    text = to_unicode(text)
    if not shows_unicode(stream):
        text = to_ascii(text)  # one ASCII spelling too (R^ and R_hat are both R_hat)
    isatty = getattr(stream, "isatty", None)
    width = (
        shutil.get_terminal_size((FALLBACK_WIDTH, 24)).columns
        if isatty is not None and isatty()
        else FALLBACK_WIDTH
    )
    return "\n".join(
        textwrap.fill(line, max(width - 1, 40), subsequent_indent="  ", break_on_hyphens=False)
        for line in text.split("\n")
    )
