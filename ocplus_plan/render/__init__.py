"""Drawing: numpy RGB frames (:mod:`.rgb`, always available) and, as an optional extra
(``pip install ocplus-plan[gui]``), the pygame window in ``ocplus_plan.render.window``,
which shows the frames of :func:`render_frame`. Importing this package never imports
pygame.
"""

from __future__ import annotations

from .rgb import RgbEncoder, render_frame
from .sprites import TILE_SIZE

__all__ = ["TILE_SIZE", "RgbEncoder", "render_frame"]
