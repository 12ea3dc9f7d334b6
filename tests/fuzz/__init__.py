"""Fuzzing of the file readers (maps, plans, recordings) and a corpus of hostile files.

``OCPLUS_FUZZ_SCALE`` multiplies every fuzz test's example count (default 1: the suite's
budget); e.g. ``OCPLUS_FUZZ_SCALE=20 .venv/bin/python -m pytest tests/fuzz`` searches
longer.
"""

from __future__ import annotations

import os
from typing import Any


def fuzz_settings(examples: int) -> Any:
    """Hypothesis settings for a fuzz test: ``examples`` times ``OCPLUS_FUZZ_SCALE``.
    (Imported here, not above: the limited runner of this package does without it.)"""
    from hypothesis import HealthCheck, settings

    scale = float(os.environ.get("OCPLUS_FUZZ_SCALE", "1"))
    return settings(max_examples=max(1, int(examples * scale)), deadline=None,
                    suppress_health_check=[HealthCheck.too_slow])
