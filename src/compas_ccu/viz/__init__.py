"""Pictures of CCU structures: figures, animation, the offline viewer page and the report.

Needs the ``viz`` extra (``pip install compas_ccu[viz]``: matplotlib, plotly, tqdm); MP4 output
also needs the ``video`` extra (imageio-ffmpeg). Nothing here is imported by ``import compas_ccu``.
"""

from __future__ import annotations
