"""``python -m vorobound``."""

from .cli import entry

entry()
