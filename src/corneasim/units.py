"""The unit system and the few conversions the papers need.

corneasim works in a consistent set of units, everywhere, without exception:

=========  =============  =========================================
quantity   unit           note
=========  =============  =========================================
length     mm
time       s
force      N
stress     MPa            N/mm^2
density    tonne/mm^3     1000 kg/m^3 = 1e-9 tonne/mm^3
energy     mJ             N*mm
velocity   mm/s
=========  =============  =========================================
"""

MMHG_IN_MPA = 133.322387415e-6
"""One millimetre of mercury in MPa (17.5 mmHg = 2.333e-3 MPa)."""

KG_PER_M3_IN_TONNE_PER_MM3 = 1.0e-12
"""1 kg/m^3 in tonne/mm^3 (water: 1000 kg/m^3 = 1.0e-9 tonne/mm^3)."""

RPM_IN_RAD_PER_S = 2.0 * 3.141592653589793 / 60.0
"""One revolution per minute in rad/s."""


def mmhg_to_mpa(pressure_mmhg: float) -> float:
    """Convert a pressure from mmHg to MPa.

    >>> round(mmhg_to_mpa(17.5), 6)
    0.002333
    """
    return pressure_mmhg * MMHG_IN_MPA
