"""Command line: a thin layer over the API (``tensegrity-rigidity COMMAND``)."""

from .main import main

__all__ = ["main"]
