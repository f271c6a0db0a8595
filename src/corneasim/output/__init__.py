"""Results folders, ParaView files, plots, progress and the platform record.

The modules are private; their public names are exported here, those that need meshio or
matplotlib (``TimeSeriesWriter``, the plots) imported on first use:

* files: ``atomic_write_bytes``, ``atomic_write_text``, ``write_json``, :class:`HistoryWriter`;
* ParaView time series: :class:`TimeSeriesWriter`;
* plots: ``force_plot``, ``section_map``, ``draw_instrument``, ``save``;
* progress: ``track``; platform: ``describe_platform``, ``compiled_in_process``.
"""

from __future__ import annotations

import importlib

from corneasim.output._files import HistoryWriter, atomic_write_bytes, atomic_write_text, write_json
from corneasim.output._platform import compiled_in_process, describe_platform
from corneasim.output._progress import track

_LAZY = {"TimeSeriesWriter": "_paraview", "force_plot": "_plots", "section_map": "_plots",
         "draw_instrument": "_plots", "save": "_plots"}
__all__ = ["HistoryWriter", "atomic_write_bytes", "atomic_write_text", "compiled_in_process", "describe_platform",
           "track", "write_json", *_LAZY]


def __getattr__(name: str):
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'corneasim.output' has no attribute '{name}'")
    return getattr(importlib.import_module(f"corneasim.output.{module}"), name)
