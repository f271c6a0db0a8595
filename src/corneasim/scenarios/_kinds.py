"""Scenario kinds: what a ``kind`` adds to a run (history columns, summary, plots, figure
instants, command-line shortcuts).

A scenario's ``kind`` (``general``, ``needle``, ``trephine``) names one object of this module
(:func:`scenario_kind`); the runner, the summary, the plots and the command line ask it, so a
new kind is one new class and its entry in :data:`KINDS`:

* ``lead_columns``: the history columns written first;
* :meth:`ScenarioKind.instrument_columns`: the kind's own columns from the instrument's pose
  and forces (depth and force for a needle, displacement, angle, F_z, F_c for a trephine);
* :meth:`ScenarioKind.summary`: the kind's entries of ``summary.json``;
* :meth:`ScenarioKind.plots`: its figures in ``plots/``;
* :meth:`ScenarioKind.figure_instants`: procedure times with a field snapshot (the papers'
  figures);
* :meth:`ScenarioKind.shortcut_overrides`: the ``--speed``/``--depth``/``--mesh`` options
  turned into ``--set`` overrides, and :meth:`ScenarioKind.default_out_dir`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from corneasim.errors import InputError
from corneasim.mesh import mesh_presets


def _at(history: dict, column: str, time: float) -> float:
    return float(np.interp(time, history["time_s"], history[column]))


class ScenarioKind:
    """The ``general`` kind: energies, deletions and reactions; the base of the paper kinds."""

    name = "general"
    lead_columns = ["time_s", "kinetic_energy_mJ", "internal_energy_mJ", "deleted_elements"]

    def instrument_columns(self, raw: dict, depth: float, angle: float) -> dict:
        """Columns from the instrument's insertion depth (mm), angle (rad) and the raw row."""
        return {"depth_mm": depth, "force_N": raw["instrument_force_z_N"]}

    def summary(self, setup, history: dict, events: dict, status: str) -> dict:
        """The kind's entries of the summary (``events``: puncture name -> procedure time, s)."""
        named = {f"{output.name}_N" for output in setup.scenario.reactions}
        return {"reactions": {k: float(np.abs(v).max()) for k, v in history.items()
                              if k.startswith("reaction_") or k in named}}

    def plots(self, setup, history: dict, summary: dict, snapshots: dict, plots: Path) -> None:
        """The kind's figures (none for the general kind)."""

    def figure_instants(self, scenario) -> dict[str, float]:
        """Procedure times (physical, s) with a field snapshot, by name."""
        return {}

    def shortcut_overrides(self, arguments) -> list[str]:
        """``--preset``, ``--mesh``, ``--speed`` as ``--set`` overrides, then the ``--set`` ones: a
        ``--preset`` that names a mesh density sets ``mesh.preset``, any other the model ``variant``.
        Needs the command line's ``preset``, ``mesh_strategy``, ``speed`` and ``overrides``."""
        densities = mesh_presets()
        overrides = [f"mesh.preset={name}" if name in densities else f"variant={name}"
                     for name in arguments.preset or []]
        if arguments.mesh_strategy:
            overrides += self.mesh_overrides(arguments.mesh_strategy)
        if arguments.speed is not None:
            overrides += self.speed_overrides(arguments.speed)
        return overrides + list(arguments.overrides)

    def mesh_overrides(self, strategy: str) -> list[str]:
        raise InputError("--mesh: only the trephine scenario has meshing strategies")

    def speed_overrides(self, speed: float) -> list[str]:
        raise InputError("--speed: only the needle scenario has an insertion speed option")

    def depth_overrides(self, depth: float, load_scenario) -> list[str]:
        """``--depth`` (mm) as overrides for the scenario that ``load_scenario()`` returns (as the
        other options made it)."""
        raise InputError("--depth: only the needle scenario has an insertion depth option")

    def default_out_dir(self, scenario) -> Path:
        """``results/<name>``."""
        return Path("results") / scenario.name


