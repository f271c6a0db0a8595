"""Force surrogates of a study's cases, for real-time force reference and puncture detection.

* :func:`build_surrogate` (``corneasim surrogate build``): fit force against depth (needle)
  or F_z, F_c against time (trephine), and the puncture abscissae, as functions of a study's
  varied inputs, with a calibrated 95% band;
* :class:`Surrogate`, :func:`load`: the saved model, evaluated in closed form with numpy
  (:mod:`corneasim.surrogate._evaluate` imports nothing else and can be used on its own);
* :func:`write_c_export`: the model as a C header and a reference evaluator in plain C;
* :class:`PunctureDetector` (:mod:`corneasim.surrogate.detection`): a causal detector of
  the layers' punctures in a streamed force signal.

See ``docs/surrogate.md``.
"""

from corneasim.surrogate._evaluate import Surrogate, load
from corneasim.surrogate.build import build_surrogate
from corneasim.surrogate.c_export import write_c_export
from corneasim.surrogate.detection import PunctureDetector

__all__ = ["PunctureDetector", "Surrogate", "build_surrogate", "load", "write_c_export"]
