"""Raw-data simulation: dechirped (stretch) LFM echoes with beam weighting, speckle and noise, and
the balanced current of down-looking SAL.

``simulate(scenario)`` dispatches on the scenario's kind (:data:`SIMULATORS`); the package is
callable: ``salkit.simulate(sc)`` is ``salkit.simulate.simulate(sc)``.

Modules: :mod:`~salkit.simulate.registry` (``simulate``, ``SIMULATORS``), :mod:`~salkit.simulate.sal`
(the SAL simulator), :mod:`~salkit.simulate.echoes` (echoes, photon noise, signal scale, sizes),
:mod:`~salkit.simulate.turbulent` (the atmosphere of a scenario), :mod:`~salkit.simulate.kernels`
(numba kernels), :mod:`~salkit.simulate.scene`, :mod:`~salkit.simulate.downlooking`, and, for
accuracy work, :mod:`~salkit.simulate.analytic` and :mod:`~salkit.simulate.testbeds`.
"""
from .downlooking import simulate_downlooking
from .echoes import echo_signal, fast_time_axis, memory_estimate, photon_noise, signal_scale, signal_shape
from .registry import SIMULATORS, simulate
from .sal import simulate_sal
from .turbulent import screen_size, turbulent_path, wave_optics_plan
from .._callable import make_callable as _make_callable

__all__ = ["SIMULATORS", "echo_signal", "fast_time_axis", "memory_estimate", "photon_noise", "screen_size",
           "signal_scale", "signal_shape", "simulate", "simulate_downlooking", "simulate_sal", "turbulent_path",
           "wave_optics_plan"]

_make_callable(__name__, "simulate")
