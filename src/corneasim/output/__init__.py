"""Results folders, ParaView files, plots, progress and the platform record.

The modules are private; their public names are exported here, those that need meshio or
matplotlib (``TimeSeriesWriter``, the plots) imported on first use:

* files: ``atomic_write_bytes``, ``atomic_write_text``, ``write_json``, :class:`HistoryWriter`,
  ``trim_table`` (a torn history repaired), ``file_mode``;
* the results folder of one run: :class:`ResultsFolder` (lock, ownership, clearing);
* ParaView time series: :class:`TimeSeriesWriter`; the nodes deleted elements release:
  :class:`OrphanNodes`;
* plots: ``force_plot``, ``experiment_label``, ``draw_instrument``, ``save``;
* stress maps: ``stress_map``, ``axisymmetric_section``, ``colour_limits``, ``colour_label``,
  ``map_title``, ``lowest_point``, ``tip_window``, ``EVENTS``, ``CLIP_PERCENTILE``;
* HTML pages (a run's or a study's report): :class:`Section`, :class:`Paragraph`,
  :class:`Table`, :class:`Mark`, :class:`Image`, ``render_page``, ``write_page``;
* a results folder's ``report.html``: ``write_run_report``, ``run_sections``,
  ``read_results``, ``REPORT``; the validation targets: ``score``;
* progress: ``track``; platform: ``describe_platform``, ``compiled_in_process``,
  ``cached_for_this_machine``, ``process_age``.
"""

from __future__ import annotations

import importlib

from corneasim.output._files import (
    HistoryWriter, atomic_write_bytes, atomic_write_text, file_mode, trim_table, write_json)
from corneasim.output._html_report import Image, Mark, Paragraph, Section, Table, render_page, write_page
from corneasim.output._orphans import OrphanNodes
from corneasim.output._results_folder import ResultsFolder
from corneasim.output._platform import (
    cached_for_this_machine, compiled_in_process, describe_platform, process_age)
from corneasim.output._progress import track
from corneasim.output._run_report import REPORT, read_results, run_sections, write_run_report
from corneasim.output._targets import NEEDLE_RMSE_N, score

_LAZY = {"TimeSeriesWriter": "_paraview", "force_plot": "_plots", "experiment_label": "_plots",
         "draw_instrument": "_plots", "save": "_plots",
         **{name: "_stress_maps" for name in ("stress_map", "axisymmetric_section", "colour_limits", "colour_label",
                                              "map_title", "lowest_point", "tip_window", "EVENTS",
                                              "CLIP_PERCENTILE")}}
__all__ = ["HistoryWriter", "ResultsFolder", "file_mode", "trim_table", "Image", "Mark", "OrphanNodes", "Paragraph", "REPORT", "Section", "Table",
           "atomic_write_bytes", "atomic_write_text", "cached_for_this_machine", "compiled_in_process", "describe_platform", "process_age", "read_results",
           "NEEDLE_RMSE_N", "render_page", "run_sections", "score", "track", "write_json", "write_page", "write_run_report", *_LAZY]


def __getattr__(name: str):
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'corneasim.output' has no attribute '{name}'")
    return getattr(importlib.import_module(f"corneasim.output.{module}"), name)