class NeedleKind(ScenarioKind):
    """The needle paper's insertion: depth and force, punctures, force drops, Gaussian fit."""

    name = "needle"
    lead_columns = ["time_s", "depth_mm", "force_N", "kinetic_energy_mJ", "internal_energy_mJ",
                    "deleted_elements"]

    def summary(self, setup, history: dict, events: dict, status: str) -> dict:
        from corneasim.analysis import detect_force_drops
        from corneasim.scenarios._postprocess import fit_and_validate

        depth, force = history["depth_mm"], history["force_N"]
        summary = {"peak_force_N": float(force.max())}
        summary["punctures"] = [
            {"event": name, "time_s": t, "depth_mm": _at(history, "depth_mm", t), "force_N": _at(history, "force_N", t)}
            for name, t in events.items()]
        drops = detect_force_drops(force, depth)
        summary["force_drops"] = [{"depth_mm": float(d.x), "force_N": float(d.force), "drop_N": float(d.drop)}
                                  for d in drops]
        if status == "completed" and np.ptp(force) > 0:
            summary["fit"], summary["validation"] = fit_and_validate(setup, depth, force, FIT_TERMS)
        return summary

    def plots(self, setup, history: dict, summary: dict, snapshots: dict, plots: Path) -> None:
        from corneasim.output import force_plot
        from corneasim.scenarios._report import experiment_curve, gaussian_fit

        punctures = [(p["event"], p["depth_mm"], p["force_N"]) for p in summary.get("punctures", [])]
        validation = summary.get("validation") or {}
        range_fit = (gaussian_fit(validation), validation["fit_range"]) if validation.get("fit") else None
        force_plot(history["depth_mm"], history["force_N"], gaussian_fit(summary), experiment_curve(setup),
                   punctures, x_label="insertion depth, mm", title=f"Needle insertion ({setup.scenario.name})",
                   path=plots / "force.png", range_fit=range_fit)

    def speed_overrides(self, speed: float) -> list[str]:
        from corneasim.scenarios._needle import speed_overrides

        if not speed > 0:
            raise InputError(f"--speed: expected a speed > 0 mm/s, got {speed}")
        return speed_overrides(speed)

    def depth_overrides(self, depth: float, load_scenario) -> list[str]:
        if not depth > 0:
            raise InputError(f"--depth: expected a depth > 0 mm, got {depth}")
        scenario = load_scenario()
        rate = getattr(scenario.instrument.motion.insertion, "rate", None) if scenario.instrument else None
        if not rate or rate <= 0:
            raise InputError("--depth: needs a needle pushed at a constant rate (instrument.motion.insertion "
                             "type = \"linear\" with rate > 0)")
        return [f"solver.end_time={depth / rate!r}"]

    def default_out_dir(self, scenario) -> Path:
        """``results/<name>-<speed>`` (``results/needle-1``)."""
        if scenario.instrument is not None:
            return Path("results") / f"{scenario.name}-{scenario.instrument.motion.insertion.rate:g}"
        return super().default_out_dir(scenario)


FIT_TERMS = 3
"""Gaussian terms of the needle paper's fit (eq. 16); the trephine's: :mod:`corneasim.scenarios._trephine`."""


class TrephineKind(ScenarioKind):
    """The trephination paper's cut: F_z, F_c, energies, validation, Fig. 5 instants and sections."""

    name = "trephine"
    lead_columns = ["time_s", "displacement_mm", "angle_rad", "fz_N", "fc_N", "torque_Nmm", "kinetic_energy_mJ",
                    "internal_energy_mJ", "deleted_elements"]

    def instrument_columns(self, raw: dict, depth: float, angle: float) -> dict:
        return {"displacement_mm": depth, "angle_rad": angle,
                "fz_N": raw["instrument_linear_cutting_force_N"], "fc_N": raw["instrument_rotary_cutting_force_N"],
                "torque_Nmm": raw["instrument_torque_z_Nmm"]}

    def summary(self, setup, history: dict, events: dict, status: str) -> dict:
        from corneasim.scenarios._trephine import trephine_summary

        return trephine_summary(setup, history, events, status)

    def plots(self, setup, history: dict, summary: dict, snapshots: dict, plots: Path) -> None:
        from corneasim.scenarios._trephine_report import forces_figure, stress_sections

        forces_figure(setup, history, summary, plots / "forces.png")
        if snapshots and "symmetry_plane" in setup.mesh.node_sets:
            stress_sections(setup, snapshots, plots)

    def figure_instants(self, scenario) -> dict[str, float]:
        from corneasim.scenarios._trephine import figure_instants

        return figure_instants(scenario)

    def mesh_overrides(self, strategy: str) -> list[str]:
        return [f"mesh.strategy={strategy}"]


KINDS = {kind.name: kind for kind in (ScenarioKind(), NeedleKind(), TrephineKind())}
"""The scenario kinds by ``kind`` name."""


def scenario_kind(name: str) -> ScenarioKind:
    """The object of kind ``name`` (InputError for an unknown one)."""
    if name not in KINDS:
        raise InputError(f"kind: '{name}' is not a scenario kind (kinds: {', '.join(KINDS)})")
    return KINDS[name]
