"""``python -m vorobound``."""

from .launch import entry

entry()
