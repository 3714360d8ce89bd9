"""The simulators by scenario kind: ``simulate`` dispatches on the kind, runs repeat exactly with a
seed and change with another."""
import numpy as np

from salkit.params import parse_scenario
from salkit.simulate import SIMULATORS, simulate, simulate_downlooking, simulate_sal

from ..conftest import SPOT, dl_scenario, merge


def test_dispatch_by_kind(monkeypatch):
    seen = []
    for kind in ("sal", "downlooking"):
        monkeypatch.setitem(SIMULATORS, kind, lambda sc, kind=kind, **kw: seen.append((kind, sorted(kw))))
    simulate(parse_scenario(SPOT))
    simulate(dl_scenario())
    assert seen == [("sal", ["noise", "progress", "rng"]), ("downlooking", ["noise", "progress", "rng"])]


def test_registry_holds_the_simulators():
    assert SIMULATORS == {"sal": simulate_sal, "downlooking": simulate_downlooking}


def test_seeded_runs_repeat_exactly():
    sc = parse_scenario(merge(SPOT, scene={"extended": {"kind": "pattern", "pattern": "disk", "extent": [0.3, 0.3],
                                                        "spacing": 0.01, "speckle": True}},
                              receiver={"adc_rate": 20e6, "noise": {"enabled": True, "signal_photons": 5.0}}))
    a = simulate(sc)["signal"].values
    b = simulate(sc)["signal"].values
    assert np.array_equal(a, b)
    c = simulate(sc.model_copy(update={"seed": 99}))["signal"].values
    assert not np.allclose(a, c)


def test_noise_must_be_a_switch(monkeypatch):
    """noise="no" was taken as true (a non-empty string); only True, False or None pass."""
    import pytest
    from salkit.errors import ScenarioError
    monkeypatch.setitem(SIMULATORS, "sal", lambda sc, **kw: kw["noise"])
    sc = parse_scenario(SPOT)
    assert [simulate(sc, noise=v) for v in (True, False, None, np.True_)] == [True, False, None, np.True_]
    for bad in ("no", 1, 0.0):
        with pytest.raises(ScenarioError, match=r"noise = .*: must be True, False or None"):
            simulate(sc, noise=bad)


def test_progress_must_be_callable():
    """progress=5 raised TypeError ('int' object is not callable) from inside the simulation."""
    import pytest
    from salkit.errors import ScenarioError
    with pytest.raises(ScenarioError, match=r"progress = 5: must be a callable progress\(done, total\)"):
        simulate(parse_scenario(SPOT), progress=5)
