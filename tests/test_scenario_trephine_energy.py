"""summary['energy'] of a trephine run: damping energy against the trephine's work, closed forms.

A trephine descending at v with a constant axial force F_z while turning as
theta = A sin(omega t) against the moment M_z = -c theta' (viscous) does the work
W = F_z v T + c A^2 omega^2 int_0^T cos^2(omega t) dt; the damping and external work are
differences of the history's half-model columns, doubled by the symmetry factor.
"""

import numpy as np

from corneasim.scenarios._trephine import energy_shares


def _history(time, damping, external):
    velocity, force, amplitude, omega, c = 0.02, 0.1, 1.25, 3.5, 0.01
    angle = amplitude * np.sin(omega * time)
    return {"time_s": time, "displacement_mm": velocity * time, "angle_rad": angle, "fz_N": np.full_like(time, force),
            "torque_Nmm": -c * amplitude * omega * np.cos(omega * time),
            "damping_energy_mJ": damping, "external_work_mJ": external}, (velocity, force, amplitude, omega, c)


def test_trephine_work_is_axial_plus_rotary_work():
    time = np.linspace(0.0, 10.0, 20001)
    history, (v, f, a, omega, c) = _history(time, np.linspace(0.5, 0.6, time.size), np.linspace(0.2, 0.25, time.size))
    T = time[-1]
    rotary = c * a**2 * omega**2 * (T / 2 + np.sin(2 * omega * T) / (4 * omega))
    shares = energy_shares(history, 2.0)
    assert np.isclose(shares["trephine_work_mJ"], f * v * T + rotary, rtol=1e-4)
    assert np.isclose(shares["damping_energy_mJ"], 2 * 0.1)
    assert np.isclose(shares["external_work_on_tissue_mJ"], 2 * 0.05)
    assert np.isclose(shares["damping_to_trephine_work"], 0.2 / (f * v * T + rotary), rtol=1e-4)
    assert np.isclose(shares["damping_to_external_work"], 2.0)


def test_no_work_gives_no_ratio():
    time = np.linspace(0.0, 1.0, 11)
    history = {"time_s": time, "displacement_mm": np.zeros_like(time), "angle_rad": np.zeros_like(time),
               "fz_N": np.zeros_like(time), "torque_Nmm": np.zeros_like(time),
               "damping_energy_mJ": np.zeros_like(time), "external_work_mJ": np.zeros_like(time)}
    shares = energy_shares(history, 2.0)
    assert shares["damping_to_trephine_work"] is None and shares["damping_to_external_work"] is None


def test_the_quasi_static_check_counts_from_contact_and_stops_at_the_cut_through():
    """KE / IE on hand-made rows: nothing before the first force, nothing where the internal
    energy is below 5% of its peak, and with ``until`` nothing from that time on."""
    from corneasim.scenarios._postprocess import max_kinetic_to_internal

    history = {"time_s": np.array([0.0, 1.0, 2.0, 3.0, 4.0]),
               "fz_N": np.array([0.0, 0.1, 0.1, 0.1, 0.0]),
               "internal_energy_mJ": np.array([1.0, 1.0, 2.0, 0.05, 0.5]),
               "kinetic_energy_mJ": np.array([0.9, 0.01, 0.04, 0.04, 0.2])}
    assert max_kinetic_to_internal(history) == 0.4  # row 4: 0.2 / 0.5; row 3 is below 5% of 2.0
    assert max_kinetic_to_internal(history, until=3.5) == 0.02  # rows 1-2
