"""ocplus-plan: a symbolic-planning benchmark on an Overcooked-style cooking simulator."""

__version__ = "0.1.0"
