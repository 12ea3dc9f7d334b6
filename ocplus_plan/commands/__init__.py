"""Subcommands of ``ocplus``; each module has ``register(subparsers)``."""
