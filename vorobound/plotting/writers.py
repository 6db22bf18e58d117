"""Figures written to files: atomically, one at a time or as a set, with no time stamps."""

from __future__ import annotations

from pathlib import Path

from ..files import atomic_path, ensure_folder, write_set
from .style import STYLE

DPI = 200
"""Resolution of raster formats."""
_NO_DATES = {"pdf": {"CreationDate": None}, "svg": {"Date": None}}
"""Metadata that drops time stamps, so a figure's file depends only on its data."""


def write_figure(fig, path, fmt: str, dpi: int) -> None:
    """Draw ``fig`` into ``path`` (the figures' style, no time stamps)."""
    import matplotlib

    with matplotlib.rc_context(STYLE):
        fig.savefig(path, format=fmt, dpi=dpi, metadata=_NO_DATES.get(fmt))


def save(fig, out_dir: str | Path, stem: str, fmt: str = "png", dpi: int = DPI) -> Path:
    """Write ``fig`` to ``out_dir/stem.fmt`` atomically (temporary file, then rename)."""
    path = ensure_folder(out_dir) / f"{stem}.{fmt}"
    with atomic_path(path) as temp:
        write_figure(fig, temp, fmt, dpi)
    return path


def figure_writer(fig, fmt: str = "png", dpi: int = DPI):
    """A writer for :func:`vorobound.files.write_set`: draws ``fig`` into the path it is given."""
    return lambda temp: write_figure(fig, temp, fmt, dpi)


def save_set(figures: dict, out_dir: str | Path, fmt: str = "png", dpi: int = DPI) -> list[Path]:
    """Write ``{stem: figure}`` into ``out_dir`` as one set: all files or none are replaced."""
    out = ensure_folder(out_dir)
    return write_set(
        {out / f"{stem}.{fmt}": figure_writer(fig, fmt, dpi) for stem, fig in figures.items()}
    )
