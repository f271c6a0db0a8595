"""Explicit dynamics: model and state, element kernels, loads and their amplitudes, deletion, time integration.

Read top to bottom, a simulation is::

    model = build_model(mesh, {"stroma": material}, [Fixed("limbus", "rz")],
                        [Pressure("posterior", 2.333e-3, SmoothStep(0.0, 0.05))],
                        target_time_step=2e-5)
    state = new_state(model)
    for frame in run(model, state, end_time=1.0):
        ...

Theory and choices: ``docs/solver.md``; element kernels: ``docs/elements.md``.
"""

from corneasim.solver._amplitudes import (
    Amplitude, AmplitudeConfig, Constant, ConstantAmplitude, Fourier, FourierAmplitude, Linear, LinearAmplitude,
    SmoothStep, SmoothStepAmplitude, Tabular, TabularAmplitude, shifted)
from corneasim.solver._amplitudes import evaluate as evaluate_amplitude
from corneasim.solver._checkpoint import load_checkpoint, model_fingerprint, save_checkpoint
from corneasim.solver._checks import SimulationError
from corneasim.solver._cyclic import CyclicSymmetry
from corneasim.solver._distortion_check import DistortionCheck
from corneasim.solver._hourglass import physical_hourglass_coefficient, physical_hourglass_coefficients
from corneasim.solver._loads import Fixed, Prescribed, Pressure, SymmetryPlane, component_index
from corneasim.solver._lowest_mode import lowest_period
from corneasim.solver._model import Model, build_model
from corneasim.solver._outputs import field_output, history_row, out_of_balance
from corneasim.solver._reference import StressFreeReference, backward_displacement
from corneasim.solver._run import Frame, advance, preload, run
from corneasim.solver._state import (
    EVENT_CORNEA, EVENT_EPITHELIUM, EVENT_RELEASE, EVENT_STROMA, N_EVENTS, State, attach_derived, new_state)
from corneasim.solver._support import ElasticSupport, check_support_stability, critical_dashpot

__all__ = [
    "Amplitude", "AmplitudeConfig", "Constant", "ConstantAmplitude", "CyclicSymmetry", "DistortionCheck",
    "EVENT_CORNEA", "EVENT_EPITHELIUM", "EVENT_RELEASE", "EVENT_STROMA", "ElasticSupport", "Fixed", "Fourier",
    "FourierAmplitude", "Frame", "Linear", "LinearAmplitude", "Model", "N_EVENTS", "Prescribed", "Pressure",
    "SimulationError", "SmoothStep", "SmoothStepAmplitude", "State", "StressFreeReference", "SymmetryPlane", "Tabular",
    "TabularAmplitude", "advance", "attach_derived", "backward_displacement", "build_model", "check_support_stability",
    "component_index", "critical_dashpot", "evaluate_amplitude", "field_output", "history_row", "load_checkpoint",
    "lowest_period", "model_fingerprint", "new_state", "out_of_balance", "physical_hourglass_coefficient",
    "physical_hourglass_coefficients", "preload", "run", "save_checkpoint", "shifted",
]
