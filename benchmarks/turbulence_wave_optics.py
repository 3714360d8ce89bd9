"""turbulence_wave_optics: the turbulence workflow with the wave-optics atmosphere, one class at a time
(weak, medium, strong): the time of a run and its PGA result.

``make bench NAME=turbulence_wave_optics`` (or ``python benchmarks/turbulence_wave_optics.py``) runs it alone.
"""
from __future__ import annotations

from common import best_of


def bench_turbulence_wave_optics(classes=("weak", "medium", "strong")):
    """Cost of the seed 004 point-target simulation per turbulence class (51 pulses, 50 layers):
    phase-only screens against wave optics through the same screens (one beam propagation per
    pulse on the planned grid); the grid side and the time per pulse."""
    import salkit
    from salkit.geometry.collection import build_collection
    from salkit.params import load_scenario
    from salkit.simulate import screen_size, simulate, wave_optics_plan
    base = load_scenario(salkit.example_path("turbulence_pga"), ["experiment=null", "receiver.noise.enabled=false"])
    cn2s = {"weak": 1e-15, "medium": 1e-14, "strong": 1e-13}
    out = {}
    simulate(load_scenario(salkit.example_path("turbulence_pga"), ["experiment=null", "atmosphere.cn2=1e-15",
                                                                   "atmosphere.model=wave_optics"]))  # compile
    for name in classes:
        wo = base.model_copy(update={"atmosphere": base.atmosphere.model_copy(
            update={"cn2": cn2s[name], "model": "wave_optics"})})
        col = build_collection(wo)
        n_screen = screen_size(wo, col)
        plan, _ = wave_optics_plan(wo, col)
        wo = wo.model_copy(update={"atmosphere": wo.atmosphere.model_copy(update={"screen_n": n_screen})})
        ps = wo.model_copy(update={"atmosphere": wo.atmosphere.model_copy(update={"model": "phase_screen"})})
        t_ps, _ = best_of(lambda: simulate(ps), 1)
        t_wo, _ = best_of(lambda: simulate(wo), 1)
        out[f"wave_optics_{name}_grid_n"] = plan.n
        out[f"wave_optics_{name}_screen_n"] = n_screen
        out[f"wave_optics_{name}_phase_screen_s"] = t_ps
        out[f"wave_optics_{name}_wave_optics_s"] = t_wo
        out[f"wave_optics_{name}_per_pulse_s"] = (t_wo - t_ps) / col.n_pulses
    return out


if __name__ == "__main__":
    import runner
    runner.main(["turbulence_wave_optics"])
